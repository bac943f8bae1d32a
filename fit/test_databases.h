// Test helpers shared by fit's tests (not part of the library).
#pragma once

#include <array>
#include <random>
#include <string>

#include "fit/database.h"
#include "normals/sphere_geometry.h"
#include "util/eigen_types.h"

namespace brdfshot {

// The repository's 16 demo stand-ins on a small grid, computed afresh (no
// cache): a real database small enough for a unit test.
inline DatabaseOptions DemoStandins(MerlGrid grid = MerlGrid{10, 10, 20}) {
  DatabaseOptions o;
  o.kind = "standin";
  o.data_root = std::string(BRDFSHOT_SOURCE_DIR) + "/samples/assets";
  o.grid = grid;
  o.use_cache = false;
  return o;
}

// Random images of n bases on a sphere: a quadratic in the normal plus a
// little per-pixel texture, so every scene's images have full column rank.
inline std::array<MatrixXfR, 3> RandomBasisImages(const PixelGeometry& g, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.1, 1.0);
  std::array<MatrixXfR, 3> Y;
  for (int c = 0; c < 3; ++c) {
    Y[c].resize(static_cast<Eigen::Index>(g.size()), n);
    for (int j = 0; j < n; ++j) {
      const double a = u(rng), bx = u(rng) - .5, by = u(rng) - .5, q = u(rng);
      for (size_t p = 0; p < g.size(); ++p)
        Y[c](static_cast<Eigen::Index>(p), j) = static_cast<float>(a + bx * g.normal[p].x + by * g.normal[p].y +
                                                                   q * g.normal[p].z * g.normal[p].x + 0.05 * u(rng));
    }
  }
  return Y;
}

}  // namespace brdfshot
