#include "fit/basis_reference.h"

#include <algorithm>

#include "fit/transport.h"
#include "util/check.h"

namespace brdfshot {

const std::vector<MaterialClassList>& ReferenceClasses() {
  // Three per class, spanning each class's range: matte to dusty, rough to
  // mirror-like, single- to two-layer coats.
  static const std::vector<MaterialClassList> kClasses = {
      {"diffuse", {"blue-fabric", "pink-felt", "white-diffuse-bball"}},
      {"plastic", {"red-plastic", "gray-plastic", "pvc"}},
      {"metal", {"chrome", "aluminium", "brass"}},
      {"specular paint", {"specular-black-phenolic", "gold-metallic-paint", "two-layer-gold"}},
  };
  return kClasses;
}

std::vector<std::string> ReferenceMaterialNames() {
  std::vector<std::string> names;
  for (const auto& c : ReferenceClasses()) names.insert(names.end(), c.materials.begin(), c.materials.end());
  return names;
}

std::string ReferenceClassOf(const std::string& material) {
  for (const auto& c : ReferenceClasses())
    for (const auto& m : c.materials)
      if (m == material) return c.name;
  return "";
}

std::vector<int> ReferenceMaterialIndices(const BasisDatabase& db) {
  std::vector<int> out;
  for (const std::string& name : ReferenceMaterialNames()) {
    const auto it = std::find(db.materials.begin(), db.materials.end(), name);
    if (it != db.materials.end()) out.push_back(static_cast<int>(it - db.materials.begin()));
  }
  return out;
}

MatrixXfR MaterialColumns(const BasisDatabase& db, const std::vector<int>& materials) {
  MatrixXfR B(db.B.rows(), 3 * materials.size());
  for (size_t k = 0; k < materials.size(); ++k) {
    BRDFSHOT_CHECK(materials[k] >= 0 && materials[k] < db.num_materials());
    B.middleCols(3 * k, 3) = db.B.middleCols(3 * materials[k], 3);
  }
  return B;
}

std::map<std::string, double> WorstErrorPerLabel(const std::array<MatrixXfR, 3>& Y, const std::array<MatrixXfR, 3>& ref,
                                                 const std::vector<std::string>& labels) {
  std::map<std::string, double> worst;
  for (size_t k = 0; k < labels.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index col = 3 * k + c;
      BRDFSHOT_CHECK(col < Y[c].cols() && col < ref[c].cols());
      double& m = worst[labels[k]];
      m = std::max(m, RelativeRmse(Y[c].col(col).cast<double>(), ref[c].col(col).cast<double>()));
    }
  return worst;
}

MerlBrdf MaterialTable(const BasisDatabase& db, int m) {
  BRDFSHOT_CHECK(m >= 0 && m < db.num_materials());
  MerlBrdf t(db.grid);
  for (size_t idx = 0; idx < db.grid.size(); ++idx)
    for (int c = 0; c < 3; ++c) t.set_raw(c, idx, db.B(idx, 3 * m + c) / kMerlScale[c]);
  return t;
}

BasisImages RenderReferenceImages(const PixelGeometry& g, const LatLongProbe& probe, const BasisDatabase& db,
                                  const std::vector<int>& materials, int theta, int phi, Progress* progress) {
  BasisImages out;
  out.geometry = g;
  for (auto& y : out.Y) y = MatrixXfR::Zero(g.size(), 3 * materials.size());
  std::vector<std::string> names;
  for (size_t k = 0; k < materials.size(); ++k) {
    const MerlBrdf table = MaterialTable(db, materials[k]);
    const Eigen::MatrixXd img = RenderReference(
        g, probe, [&](const Vec3& wi, const Vec3& wo) { return table.Eval(wi, wo); }, theta, phi);
    for (int c = 0; c < 3; ++c) {
      // Every channel image is stored for every light channel column layout the
      // fast cache uses: column 3k + c of Y_c.
      out.Y[c].col(3 * k + c) = img.col(c).cast<float>();
      names.push_back(db.BasisName(3 * materials[k] + c));
    }
    if (progress) progress->Step();
  }
  out.header = BasisImagesHeader(
      probe, g, "reference theta=" + std::to_string(theta) + ",phi=" + std::to_string(phi) + ",trilinear,unfiltered",
      db, names);
  out.header["reference"] = true;
  return out;
}

double RelativeRmse(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& ref) {
  BRDFSHOT_CHECK(y.size() == ref.size());
  const double n = ref.norm();
  const double d = (y - ref).norm();
  if (n == 0) return d == 0 ? 0 : std::numeric_limits<double>::infinity();
  return d / n;
}

}  // namespace brdfshot
