// The basis-image cache: Y for one scene (probe + pixel geometry + quality +
// database), so later stages never re-render. File layout:
//   "BSHOTBI1" | uint64 header bytes | JSON header | int32 x,y per pixel |
//   float64 normal, view per pixel | float32 Y_R, Y_G, Y_B (pixels × bases, row-major)
//   | float32 L_R, L_G, L_B (pixels × lobes, row-major; only with "num_lobes" > 0)
// The JSON header records the probe (name, hash), the geometry hash, the
// quality settings, the database label and every basis name; with lobes, their
// description ("lobes", fit/lambert_ggx.h) and count ("num_lobes").
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "calib/latlong_probe.h"
#include "fit/database.h"
#include "fit/lambert_ggx.h"
#include "fit/nbrdf.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {

struct BasisImages {
  nlohmann::json header;
  PixelGeometry geometry;
  std::array<MatrixXfR, 3> Y;
  // The analytic baseline's lobes rendered the same way (pixels × lobes per
  // channel; no columns when the file holds none).
  std::array<MatrixXfR, 3> lobes;

  std::vector<std::string> BasisNames() const;
  MerlGrid Grid() const;  // the database grid the bases were tabulated on (header "grid")
  bool has_lobes() const { return lobes[0].cols() > 0; }
  LambertGgxLobes Lobes(const std::string& source) const;  // Error naming `source` when absent or bad
  void Write(const std::string& path) const;  // atomic
  // Errors name the file: bad magic, truncated, header/payload mismatch, NaN.
  static BasisImages Read(const std::string& path);
  static BasisImages Parse(std::string_view bytes, const std::string& name);
};

// The header every basis-image file carries: its format, the probe (name,
// hash, size), the geometry's hash, the quality the images were rendered at,
// the database (label, kind, grid) and the name of every basis, in column
// order. Writers add what else they know (the files they came from).
nlohmann::json BasisImagesHeader(const LatLongProbe& probe, const PixelGeometry& geometry, const std::string& quality,
                                 const BasisDatabase& db, const std::vector<std::string>& basis_names);

}  // namespace brdfshot
