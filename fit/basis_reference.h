// Converged references for basis images, and the error of fast ones against them.
//
// The reference integrates the same basis tables (trilinear, not nearest-entry)
// against the unfiltered probe on a dense half-vector grid: slow by design, so it
// is run for a few materials per class on a few hundred pixels and cached in the
// basis-image file format (`brdfshot reference`).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/basis_images.h"
#include "fit/database.h"
#include "normals/sphere_geometry.h"
#include "util/progress.h"

namespace brdfshot {

// Named MERL materials standing for each class the error goal is stated for.
struct MaterialClassList {
  std::string name;  // diffuse | plastic | metal | specular paint
  std::vector<std::string> materials;
};
const std::vector<MaterialClassList>& ReferenceClasses();
std::vector<std::string> ReferenceMaterialNames();          // all of the above, in order
std::string ReferenceClassOf(const std::string& material);  // "" if none

// The table of one material of the database (unmeasured entries = 0, as the
// basis matrix stores them).
MerlBrdf MaterialTable(const BasisDatabase& db, int material);

// Reference images (pixels × 3 per material, channel c under light channel c)
// for the given materials, with `theta`×`phi` half-vector samples per pixel.
BasisImages RenderReferenceImages(const PixelGeometry& geometry, const LatLongProbe& probe, const BasisDatabase& db,
                                  const std::vector<int>& materials, int theta, int phi, Progress* progress);

// Indices of the reference materials (ReferenceMaterialNames) the database
// holds, in that order; empty for a database without MERL names.
std::vector<int> ReferenceMaterialIndices(const BasisDatabase& db);

// The database's three channel columns of each of `materials`, in that order.
MatrixXfR MaterialColumns(const BasisDatabase& db, const std::vector<int>& materials);

// Images of MaterialColumns (column 3k + c of Y_c: material k, channel c) against
// a reference in the same layout: the worst RelativeRmse over each material's
// channels, per label (`labels[k]` for material k; materials may share one).
std::map<std::string, double> WorstErrorPerLabel(const std::array<MatrixXfR, 3>& Y, const std::array<MatrixXfR, 3>& ref,
                                                 const std::vector<std::string>& labels);

// ‖y − ref‖ / ‖ref‖ (0 when both vanish).
double RelativeRmse(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& ref);

}  // namespace brdfshot
