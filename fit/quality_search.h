// Choosing the basis images' quality from an error target, on the user's own scene.
//
// The default RenderQuality was chosen from measurements on three probes
// (docs/benchmarks.md, `brdfshot bench-basis`). A user's probe can be harder — a smaller,
// brighter sun, a sharp window edge — and the error of a half-vector quadrature
// is not even monotone in its sample counts, so a setting cannot be predicted
// from the probe's statistics. Instead this measures: it renders a few materials
// per class on a subset of the scene's own pixels with the converged reference
// (fit/basis_reference.h), then walks a ladder of settings from cheap to fine
// and keeps the first whose worst relative RMSE is within the target.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/database.h"
#include "fit/transport.h"
#include "normals/sphere_geometry.h"
#include "util/progress.h"

namespace brdfshot {

// A material the error is measured on, and the class it stands for.
struct ErrorTestMaterial {
  int index;          // into BasisDatabase::materials
  std::string label;  // diffuse | plastic | metal | specular paint | family | material name
};
// MERL databases: the named reference materials (3 per class) it holds. The
// stand-in: the first material of each family. Otherwise up to 8 spread over
// the list. Never empty for a non-empty database.
std::vector<ErrorTestMaterial> ErrorTestMaterials(const BasisDatabase& db);

// Settings from cheap to fine. Sample counts first, at `base`'s probe width;
// then, when the probe is wider than that, the probe as given. Every other
// field is `base`'s.
std::vector<RenderQuality> QualityLadder(const RenderQuality& base, int probe_width);

struct QualitySearchOptions {
  double target = 0.01;  // worst relative RMSE allowed over the test materials' channels
  // About this many pixels of the scene carry the error: bench-basis's count.
  // The error sits on a few grazing pixels, so 200 pixels can miss them (sunset,
  // 128²: 0.7 % on 193 pixels, 2.1 % on 779); 700 cost ~60 s of reference on 2 cores.
  int pixels = 700;
  int reference_theta = 192;  // reference half-vector samples (bench-basis's converged setting)
  int reference_phi = 384;
};

struct QualityTrial {
  RenderQuality quality;
  std::map<std::string, double> label_error;  // worst channel per label
  double worst = 0;
};

struct QualityChoice {
  RenderQuality quality;  // the first trial within target, else the trial with the least error
  bool reached = false;
  double error = 0;                  // its worst relative RMSE
  std::vector<QualityTrial> trials;  // in ladder order, up to and including the chosen one when reached
  size_t pixels = 0;                 // pixels the error was measured on
  double reference_seconds = 0;
};

// Throws Error when the target is not a positive finite number or the geometry
// is empty. When no setting reaches the target, returns the best one with
// reached = false: the caller decides whether that is acceptable.
QualityChoice ChooseQuality(const PixelGeometry& geometry, const LatLongProbe& probe, const BasisDatabase& db,
                            const RenderQuality& base, const QualitySearchOptions& options, Progress* progress);

}  // namespace brdfshot
