// Speed against error of the basis images (`brdfshot bench-basis`; a
// benchmark, not a test). For each probe size, sphere size and quality setting
// it times building the operator and rendering all bases on the whole sphere
// (median of `repeats`), and measures the relative RMSE of the reference
// materials' images against a converged reference on a pixel subset.
// References are cached, keyed on everything they depend on.
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/basis_images.h"
#include "fit/database.h"
#include "fit/transport.h"

namespace brdfshot {

struct BasisBenchmarkOptions {
  std::string probe;
  std::vector<int> spheres{64, 128, 256};  // diameters, px
  std::vector<int> probe_widths{256, 512, 1024};
  std::vector<std::pair<int, int>> qualities;  // half-vector samples θ × φ
  std::pair<int, int> reference_samples{192, 384};
  int reference_pixels = 700;  // about this many pixels carry the error
  int repeats = 3;             // timing runs per setting (median)
  double margin_deg = 80;
  std::string cache;           // folder for references
  RenderQuality base_quality;  // all but the sample counts and probe width
  DatabaseOptions database;
  bool progress = false;
};

struct BasisBenchmarkRow {
  int sphere = 0, probe_width = 0;
  std::string quality;
  size_t pixels = 0, levels = 0;
  double build_s = 0, apply_s = 0, brute_s = 0;
  std::map<std::string, double> class_max;  // worst basis of each reference class
  double worst = 0;
};

struct BasisBenchmark {
  std::vector<BasisBenchmarkRow> rows;
  std::string database_label;
};

// Error when the database holds none of the reference materials.
BasisBenchmark RunBasisBenchmark(const BasisBenchmarkOptions& options);

std::string BasisBenchmarkMarkdown(const std::vector<BasisBenchmarkRow>& rows);
std::string BasisBenchmarkCsv(const std::vector<BasisBenchmarkRow>& rows);
// Time against worst error: colour = sphere size, marker = probe width, each
// line through the qualities in the order given.
cv::Mat BasisBenchmarkPlot(const BasisBenchmark& b, const BasisBenchmarkOptions& options);

// The reference at `path` when its header says it is of this geometry, probe,
// sample counts, integrator version and material count; else rendered and
// written there. `seconds`: how long it took to render (then or now).
BasisImages LoadOrRenderReference(const std::string& path, const PixelGeometry& geometry, const LatLongProbe& probe,
                                  const BasisDatabase& db, const std::vector<int>& materials,
                                  std::pair<int, int> samples, bool progress, double* seconds);

}  // namespace brdfshot
