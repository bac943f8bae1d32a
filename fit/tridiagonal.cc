#include "fit/tridiagonal.h"

#include <algorithm>

#include "util/check.h"

namespace brdfshot {
namespace {
double PivotFloor(const Eigen::VectorXd& d) {
  return 1e-13 * std::max(d.size() ? d.cwiseAbs().maxCoeff() : 0.0, 1e-300);
}
}  // namespace

Eigen::MatrixXd TridiagonalSolves(const Eigen::VectorXd& d, const Eigen::VectorXd& e, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& lj, std::vector<char>* solved) {
  const Eigen::Index k = d.size(), L = lj.size();
  BRDFSHOT_CHECK(b.size() == k && e.size() == std::max<Eigen::Index>(k - 1, 0), "a tridiagonal solve's sizes differ");
  const double floor = PivotFloor(d);
  // Every λ's recurrence side by side, row by row: each λ's arithmetic is
  // its own recurrence's, but the divisions of different λ overlap instead
  // of each waiting on the last.
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(k, L);
  Eigen::MatrixXd piv(L, k), y(L, k);  // column i: every λ's pivot and forward value at row i
  std::vector<char> ok(static_cast<size_t>(L), 1);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double off = i > 0 ? e[i - 1] : 0.0;
    for (Eigen::Index l = 0; l < L; ++l) {
      if (!ok[static_cast<size_t>(l)]) continue;
      piv(l, i) = d[i] + lj[l] - (i > 0 ? off * off / piv(l, i - 1) : 0.0);
      ok[static_cast<size_t>(l)] = piv(l, i) > floor;
      y(l, i) = b[i] - (i > 0 ? off * y(l, i - 1) / piv(l, i - 1) : 0.0);
    }
  }
  for (Eigen::Index i = k - 1; i >= 0; --i)
    for (Eigen::Index l = 0; l < L; ++l)
      if (ok[static_cast<size_t>(l)]) X(i, l) = (y(l, i) - (i + 1 < k ? e[i] * X(i + 1, l) : 0.0)) / piv(l, i);
  if (solved) *solved = std::move(ok);
  return X;
}

ShiftedTridiagonal::ShiftedTridiagonal(const Eigen::VectorXd& d, const Eigen::VectorXd& e, double lambda)
    : d_(d), e_(e), piv_(d.size()) {
  const Eigen::Index k = d.size();
  BRDFSHOT_CHECK(e.size() == std::max<Eigen::Index>(k - 1, 0),
                 "a tridiagonal matrix's off-diagonal has " << e.size() << " entries for " << k << " rows");
  const double floor = PivotFloor(d);
  for (Eigen::Index i = 0; i < k && ok_; ++i) {
    piv_[i] = d[i] + lambda - (i > 0 ? e[i - 1] * e[i - 1] / piv_[i - 1] : 0.0);
    ok_ = piv_[i] > floor;
  }
}

Eigen::MatrixXd ShiftedTridiagonal::Solve(const Eigen::MatrixXd& B) const {
  BRDFSHOT_CHECK(ok_, "a solve with a shifted tridiagonal matrix whose recurrence stopped");
  const Eigen::Index k = d_.size();
  BRDFSHOT_CHECK(B.rows() == k, "a tridiagonal solve's right side has " << B.rows() << " rows for " << k);
  // Row by row over every column at once: in a row-major copy each step is
  // one contiguous vector operation.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Y = B;
  for (Eigen::Index i = 1; i < k; ++i) Y.row(i) -= (e_[i - 1] / piv_[i - 1]) * Y.row(i - 1);
  for (Eigen::Index i = k - 1; i >= 0; --i) {
    if (i + 1 < k) Y.row(i) -= e_[i] * Y.row(i + 1);
    Y.row(i) /= piv_[i];
  }
  return Y;
}

}  // namespace brdfshot
