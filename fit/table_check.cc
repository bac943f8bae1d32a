#include "fit/table_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "util/check.h"

namespace brdfshot {

TableCheck::TableCheck(const TablesRef& tables, int block_rows) : tables_(MapOf(tables)), block_rows_(block_rows) {
  BRDFSHOT_CHECK(block_rows >= 1, "TableCheck: blocks need at least one row");
  const Eigen::Index rows = tables.rows(), cols = tables.cols();
  const Eigen::Index blocks = (rows + block_rows - 1) / block_rows;
  centre_.resize(blocks, cols);
  spread_.resize(blocks, cols);
#pragma omp parallel for schedule(static)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index r0 = b * block_rows, r1 = std::min(rows, r0 + block_rows);
    float* lo = centre_.row(b).data();  // the least value first, then the centre
    float* hi = spread_.row(b).data();  // the largest value first, then the spread
    std::fill_n(lo, cols, std::numeric_limits<float>::infinity());
    std::fill_n(hi, cols, -std::numeric_limits<float>::infinity());
    for (Eigen::Index r = r0; r < r1; ++r) {
      const float* row = tables.row(r).data();
      // A bin no material was measured at is zero in every column, and so
      // is every BRDF there: it cannot go negative, and leaving it out of
      // the range keeps the block's spread to the measured bins.
      bool measured = false;
      for (Eigen::Index i = 0; i < cols && !measured; ++i) measured = row[i] != 0;
      if (!measured) continue;
      for (Eigen::Index i = 0; i < cols; ++i) lo[i] = std::min(lo[i], row[i]), hi[i] = std::max(hi[i], row[i]);
    }
    if (!(lo[0] <= hi[0])) {  // no measured bin in the block
      std::fill_n(lo, cols, 0.0f);
      std::fill_n(hi, cols, 0.0f);
      continue;
    }
    // The centre of the range (float) and the deviation from it rounded up,
    // so that b = centre + (b − centre) holds exactly in the bound; the
    // differences of floats are exact in double.
    for (Eigen::Index i = 0; i < cols; ++i) {
      const double l = lo[i], h = hi[i];
      const float centre = static_cast<float>(0.5 * (l + h));
      const double d = std::max(h - centre, centre - l);
      float spread = static_cast<float>(d);
      if (static_cast<double>(spread) < d) spread = std::nextafter(spread, std::numeric_limits<float>::infinity());
      lo[i] = centre, hi[i] = spread;
    }
  }
}

std::vector<int> TableCheck::NegativeBins(const std::vector<int>& members, const Eigen::MatrixXd& wJ,
                                          double* cleared_share) const {
  const Eigen::Index k = static_cast<Eigen::Index>(members.size());
  BRDFSHOT_CHECK(wJ.rows() == k && wJ.cols() == 3, "TableCheck: weights are members × 3");
  for (int m : members) BRDFSHOT_CHECK(m >= 0 && m < tables_.cols(), "TableCheck: member out of range");
  const Eigen::Index rows = tables_.rows(), blocks = centre_.rows();
  // Each member's three channels side by side, read with its centre and spread.
  const MatrixXdR w3 = wJ;
  const Eigen::ArrayXXd aw3 = w3.array().abs();
  std::vector<char> negative(static_cast<size_t>(rows), 0);
  long cleared = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : cleared)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const float* centre = centre_.row(b).data();
    const float* spread = spread_.row(b).data();
    double bound[3] = {0, 0, 0};
    for (Eigen::Index j = 0; j < k; ++j) {
      const double m = centre[members[static_cast<size_t>(j)]], d = spread[members[static_cast<size_t>(j)]];
      for (int c = 0; c < 3; ++c) bound[c] += w3(j, c) * m - aw3(j, c) * d;
    }
    if (bound[0] >= 0 && bound[1] >= 0 && bound[2] >= 0) {
      ++cleared;
      continue;
    }
    const Eigen::Index r0 = b * block_rows_, r1 = std::min(rows, r0 + block_rows_);
    for (Eigen::Index r = r0; r < r1; ++r)
      negative[static_cast<size_t>(r)] = IsNegativeBin(tables_.row(r).data(), members, w3.data());
  }
  if (cleared_share) *cleared_share = blocks ? static_cast<double>(cleared) / static_cast<double>(blocks) : 1.0;
  std::vector<int> out;
  for (Eigen::Index r = 0; r < rows; ++r)
    if (negative[static_cast<size_t>(r)]) out.push_back(static_cast<int>(r));
  return out;
}

int KeepNonNegativeOnTable(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls, const Observation& obs,
                           double lambda, const TablesRef& tables, const TableCheck* check, BinRows* bins,
                           ClassSolution* s, int max_passes) {
  BRDFSHOT_CHECK(bins && s, "KeepNonNegativeOnTable: no bins or solution");
  BRDFSHOT_CHECK(!check || (check->tables().data() == tables.data() && check->tables().rows() == tables.rows() &&
                             check->tables().cols() == tables.cols()),
                 "KeepNonNegativeOnTable: the check is of other tables");
  WeightConstraint constraint;
  constraint.kind = WeightConstraint::Kind::kBins;
  constraint.bins = bins;
  std::unique_ptr<TableCheck> own;  // built at the second pass, when none is given
  int added = 0;
  for (int pass = 0; pass < max_passes; ++pass) {
    const Eigen::MatrixXd wJ = s->weights(cls.members, Eigen::all);
    if (!check && pass > 0) own = std::make_unique<TableCheck>(tables), check = own.get();
    const std::vector<int> negative = check ? check->NegativeBins(cls.members, wJ) : NegativeBins(tables, cls.members, wJ);
    if (negative.empty()) break;
    added += static_cast<int>(negative.size());
    bins->Append(tables, cls.members, negative);
    *s = SolveClass(f, cls, obs, lambda, constraint);
  }
  return added;
}

}  // namespace brdfshot
