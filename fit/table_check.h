// The whole table checked for negative bins, in a fraction of a pass over
// every bin.
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
// whose bound is ≥ 0 needs no look at its bins; in the others each sub-block
// (a finer summary of the same kind) is bounded in turn, and only the bins of
// the sub-blocks left are checked bin by bin, as NegativeBins does (the
// result is the same, to the bin). Bins that
// are zero in every column (not measured) are left out of the ranges: every
// BRDF is zero there.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include "fit/bin_constraints.h"
#include "fit/solver.h"
#include "util/eigen_types.h"

namespace brdfshot {

class TableCheck {
 public:
  // Summarises `tables` (bins × bases) in blocks of `block_rows` rows, and
  // each block in sub-blocks of `sub_rows` rows (0, or not fewer than
  // `block_rows`: one level): one pass over the tables. `tables` must
  // outlive the check.
  explicit TableCheck(const TablesRef& tables, int block_rows = kDefaultBlockRows, int sub_rows = kDefaultSubRows);

  // The bins where the BRDF of weights wJ (members × 3, over columns
  // `members` of the tables) is negative in any channel, by the rule of
  // NegativeBins (kNegativeBinTolerance), ascending. `cleared_share`: the
  // share of bins the bounds cleared without reading them (for benchmarks).
  std::vector<int> NegativeBins(const std::vector<int>& members, const Eigen::MatrixXd& wJ,
                                double* cleared_share = nullptr) const;

  const TablesMap& tables() const { return tables_; }
  // The bound Σ_i w_i c_i − Σ_i |w_i| s_i of block `b` (sub-block `u`), per
  // channel, for the weights w3 (members × 3, column-major: one channel
  // after another) and their magnitudes aw3.
  void BlockBound(Eigen::Index b, const std::vector<int>& members, const double* w3, const double* aw3,
                  double bound[3]) const;
  void SubBound(Eigen::Index u, const std::vector<int>& members, const double* w3, const double* aw3,
                double bound[3]) const;
  Eigen::Index blocks() const { return centre_.rows(); }
  Eigen::Index subs() const;
  int block_rows() const { return block_rows_; }
  int sub_rows() const { return sub_rows_; }
  bool two_levels() const { return sub_rows_ < block_rows_; }

  // 128 rows (two thirds of a φ_d sweep of the MERL grid) clear most blocks
  // of a well-regularised fit at a read of their summary alone; where the
  // weights cancel more (a fit near least squares) a block's range is too
  // wide: on set a's fits the blocks clear 6–69 % of the bins, their 16-row
  // sub-blocks 41–95 % (docs/benchmarks.md), each for an eighth of what
  // reading its bins costs. The sub-blocks' summary is an eighth of the
  // tables' size.
  static constexpr int kDefaultBlockRows = 128;
  static constexpr int kDefaultSubRows = 16;

 private:
  const TablesMap tables_;
  int block_rows_, sub_rows_;
  MatrixXfR centre_;      // blocks × bases: the centre of the block's range
  MatrixXfR spread_;      // blocks × bases: max over the block's rows of |b − centre|, rounded up
  MatrixXfR sub_centre_;  // the same per sub-block (empty with one level)
  MatrixXfR sub_spread_;
};

// Successive checks of one class's weights, each close to the last (a fit
// solved again with the bins the last check found): a bin whose last value
// stays ≥ 0 under any change the summary allows is not read again. For the
// change d = w − w_last, every bin of a sub-block gains at least
//   Σ_i d_i c_i − Σ_i |d_i| s_i
// (the sub-block's bound, for d), so a bin is cleared where its last value
// plus that is ≥ 0, and keeps that sum as a lower bound of its new value;
// only the others are read. Adding a few hundred bins to a fit moves its
// weights by a few per cent: on set a's fits a second check reads a median
// 1.2 % of the bins where the first read 21 % (docs/benchmarks.md). The bins
// returned are those of TableCheck::NegativeBins for the same weights.
class TableCheckSequence {
 public:
  // `check` must outlive the sequence.
  TableCheckSequence(const TableCheck& check, std::vector<int> members);
  std::vector<int> NegativeBins(const Eigen::MatrixXd& wJ, double* read_share = nullptr);

 private:
  const TableCheck& check_;
  std::vector<int> members_;
  Eigen::MatrixXd last_;  // the weights of the last check (members × 3); empty before the first
  // Per sub-block: whether values_ holds, for each of its bins and channels, a
  // lower bound of the value at `last_` (the value rounded down to a float
  // where the bin was read). At a bin no material was measured at it may lie
  // above the value (zero for every BRDF), which no check can find negative.
  std::vector<char> known_;
  // Bins × 3, written only in known sub-blocks. Float, rounded down, halves
  // the 35 MB a table of MERL's size would take in double.
  std::unique_ptr<float[]> values_;
};

// Per channel, the least t in [0, 1] for which (1 − t) w + t μ' is at least
// zero at each of `rows` (table rows), μ' the class's mean (1/k on each of
// the k `members`), wJ the fit's weights over the members (members × 3); 0
// for a channel that is not below zero there. The mean is non-negative at
// every bin (the tables are), so the blend is non-negative wherever w is, and
// a bin within the check's tolerance stays within it: lifting the bins found
// below zero lifts the whole table. It is also where a larger λ pulls the
// fit (the prior), so the blend is a little more of the same regularisation.
std::array<double, 3> MeanBlendToNonNegative(const TablesRef& tables, const std::vector<int>& members,
                                             const Eigen::MatrixXd& wJ, const std::vector<int>& rows);

// What KeepNonNegativeOnTable did to a fit.
struct TableKeep {
  int bins_added = 0;  // bins found below zero and constrained
  int solves = 0;      // the class solved again with them
  // Per channel: the t of the blend toward the class's mean
  // (MeanBlendToNonNegative) that lifts what the solves left below zero;
  // 0 where they left nothing.
  std::array<double, 3> mean_blend{};
  double largest_mean_blend() const { return std::max({mean_blend[0], mean_blend[1], mean_blend[2]}); }
};

// The summary the whole-table checks of `tables` read: one given (an
// evaluation builds it once for all its fits), or one built at the first
// check that needs it and kept for the next (the parts of one fit check the
// same tables). Without one a check reads every bin: cheaper than building a
// summary for a fit checked once, which most are.
class TableCheckSource {
 public:
  // `tables` (and `given`, where given, a summary of them) must outlive it.
  explicit TableCheckSource(const TablesRef& tables, const TableCheck* given = nullptr);
  const TablesMap& tables() const { return tables_; }
  const TableCheck* summary() const { return given_ ? given_ : built_.get(); }
  // The summary, built now where there is none: the blocks' level alone (a
  // fit checked a few times does not repay the sub-blocks', which takes
  // longer to build than a pass over every bin).
  const TableCheck& Summary();

 private:
  const TablesMap tables_;
  const TableCheck* given_;
  std::unique_ptr<TableCheck> built_;
};

// `s`: class `cls` solved at `lambda` under the constraint of `bins` (its
// sampled rows, SolveClass with WeightConstraint::Kind::kBins). The whole of
// the tables of `checks` is checked: bins found below zero join `bins` and
// the class is solved again, up to `max_solves` times. Each solve with a
// check's bins leaves far fewer (bins next to those it holds at zero dip a
// little), but rarely none: what the solves leave, a hair below zero, the
// blend toward the class's mean lifts; on return the BRDF is non-negative at
// every bin of the tables. A fit's first check reads every bin unless
// `checks` has a summary; a second check builds one there.
TableKeep KeepNonNegativeOnTable(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls,
                                 const Observation& obs, double lambda, TableCheckSource* checks, BinRows* bins,
                                 ClassSolution* s, int max_solves = 2);

}  // namespace brdfshot
