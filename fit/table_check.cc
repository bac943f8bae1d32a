#include "fit/table_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/check.h"

namespace brdfshot {

TableCheck::TableCheck(const MatrixXfR& tables, int block_rows) : tables_(tables), block_rows_(block_rows) {
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
  // Weights and their magnitudes interleaved per member, read together with
  // the member's centre and spread.
  std::vector<double> w(static_cast<size_t>(3 * k)), aw(static_cast<size_t>(3 * k));
  for (Eigen::Index j = 0; j < k; ++j)
    for (int c = 0; c < 3; ++c)
      w[static_cast<size_t>(3 * j + c)] = wJ(j, c), aw[static_cast<size_t>(3 * j + c)] = std::abs(wJ(j, c));
  std::vector<char> negative(static_cast<size_t>(rows), 0);
  long cleared = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : cleared)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const float* centre = centre_.row(b).data();
    const float* spread = spread_.row(b).data();
    double bound[3] = {0, 0, 0};
    for (Eigen::Index j = 0; j < k; ++j) {
      const double m = centre[members[static_cast<size_t>(j)]], d = spread[members[static_cast<size_t>(j)]];
      for (int c = 0; c < 3; ++c)
        bound[c] += w[static_cast<size_t>(3 * j + c)] * m - aw[static_cast<size_t>(3 * j + c)] * d;
    }
    if (bound[0] >= 0 && bound[1] >= 0 && bound[2] >= 0) {
      ++cleared;
      continue;
    }
    const Eigen::Index r0 = b * block_rows_, r1 = std::min(rows, r0 + block_rows_);
    for (Eigen::Index r = r0; r < r1; ++r) {
      const float* row = tables_.row(r).data();
      double value[3] = {0, 0, 0}, magnitude[3] = {0, 0, 0};
      for (Eigen::Index j = 0; j < k; ++j) {
        const double v = row[members[static_cast<size_t>(j)]];
        for (int c = 0; c < 3; ++c) {
          const double term = v * w[static_cast<size_t>(3 * j + c)];
          value[c] += term, magnitude[c] += std::abs(term);
        }
      }
      for (int c = 0; c < 3; ++c)
        if (value[c] < -kNegativeBinTolerance * magnitude[c]) negative[static_cast<size_t>(r)] = 1;
    }
  }
  if (cleared_share) *cleared_share = blocks ? static_cast<double>(cleared) / static_cast<double>(blocks) : 1.0;
  std::vector<int> out;
  for (Eigen::Index r = 0; r < rows; ++r)
    if (negative[static_cast<size_t>(r)]) out.push_back(static_cast<int>(r));
  return out;
}

int KeepNonNegativeOnTable(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls, const Observation& obs,
                           double lambda, const TableCheck& check, BinRows* bins, ClassSolution* s, int max_passes,
                           bool* complete) {
  BRDFSHOT_CHECK(bins && s, "KeepNonNegativeOnTable: no bins or solution");
  WeightConstraint constraint;
  constraint.kind = WeightConstraint::Kind::kBins;
  constraint.bins = bins;
  int added = 0;
  bool none_left = false;
  for (int pass = 0; pass < max_passes; ++pass) {
    const std::vector<int> negative = check.NegativeBins(cls.members, s->weights(cls.members, Eigen::all));
    if (negative.empty()) {
      none_left = true;
      break;
    }
    added += static_cast<int>(negative.size());
    bins->Append(check.tables(), cls.members, negative);
    *s = SolveClass(f, cls, obs, lambda, constraint);
  }
  if (complete) *complete = none_left;
  return added;
}

}  // namespace brdfshot
