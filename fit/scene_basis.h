// The basis stage: the basis images of one scene — every database basis
// rendered under the probe at the scene's pixels, and the analytic baseline's
// lobes (fit/lambert_ggx.h) — cached for every later fit.
// The rendering quality is given, or chosen by measuring this scene against a
// converged reference (fit/quality_search.h).
#pragma once

#include <optional>
#include <string>

#include "fit/basis_images.h"
#include "fit/database.h"
#include "fit/quality_search.h"
#include "fit/transport.h"

namespace brdfshot {

struct SceneBasisOptions {
  std::string probe;         // lat-long probe file
  std::string observations;  // observation file whose geometry to use; "" : an orthographic sphere
  int sphere = 64;           // its diameter in pixels
  double margin_deg = 80;    // its largest angle between normal and view
  RenderQuality quality;
  double error_target = 0;  // > 0: choose the quality by measuring (QualitySearchOptions::target)
  int error_pixels = QualitySearchOptions{}.pixels;
  DatabaseOptions database;
  // The Lambert + GGX baseline's lobe images beside the bases (49 more
  // columns, a sixth of the images); off: `fit` writes no baseline.
  bool lobes = true;
  bool progress = false;  // the quality search's reference renders, on stderr
  // Non-empty: a folder of basis images shared by captures. Images of an
  // identical scene (the same probe pixels, pixel geometry, quality or error
  // target, and database) are taken from it instead of rendered; new ones are
  // stored in it. A damaged or mismatched file there is re-rendered.
  std::string shared_dir;
};

struct SceneBasis {
  BasisImages images;
  std::optional<QualityChoice> search;  // when an error target was given
  std::string shared_file;              // with shared_dir: the file of this scene there
  bool reused = false;                  // taken from shared_file, not rendered
  int levels = 0;                       // θ_o levels of the transport operator (0 when reused)
  int bases = 0;
  std::string probe_name, database_label;
  double seconds_database = 0, seconds_search = 0, seconds_operator = 0, seconds_apply = 0;
};

// Errors name the file (probe, observations, database). A non-empty `out`
// is written with the images (atomically); a shared file this call stores is
// then a hard link to it where the file system allows (the same bytes, one
// write of 100-odd MB fewer), else written too.
SceneBasis ComputeSceneBasis(const SceneBasisOptions& options, const std::string& out = "");

}  // namespace brdfshot
