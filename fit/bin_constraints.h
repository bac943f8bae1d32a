// A fit whose BRDF is non-negative at the database's bins, not only in its
// weights.
//
// Non-negative weights make the BRDF non-negative everywhere, but a material
// that is not in the database is mostly a *difference* of database materials
// (a sharper highlight, a darker base): forcing w ≥ 0 costs half again of the
// relit error in leave-one-out over MERL (docs/benchmarks.md). The constraint
// that matters is on the BRDF itself, Σ_i w_i b_i(bin) ≥ 0 at every bin:
//   minimise ½ wᵀHw − bᵀw  subject to  A w ≥ 0,
// A the tables' rows at the bins (bins × class members). Its Lagrange dual is
// a non-negative least squares in one multiplier per bin,
//   w(μ) = w₀ + K Aᵀμ,  minimise ½ μᵀ(A K Aᵀ)μ + μᵀ(A w₀), μ ≥ 0,
// with w₀ the unconstrained solution and K = H⁺. Only the bins that go
// negative ever get a multiplier, so the bins are added in rounds (a cutting
// plane): solve, find the bins below zero, add them, solve the dual again.
// The dual's size is the number of bins that ever went negative, not the
// table's; every other bin costs one product per round.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "util/eigen_types.h"

namespace brdfshot {

struct BinConstrainedSolution {
  Eigen::VectorXd w;
  int active = 0;         // bins with a positive multiplier
  int rounds = 0;         // cutting-plane rounds
  bool complete = false;  // no sampled bin outside the active set below −tolerance (false: the round cap was hit)
};

// inverse(): K = (G_JJ + λ_j I)⁺ (k × k), asked for only when some bin is
// below zero (it costs a k³ product, most fits never need it); w0: the unconstrained solution (k); A: the
// tables' rows at the sampled bins, restricted to the class's members in
// order (bins × k). A bin counts as negative below −tolerance × the largest
// value of A w₀ (an active bin sits at zero up to rounding).
BinConstrainedSolution ConstrainToNonNegativeBins(const std::function<Eigen::MatrixXd()>& inverse,
                                                  const Eigen::VectorXd& w0, const MatrixXdR& A,
                                                  double tolerance = 1e-9, int max_rounds = 30,
                                                  int bins_per_round = 256);

// A value Σ_i w_i b_i counts as negative below −kNegativeBinTolerance ·
// Σ_i |w_i b_i|: beyond the float rounding of the sum, at which a bin the
// constraint holds at zero sits.
constexpr double kNegativeBinTolerance = 1e-5;

// The bins (rows of `tables`) where the BRDF of weights wJ (members × 3, over
// columns `members`) is negative in any channel: the whole table, checked.
std::vector<int> NegativeBins(const MatrixXfR& tables, const std::vector<int>& members, const Eigen::MatrixXd& wJ);

// The rows of `tables` every `stride`-th bin, restricted to columns `members`,
// in double: the A of ConstrainToNonNegativeBins.
MatrixXdR ConstraintBins(const MatrixXfR& tables, const std::vector<int>& members, int stride);
// The same for the listed rows.
MatrixXdR TableRows(const MatrixXfR& tables, const std::vector<int>& members, const std::vector<int>& rows);

}  // namespace brdfshot
