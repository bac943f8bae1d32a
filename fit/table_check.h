// The whole table checked for negative bins, in milliseconds instead of a
// pass over every bin.
//
// A fitted BRDF Σ_i w_i b_i is non-negative at the bins its constraint saw
// (fit/bin_constraints.h), but a table has 1.46 M bins and checking them all
// streams the 1.75 GB of tables once per check. Neighbouring bins hold
// nearly the same values, so the table is cut into blocks of consecutive
// rows and each column's block is summarised once, when the check is built:
// the centre c of its range (float) and the largest deviation d from it
// (rounded up). Then for every bin of the block
//   Σ_i w_i b_i = Σ_i w_i c_i + Σ_i w_i (b_i − c_i) ≥ Σ_i w_i c_i − Σ_i |w_i| d_i,
// exactly, whatever the signs of the weights: the centres carry the
// cancellation between bases, only the small deviations are bounded. A block
// whose bound is ≥ 0 needs no look at its bins; the others are checked bin by
// bin, as NegativeBins does (the result is the same, to the bin). Bins that
// are zero in every column (not measured) are left out of the ranges: every
// BRDF is zero there.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "fit/bin_constraints.h"
#include "fit/solver.h"
#include "util/eigen_types.h"

namespace brdfshot {

class TableCheck {
 public:
  // Summarises `tables` (bins × bases) in blocks of `block_rows` rows: one
  // pass over the tables. `tables` must outlive the check.
  explicit TableCheck(const TablesRef& tables, int block_rows = kDefaultBlockRows);

  // The bins where the BRDF of weights wJ (members × 3, over columns
  // `members` of the tables) is negative in any channel, by the rule of
  // NegativeBins (kNegativeBinTolerance), ascending. `cleared_share`: the
  // share of blocks the bound alone cleared (for benchmarks).
  std::vector<int> NegativeBins(const std::vector<int>& members, const Eigen::MatrixXd& wJ,
                                double* cleared_share = nullptr) const;

  const TablesMap& tables() const { return tables_; }
  Eigen::Index blocks() const { return centre_.rows(); }
  int block_rows() const { return block_rows_; }

  // 128 rows (two thirds of a φ_d sweep of the MERL grid): smaller blocks
  // clear a little more but their summary takes longer to read, larger ones
  // clear less (docs/benchmarks.md measures 32 to 256).
  static constexpr int kDefaultBlockRows = 128;

 private:
  const TablesMap tables_;
  int block_rows_;
  MatrixXfR centre_;  // blocks × bases: the centre of the block's range
  MatrixXfR spread_;  // blocks × bases: max over the block's rows of |b − centre|, rounded up
};

// `s`: class `cls` solved at `lambda` under the constraint of `bins` (its
// sampled rows, SolveClass with WeightConstraint::Kind::kBins). The whole of
// `tables` is checked: bins found below zero join `bins` and the class is
// solved again, up to `max_passes` checks. `check`: a TableCheck of
// `tables`, where the caller checks many fits; without one the first pass
// reads every bin (cheaper than building a summary, and most fits need no
// second pass) and a summary is built only for a second. Returns the number
// of bins added.
int KeepNonNegativeOnTable(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls, const Observation& obs,
                           double lambda, const TablesRef& tables, const TableCheck* check, BinRows* bins,
                           ClassSolution* s, int max_passes = 4);

}  // namespace brdfshot
