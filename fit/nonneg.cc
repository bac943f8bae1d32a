#include "fit/nonneg.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <vector>

#include "util/check.h"

namespace brdfshot {

namespace {
// x_P = H_PP⁻¹ b_P with the ridge of the header's comment.
Eigen::VectorXd SolveFree(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, const std::vector<int>& P, double ridge) {
  Eigen::MatrixXd Hpp = H(P, P);
  Hpp.diagonal().array() += ridge;
  return Eigen::LDLT<Eigen::MatrixXd>(Hpp).solve(b(P));
}
}  // namespace

NonNegativeResult SolveNonNegative(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, double tolerance,
                                   int max_iterations, const Eigen::VectorXd* start) {
  BRDFSHOT_CHECK(H.rows() == H.cols() && H.rows() == b.size(), "SolveNonNegative: H must be square, b as long");
  const Eigen::Index n = b.size();
  NonNegativeResult r;
  r.x = Eigen::VectorXd::Zero(n);
  if (n == 0) {
    r.converged = true;
    return r;
  }
  if (max_iterations <= 0) max_iterations = 3 * static_cast<int>(n);
  const double scale = b.cwiseAbs().maxCoeff();
  const double ridge = 1e-13 * std::max(H.diagonal().maxCoeff(), 1e-300);
  const double threshold = tolerance * scale;
  std::vector<char> free_var(n, 0);
  if (start) {
    BRDFSHOT_CHECK(start->size() == n, "SolveNonNegative: the start has another size");
    for (Eigen::Index i = 0; i < n; ++i)
      if ((*start)[i] > 0) r.x[i] = (*start)[i], free_var[i] = 1;
  }
  // A variable whose own solve refuses it (possible only by rounding) is not
  // offered again until the iterate moves, so the loop cannot cycle on it.
  std::vector<char> refused(n, 0);
  Eigen::VectorXd& x = r.x;
  while (r.iterations < max_iterations) {
    // The steepest-descent variable among those held at zero. x is zero off
    // the free set, which is small beside n in the bin constraint's dual
    // (thousands of bins, at most a class's size of them free).
    std::vector<int> support;
    for (Eigen::Index i = 0; i < n; ++i)
      if (x[i] != 0) support.push_back(static_cast<int>(i));
    const Eigen::VectorXd descent = b - H(Eigen::all, support) * x(support);
    Eigen::Index add = -1;
    double best = threshold;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!free_var[i] && !refused[i] && descent[i] > best) best = descent[i], add = i;
    if (add < 0) {
      r.converged = true;
      break;
    }
    free_var[add] = 1;
    const Eigen::VectorXd before = x;
    // Solve on the free set; step back to the boundary while a free variable
    // would turn non-positive, and release it.
    while (r.iterations++ < max_iterations) {
      std::vector<int> P;
      for (Eigen::Index i = 0; i < n; ++i)
        if (free_var[i]) P.push_back(static_cast<int>(i));
      const Eigen::VectorXd s = SolveFree(H, b, P, ridge);
      if (s.minCoeff() > 0) {
        x.setZero();
        x(P) = s;
        break;
      }
      double alpha = 1;
      for (size_t k = 0; k < P.size(); ++k)
        if (s[k] <= 0) alpha = std::min(alpha, x[P[k]] / (x[P[k]] - s[k]));
      for (size_t k = 0; k < P.size(); ++k) {
        double& xi = x[P[k]];
        xi += alpha * (s[k] - xi);
        // The variables that reached the boundary leave the free set (the
        // one just added, if its own solve says ≤ 0, with them).
        if (xi <= 0 || (s[k] <= 0 && xi <= 1e-15 * s.cwiseAbs().maxCoeff())) xi = 0, free_var[P[k]] = 0;
      }
      if (std::none_of(free_var.begin(), free_var.end(), [](char f) { return f != 0; })) break;
    }
    if (x == before)
      refused[add] = 1;
    else
      std::fill(refused.begin(), refused.end(), 0);
  }
  return r;
}

}  // namespace brdfshot
