#include "fit/solver.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "util/check.h"

namespace brdfshot {

Eigen::VectorXd ChannelFactor::Project(const Eigen::VectorXd& y) const {
  const Eigen::Index n = R.cols();
  Eigen::VectorXd full = y;
  full.applyOnTheLeft(qr.householderQ().adjoint());
  return full.head(std::min<Eigen::Index>(n, full.size()));
}

std::array<ChannelFactor, 3> FactorBasisImages(const std::array<MatrixXfR, 3>& Y) {
  std::array<ChannelFactor, 3> f;
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd Yd = Y[c].cast<double>();
    const Eigen::Index n = Yd.cols();
    f[c].qr.compute(Yd);
    // With fewer pixels than bases the R factor is short and wide: pad with zero
    // rows so every column subset has the same n rows.
    f[c].R = Eigen::MatrixXd::Zero(n, n);
    const Eigen::Index rows = std::min(n, Yd.rows());
    f[c].R.topRows(rows) = f[c].qr.matrixQR().topRows(rows).triangularView<Eigen::Upper>();
    f[c].gram = Yd.transpose() * Yd;
  }
  return f;
}

Observation MakeObservation(const std::array<ChannelFactor, 3>& f, const Eigen::MatrixXd& y) {
  Observation o;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd z = f[c].Project(y.col(c));
    if (z.size() < f[c].R.cols()) z.conservativeResizeLike(Eigen::VectorXd::Zero(f[c].R.cols()));
    o.z[c] = z;
    o.norm2[c] = y.col(c).squaredNorm();
  }
  return o;
}

Eigen::VectorXd SolveRidge(const Eigen::MatrixXd& A, const Eigen::VectorXd& z, double lambda,
                           const Eigen::VectorXd& prior, double* condition) {
  BRDFSHOT_CHECK(lambda >= 0 && A.rows() == z.size() && A.cols() == prior.size());
  const Eigen::Index m = A.rows(), k = A.cols();
  // Solve for v = w − prior: min ‖A v − (z − A prior)‖² + λ‖v‖².
  Eigen::MatrixXd aug(m + k, k);
  aug.topRows(m) = A;
  aug.bottomRows(k) = std::sqrt(lambda) * Eigen::MatrixXd::Identity(k, k);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + k);
  rhs.head(m) = z - A * prior;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(aug);
  if (condition) {
    const Eigen::VectorXd s = Eigen::BDCSVD<Eigen::MatrixXd>(A).singularValues();
    const double smax = s.size() ? s[0] : 0, smin = s.size() == k ? s[k - 1] : 0;
    const double den = smin * smin + lambda;
    *condition = den > 0 ? std::sqrt((smax * smax + lambda) / den) : std::numeric_limits<double>::infinity();
  }
  return prior + cod.solve(rhs);
}

ClasswiseFit SolveClasswise(const std::array<Eigen::MatrixXd, 3>& R, const Observation& obs,
                            const std::vector<std::vector<int>>& members, const SolveOptions& opt) {
  const Eigen::Index n = R[0].cols();
  ClasswiseFit fit;
  double best = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < members.size(); ++j) {
    ClassSolution s;
    s.members = static_cast<int>(members[j].size());
    s.weights = Eigen::MatrixXd::Zero(n, 3);
    if (members[j].empty()) {
      s.residual = std::numeric_limits<double>::infinity();
      fit.classes.push_back(s);
      continue;
    }
    const double cj = static_cast<double>(members[j].size());
    const Eigen::VectorXd prior = Eigen::VectorXd::Constant(members[j].size(), 1.0 / cj);
    for (int c = 0; c < 3; ++c) {
      const Eigen::MatrixXd A = R[c](Eigen::all, members[j]);
      const double lambda_j = opt.lambda * obs.norm2[c] / cj;
      double cond = 0;
      const Eigen::VectorXd w = SolveRidge(A, obs.z[c], lambda_j, prior, opt.condition ? &cond : nullptr);
      s.condition[c] = cond;
      s.residual += (A * w - obs.z[c]).squaredNorm();
      for (size_t k = 0; k < members[j].size(); ++k) s.weights(members[j][k], c) = w[k];
    }
    if (s.residual < best) best = s.residual, fit.chosen = static_cast<int>(j);
    fit.classes.push_back(s);
  }
  BRDFSHOT_CHECK(fit.chosen >= 0, "no non-empty class to solve with");
  return fit;
}

Eigen::MatrixXd SolveLeastSquares(const std::array<Eigen::MatrixXd, 3>& R, const Observation& obs,
                                  const std::vector<int>& columns) {
  const Eigen::Index n = R[0].cols();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 3);
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd A = R[c](Eigen::all, columns);
    const Eigen::VectorXd x = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(obs.z[c]);
    for (size_t k = 0; k < columns.size(); ++k) w(columns[k], c) = x[k];
  }
  return w;
}

}  // namespace brdfshot
