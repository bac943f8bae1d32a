// Non-negative quadratic minimisation, for fits that must stay physically
// plausible.
//
// Every basis of the database is a measured BRDF channel, non-negative at
// every bin, so weights w ≥ 0 give a BRDF that is non-negative everywhere —
// the only guarantee that holds over all 1.46 M bins without evaluating them.
// The class-wise solve then becomes
//   minimise ½ wᵀ H w − bᵀ w  subject to w ≥ 0,
// H = G_JJ + λ_j I (symmetric, positive semi-definite), b = z_J + λ_j μ'.
#pragma once

#include <Eigen/Core>

namespace brdfshot {

struct NonNegativeResult {
  Eigen::VectorXd x;
  int iterations = 0;
  bool converged = false;  // false: the iteration cap was hit; x is feasible but not optimal
};

// Active-set method of Lawson and Hanson in its normal-equations form (Bro and
// De Jong's FNNLS): the free set grows one variable at a time by the most
// negative gradient and shrinks by interpolating back to feasibility, so every
// iterate is feasible and the objective never increases. Each free-set system
// H_PP x_P = b_P is solved by a Cholesky (LDLᵀ) factorisation with a ridge of
// 1e-13·max diag(H): when H is singular (λ = 0 with collinear bases) that picks
// one minimiser among many — any of them reaches the same objective to that
// relative precision. `tolerance`: a variable is added while its gradient
// component is below −tolerance·max|b| (KKT within that). H must be square,
// b as long; throws otherwise.
// `start` (optional, ≥ 0): a point that minimises the objective over its own
// support, e.g. the solution of the same problem with fewer variables padded
// with zeros; the method resumes from it instead of from 0.
NonNegativeResult SolveNonNegative(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, double tolerance = 1e-10,
                                   int max_iterations = 0 /* 0: 3·size */, const Eigen::VectorXd* start = nullptr);

}  // namespace brdfshot
