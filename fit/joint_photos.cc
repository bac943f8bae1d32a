#include "fit/joint_photos.h"

#include <cmath>

#include "fit/lambda_choice.h"
#include "fit/photo_noise.h"
#include "util/check.h"

namespace brdfshot {

JointPhotos StackPhotos(const std::vector<BasisImages>& bases, const std::vector<Eigen::MatrixXd>& pixels,
                        const std::vector<std::string>& basis_paths, int folds) {
  BRDFSHOT_CHECK(!bases.empty() && bases.size() == pixels.size() && bases.size() == basis_paths.size());
  const BasisImages& first = bases[0];
  for (size_t i = 1; i < bases.size(); ++i) {
    if (bases[i].BasisNames() != first.BasisNames())
      throw FileError(basis_paths[i], "holds other bases than " + basis_paths[0] + ": photos fitted together need "
                                          "basis images of the same database");
    for (const char* key : {"database_kind", "grid"})
      if (bases[i].header.value(key, nlohmann::json()) != first.header.value(key, nlohmann::json()))
        throw FileError(basis_paths[i], std::string("has another ") + key + " than " + basis_paths[0]);
  }
  JointPhotos j;
  size_t total = 0;
  for (const BasisImages& b : bases) total += b.geometry.size();
  const Eigen::Index n = first.Y[0].cols();
  for (int c = 0; c < 3; ++c) j.basis.Y[c].resize(static_cast<Eigen::Index>(total), n);
  // The analytic baseline's lobes are stacked too where every photo has the same ones.
  bool lobes = first.has_lobes();
  for (const BasisImages& b : bases)
    lobes = lobes && b.has_lobes() && b.header.value("lobes", nlohmann::json()) == first.header.value("lobes", nlohmann::json());
  const Eigen::Index nl = lobes ? first.lobes[0].cols() : 0;
  for (int c = 0; c < 3; ++c) j.basis.lobes[c].resize(static_cast<Eigen::Index>(total), nl);
  j.y.resize(static_cast<Eigen::Index>(total), 3);
  PixelGeometry& g = j.basis.geometry;
  g.width = first.geometry.width, g.height = first.geometry.height;
  Eigen::Index row = 0;
  double noise2 = 0;
  bool unknown = false;
  std::string probes, probe_names;
  for (size_t i = 0; i < bases.size(); ++i) {
    const BasisImages& b = bases[i];
    const Eigen::Index rows = static_cast<Eigen::Index>(b.geometry.size());
    BRDFSHOT_CHECK(pixels[i].rows() == rows && pixels[i].cols() == 3);
    const double rms = std::sqrt(pixels[i].squaredNorm() / std::max<double>(1, 3.0 * static_cast<double>(rows)));
    if (!(rms > 0)) throw FileError(basis_paths[i], "its photo's pixels are all zero: nothing to fit");
    const double s = 1.0 / rms;
    for (int c = 0; c < 3; ++c) j.basis.Y[c].middleRows(row, rows) = b.Y[c] * static_cast<float>(s);
    for (int c = 0; c < 3 && lobes; ++c) j.basis.lobes[c].middleRows(row, rows) = b.lobes[c] * static_cast<float>(s);
    j.y.middleRows(row, rows) = pixels[i] * s;
    for (int f : WedgeFolds(b.geometry, folds)) j.fold_of_pixel.push_back(f);
    g.x.insert(g.x.end(), b.geometry.x.begin(), b.geometry.x.end());
    g.y.insert(g.y.end(), b.geometry.y.begin(), b.geometry.y.end());
    g.normal.insert(g.normal.end(), b.geometry.normal.begin(), b.geometry.normal.end());
    g.view.insert(g.view.end(), b.geometry.view.begin(), b.geometry.view.end());
    j.pixels.push_back(b.geometry.size());
    j.scale.push_back(s);
    const double e = RelativePixelNoise(b.geometry, pixels[i]);
    unknown = unknown || e < 0;
    noise2 += e * e * static_cast<double>(rows);
    probes += (i ? "," : "") + b.header.value("probe", std::string());
    probe_names += (i ? "," : "") + b.header.value("probe_name", std::string());
    row += rows;
  }
  j.relative_noise = unknown ? kUnknownNoise : std::sqrt(noise2 / std::max<double>(1, static_cast<double>(total)));
  j.basis.header = first.header;
  j.basis.header["probe"] = probes;
  j.basis.header["probe_name"] = probe_names;
  if (!lobes) j.basis.header.erase("lobes");
  return j;
}

}  // namespace brdfshot
