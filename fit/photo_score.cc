#include "fit/photo_score.h"

#include <cmath>
#include <unordered_map>

#include "util/check.h"

namespace brdfshot {

PredictionError ComparePrediction(const Eigen::MatrixXd& y, const Eigen::MatrixXd& p) {
  if (y.rows() != p.rows() || y.cols() != p.cols())
    throw Error("the prediction has " + std::to_string(p.rows()) + " × " + std::to_string(p.cols()) +
                " values, the photo " + std::to_string(y.rows()) + " × " + std::to_string(y.cols()));
  const double yy = y.squaredNorm();
  if (!(yy > 0)) throw Error("the photo is black on every pixel: nothing to score against");
  PredictionError e;
  e.relative_rmse = std::sqrt((p - y).squaredNorm() / yy);
  const double pp = p.squaredNorm();
  e.scale = pp > 0 ? (p.array() * y.array()).sum() / pp : 1.0;
  e.relative_rmse_scaled = std::sqrt((e.scale * p - y).squaredNorm() / yy);
  return e;
}

namespace {
// The photo's prediction, per channel: the fit's weights times the basis
// images of its bases, found by name.
Eigen::MatrixXd PredictFromBases(const FitRecord& fit, const BasisImages& basis, const std::string& basis_source) {
  const std::vector<std::string> names = basis.BasisNames();
  std::unordered_map<std::string, Eigen::Index> column;
  for (size_t i = 0; i < names.size(); ++i) column[names[i]] = static_cast<Eigen::Index>(i);
  BRDFSHOT_CHECK(fit.weights.rows() == static_cast<Eigen::Index>(fit.bases.size()) && fit.weights.cols() == 3,
                 "FitRecord: weights do not match its bases");
  const Eigen::Index P = basis.Y[0].rows();
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(P, 3);
  for (size_t i = 0; i < fit.bases.size(); ++i) {
    const auto at = column.find(fit.bases[i]);
    if (at == column.end()) throw FileError(basis_source, "has no basis image of the fit's basis " + fit.bases[i]);
    for (int c = 0; c < 3; ++c) {
      const double w = fit.weights(static_cast<Eigen::Index>(i), c);
      if (w != 0) p.col(c) += w * basis.Y[c].col(at->second).cast<double>();
    }
  }
  return p;
}
}  // namespace

PhotoScore ScoreFitOnPhoto(const FitRecord& fit, const std::string& fit_source, const BasisImages& basis,
                           const std::string& basis_source, const Eigen::MatrixXd& y, const std::string& photo_source) {
  const std::string database = basis.header.value("database", "");
  if (database != fit.database)
    throw FileError(basis_source, "is rendered with database \"" + database + "\", " + fit_source +
                                      " was fitted with \"" + fit.database + "\"");
  if (!(basis.Grid() == fit.grid))
    throw FileError(basis_source, "tabulates its bases on another grid than " + fit_source);
  if (y.rows() != basis.Y[0].rows() || y.cols() != 3)
    throw FileError(basis_source,
                    "has " + std::to_string(basis.Y[0].rows()) + " pixels, the photo " + std::to_string(y.rows()));
  if (!(y.squaredNorm() > 0)) throw FileError(photo_source, "is black on every pixel: nothing to score against");
  PhotoScore s;
  s.pixels = static_cast<size_t>(y.rows());
  s.fit = ComparePrediction(y, PredictFromBases(fit, basis, basis_source));
  if (fit.lambert_ggx && basis.has_lobes() && basis.Lobes(basis_source) == fit.lobes) {
    Eigen::MatrixXd p(y.rows(), 3);
    for (int c = 0; c < 3; ++c) p.col(c) = basis.lobes[c].cast<double>() * fit.lambert_ggx->weights.col(c);
    s.lambert_ggx = ComparePrediction(y, p);
  }
  return s;
}

}  // namespace brdfshot
