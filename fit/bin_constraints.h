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
// The dual holds the bins with a multiplier and the latest round's, not the
// table's; every other bin costs at most one product per round.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "fit/basis_tables.h"
#include "util/eigen_types.h"

namespace brdfshot {

struct BinConstrainedSolution {
  Eigen::VectorXd w;
  int active = 0;         // bins with a positive multiplier
  int rounds = 0;         // cutting-plane rounds
  bool complete = false;  // no sampled bin outside the active set below −tolerance (false: the round cap was hit)
};

// The A of the constraint: rows `rows` of float `tables` (bins × bases),
// restricted to columns `members` in their order, kept in float. Products
// accumulate in double; they stream the whole of A, so A is as small as the
// values allow (half a copy in double) and the three channels' products are
// one pass (Times of a k × 3 matrix).
class BinRows {
 public:
  BinRows() = default;
  BinRows(const TablesRef& tables, const std::vector<int>& members, const std::vector<int>& rows);
  // Every `stride`-th row of the tables.
  static BinRows EveryNth(const TablesRef& tables, const std::vector<int>& members, int stride);
  // Every row of `tables` over `members`. Where the members are most of the
  // columns (nine tenths or more) the rows are read in place, the other
  // columns weighed by zero: a class of nearly every basis would otherwise be
  // a copy of nearly the whole sample (57 MB for 297 of MERL's 300 bases at
  // every 31st bin) for each material an evaluation fits, and the zero
  // columns cost at most a ninth more per product. In place, `tables` must
  // outlive the result (and its copies); Append first copies the rows.
  static BinRows AllRows(const TablesRef& tables, const std::vector<int>& members);

  Eigen::Index rows() const { return in_place() ? source_rows_ : a_.rows(); }
  Eigen::Index cols() const { return in_place() ? static_cast<Eigen::Index>(members_.size()) : a_.cols(); }
  bool in_place() const { return source_ != nullptr; }
  Eigen::MatrixXd Times(const Eigen::MatrixXd& w) const;  // A w, for every column of w
  // A(which, :) w: the same products as Times's at those rows.
  Eigen::MatrixXd TimesRows(const Eigen::MatrixXd& w, const std::vector<int>& which) const;
  Eigen::MatrixXd Rows(const std::vector<int>& which) const;  // A(which, :)
  // An upper bound of each row's Euclidean norm over the members (in place:
  // over the whole table row), for |A(i, :) d| ≤ norm_i ‖d‖.
  const Eigen::VectorXd& RowNorms() const { return norms_; }
  double RowSum(Eigen::Index i) const;
  void Append(const TablesRef& tables, const std::vector<int>& members, const std::vector<int>& table_rows);

 private:
  void AddRowNorms(Eigen::Index from);  // norms_ of rows from `from` on
  MatrixXfR a_;                         // the rows, copied over the members
  Eigen::VectorXd norms_;               // RowNorms
  TablesMap Source() const { return TablesMap(source_, source_rows_, source_cols_, Eigen::OuterStride<>(source_stride_)); }
  // Or, in place: every row of the tables at source_ over members_.
  const float* source_ = nullptr;
  Eigen::Index source_rows_ = 0, source_cols_ = 0, source_stride_ = 0;
  std::vector<int> members_;
};

// The rounds' cap. A round adds at most `bins_per_round` bins, and a
// weakly regularised class of nearly every basis checked against the whole
// table holds thousands at once: it takes up to about 45 rounds of 256
// (docs/benchmarks.md). A solution cut off before the dual converges is the
// dual's latest iterate, which can lie further below zero, elsewhere, than
// the unconstrained one; the cap only bounds what a pathological case costs.
constexpr int kDefaultMaxRounds = 200;

// inverse(): K = (G_JJ + λ_j I)⁺ (k × k), asked for only when some bin is
// below zero (it costs a k³ product, most fits never need it); w0: the
// unconstrained solution (k); A: the tables at the sampled bins, over the
// class's members (bins × k). A bin counts as negative below −tolerance × the
// largest value of A w₀ (an active bin sits at zero up to rounding).
// `v0`: A w₀ when the caller has it (one pass for three channels), else computed.
BinConstrainedSolution ConstrainToNonNegativeBins(const std::function<Eigen::MatrixXd()>& inverse,
                                                  const Eigen::VectorXd& w0, const BinRows& A, double tolerance = 1e-9,
                                                  int max_rounds = kDefaultMaxRounds, int bins_per_round = 256,
                                                  const Eigen::VectorXd* v0 = nullptr);

// The same for the channels of one fit (the columns of W0), each with its own
// multipliers and rounds (inverse(c): channel c's K). The channels still
// going share each round's product over the bins, one pass over A instead of
// one per channel; each channel's result is what ConstrainToNonNegativeBins
// gives it alone. A round computes A w again only at the bins whose last
// value, less norm_i ‖Δw‖, could be below zero (RowNorms); the others keep
// that lower bound, which is never below zero, so the bins found negative —
// and so the rounds and the result — are those of every bin computed.
std::vector<BinConstrainedSolution> ConstrainChannelsToNonNegativeBins(
    const std::function<Eigen::MatrixXd(int)>& inverse, const Eigen::MatrixXd& W0, const BinRows& A,
    double tolerance = 1e-9, int max_rounds = kDefaultMaxRounds, int bins_per_round = 256, const Eigen::MatrixXd* V0 = nullptr);

// A value Σ_i w_i b_i counts as negative below −kNegativeBinTolerance ·
// Σ_i |w_i b_i|: beyond the float rounding of the sum, at which a bin the
// constraint holds at zero sits.
constexpr double kNegativeBinTolerance = 1e-5;

// The weights of one fit for reading table rows: `members` (columns of the
// tables) and their weights in each channel (wJ, members × 3), kept one
// channel after another so that a row's three values are summed four
// members at a time (the checks of the whole table spend their time here).
class BinWeights {
 public:
  BinWeights(const std::vector<int>& members, const Eigen::MatrixXd& wJ);
  // Whether the BRDF is negative in any channel at one table row (`row`: its
  // values over every basis); `value`, where given: the row's value in each
  // channel, Σ_i w_i b_i.
  bool IsNegative(const float* row, double value[3] = nullptr) const;
  const std::vector<int>& members() const { return members_; }

 private:
  std::vector<int> members_;
  std::vector<double> w_[3];
};

// The bins (rows of `tables`) where the BRDF of weights wJ (members × 3, over
// columns `members`) is negative in any channel: the whole table, checked.
std::vector<int> NegativeBins(const TablesRef& tables, const std::vector<int>& members, const Eigen::MatrixXd& wJ);

}  // namespace brdfshot
