#include "fit/table_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "util/check.h"

namespace brdfshot {

namespace {

// The centre of the range [l, h] (float) and the deviation from it rounded
// up, so that b = centre + (b − centre) holds exactly in the bound; the
// differences of floats are exact in double.
void CentreAndSpread(float l, float h, float* centre, float* spread) {
  const float c = static_cast<float>(0.5 * (static_cast<double>(l) + h));
  const double d = std::max(static_cast<double>(h) - c, static_cast<double>(c) - l);
  float s = static_cast<float>(d);
  if (static_cast<double>(s) < d) s = std::nextafter(s, std::numeric_limits<float>::infinity());
  *centre = c, *spread = s;
}

}  // namespace

TableCheck::TableCheck(const TablesRef& tables, int block_rows, int sub_rows)
    : tables_(MapOf(tables)), block_rows_(block_rows), sub_rows_(sub_rows) {
  BRDFSHOT_CHECK(block_rows >= 1, "TableCheck: blocks need at least one row");
  if (sub_rows_ <= 0 || sub_rows_ >= block_rows_) sub_rows_ = block_rows_;
  BRDFSHOT_CHECK(block_rows_ % sub_rows_ == 0, "TableCheck: sub-blocks must divide the blocks");
  const Eigen::Index rows = tables.rows(), cols = tables.cols();
  const Eigen::Index blocks = (rows + block_rows_ - 1) / block_rows_, subs = (rows + sub_rows_ - 1) / sub_rows_;
  const Eigen::Index per_block = block_rows_ / sub_rows_;
  centre_.resize(blocks, cols);
  spread_.resize(blocks, cols);
  sub_centre_.resize(two_levels() ? subs : 0, cols);
  sub_spread_.resize(two_levels() ? subs : 0, cols);
#pragma omp parallel for schedule(static)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    float* lo = centre_.row(b).data();  // the least value first, then the centre
    float* hi = spread_.row(b).data();  // the largest value first, then the spread
    std::fill_n(lo, cols, std::numeric_limits<float>::infinity());
    std::fill_n(hi, cols, -std::numeric_limits<float>::infinity());
    std::vector<float> sub_lo(static_cast<size_t>(cols)), sub_hi(static_cast<size_t>(cols));
    for (Eigen::Index u = b * per_block; u < std::min(subs, (b + 1) * per_block); ++u) {
      std::fill(sub_lo.begin(), sub_lo.end(), std::numeric_limits<float>::infinity());
      std::fill(sub_hi.begin(), sub_hi.end(), -std::numeric_limits<float>::infinity());
      for (Eigen::Index r = u * sub_rows_; r < std::min(rows, (u + 1) * sub_rows_); ++r) {
        const float* row = tables.row(r).data();
        // A bin no material was measured at is zero in every column, and so
        // is every BRDF there: it cannot go negative, and leaving it out of
        // the range keeps the block's spread to the measured bins.
        bool measured = false;
        for (Eigen::Index i = 0; i < cols && !measured; ++i) measured = row[i] != 0;
        if (!measured) continue;
        for (Eigen::Index i = 0; i < cols; ++i)
          sub_lo[static_cast<size_t>(i)] = std::min(sub_lo[static_cast<size_t>(i)], row[i]),
          sub_hi[static_cast<size_t>(i)] = std::max(sub_hi[static_cast<size_t>(i)], row[i]);
      }
      const bool measured = sub_lo[0] <= sub_hi[0];
      for (Eigen::Index i = 0; i < cols; ++i) {
        const float l = sub_lo[static_cast<size_t>(i)], h = sub_hi[static_cast<size_t>(i)];
        if (measured) lo[i] = std::min(lo[i], l), hi[i] = std::max(hi[i], h);
        if (two_levels()) {
          if (measured)
            CentreAndSpread(l, h, &sub_centre_(u, i), &sub_spread_(u, i));
          else
            sub_centre_(u, i) = sub_spread_(u, i) = 0;  // no measured bin: every BRDF is zero there
        }
      }
    }
    const bool measured = lo[0] <= hi[0];
    for (Eigen::Index i = 0; i < cols; ++i) {
      if (measured)
        CentreAndSpread(lo[i], hi[i], &lo[i], &hi[i]);
      else
        lo[i] = hi[i] = 0;
    }
  }
}

namespace {

// Σ_i w_i c_i − Σ_i |w_i| s_i over the members, per channel, for one row of
// a summary's centres and spreads.
void Bound(const float* centre, const float* spread, const std::vector<int>& members, const double* w,
           const double* aw, double bound[3]) {
  // Four partial sums per channel (members j, j+1, j+2, j+3), as in
  // BinWeights::IsNegative: independent chains the compiler vectorises.
  constexpr int kLanes = 4;
  const size_t k = members.size();
  const int* m = members.data();
  double acc[3][kLanes] = {};
  size_t j = 0;
  for (; j + kLanes <= k; j += kLanes) {
    double c4[kLanes], d4[kLanes];
    for (int l = 0; l < kLanes; ++l) c4[l] = centre[m[j + static_cast<size_t>(l)]], d4[l] = spread[m[j + static_cast<size_t>(l)]];
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < kLanes; ++l) {
        const size_t i = static_cast<size_t>(c) * k + j + static_cast<size_t>(l);
        acc[c][l] += w[i] * c4[l] - aw[i] * d4[l];
      }
  }
  for (; j < k; ++j)
    for (int c = 0; c < 3; ++c) {
      const size_t i = static_cast<size_t>(c) * k + j;
      acc[c][0] += w[i] * centre[m[j]] - aw[i] * spread[m[j]];
    }
  for (int c = 0; c < 3; ++c) bound[c] = (acc[c][0] + acc[c][1]) + (acc[c][2] + acc[c][3]);
}

bool AtLeastZero(const double v[3]) { return v[0] >= 0 && v[1] >= 0 && v[2] >= 0; }

// The largest float not above v: a value kept in float stays a lower bound.
float FloatBelow(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

void TableCheck::BlockBound(Eigen::Index b, const std::vector<int>& members, const double* w3, const double* aw3,
                            double bound[3]) const {
  Bound(centre_.row(b).data(), spread_.row(b).data(), members, w3, aw3, bound);
}

void TableCheck::SubBound(Eigen::Index u, const std::vector<int>& members, const double* w3, const double* aw3,
                          double bound[3]) const {
  if (two_levels())
    Bound(sub_centre_.row(u).data(), sub_spread_.row(u).data(), members, w3, aw3, bound);
  else
    BlockBound(u, members, w3, aw3, bound);
}

Eigen::Index TableCheck::subs() const { return two_levels() ? sub_centre_.rows() : centre_.rows(); }

std::vector<int> TableCheck::NegativeBins(const std::vector<int>& members, const Eigen::MatrixXd& wJ,
                                          double* cleared_share) const {
  // A sequence's first check is exactly this one: no bin has a value kept.
  double read = 0;
  std::vector<int> out = TableCheckSequence(*this, members).NegativeBins(wJ, &read);
  if (cleared_share) *cleared_share = 1.0 - read;
  return out;
}

TableCheckSequence::TableCheckSequence(const TableCheck& check, std::vector<int> members)
    : check_(check), members_(std::move(members)), known_(static_cast<size_t>(check.subs()), 0) {
  for (int m : members_) BRDFSHOT_CHECK(m >= 0 && m < check.tables().cols(), "TableCheck: member out of range");
}

std::vector<int> TableCheckSequence::NegativeBins(const Eigen::MatrixXd& wJ, double* read_share) {
  const Eigen::Index k = static_cast<Eigen::Index>(members_.size());
  BRDFSHOT_CHECK(wJ.rows() == k && wJ.cols() == 3, "TableCheck: weights are members × 3");
  const TablesMap& tables = check_.tables();
  const Eigen::Index rows = tables.rows(), blocks = check_.blocks(), subs = check_.subs();
  const Eigen::Index sub_rows = check_.sub_rows(), per_block = check_.block_rows() / sub_rows;
  if (!values_) values_.reset(new float[static_cast<size_t>(3 * rows)]);  // left unset: pages only for read blocks
  const bool have_last = last_.size() != 0;
  const Eigen::MatrixXd& w3 = wJ;
  const Eigen::MatrixXd aw3 = w3.cwiseAbs();
  const BinWeights weights(members_, wJ);
  const Eigen::MatrixXd d3 = have_last ? Eigen::MatrixXd(wJ - last_) : Eigen::MatrixXd::Zero(k, 3), ad3 = d3.cwiseAbs();
  std::vector<char> negative(static_cast<size_t>(rows), 0);
  long read = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : read)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index u0 = b * per_block, u1 = std::min(subs, (b + 1) * per_block);
    double bound[3];
    check_.BlockBound(b, members_, w3.data(), aw3.data(), bound);
    const bool block_cleared = AtLeastZero(bound);
    for (Eigen::Index u = u0; u < u1; ++u) {
      if (!block_cleared && check_.two_levels()) check_.SubBound(u, members_, w3.data(), aw3.data(), bound);
      if (block_cleared || AtLeastZero(bound)) {
        known_[static_cast<size_t>(u)] = 0;  // cleared by a bound: no value of its bins kept
        continue;
      }
      double gain[3] = {0, 0, 0};
      const bool known = have_last && known_[static_cast<size_t>(u)];
      if (known) check_.SubBound(u, members_, d3.data(), ad3.data(), gain);
      for (Eigen::Index r = u * sub_rows; r < std::min(rows, (u + 1) * sub_rows); ++r) {
        float* v = &values_[static_cast<size_t>(3 * r)];
        double sum[3];
        if (known) {
          for (int c = 0; c < 3; ++c) sum[c] = static_cast<double>(v[c]) + gain[c];
          if (sum[0] >= 0 && sum[1] >= 0 && sum[2] >= 0) {
            for (int c = 0; c < 3; ++c) v[c] = FloatBelow(sum[c]);  // a lower bound of the value at wJ
            continue;
          }
        }
        negative[static_cast<size_t>(r)] = weights.IsNegative(tables.row(r).data(), sum);
        for (int c = 0; c < 3; ++c) v[c] = FloatBelow(sum[c]);
        ++read;
      }
      known_[static_cast<size_t>(u)] = 1;
    }
  }
  last_ = wJ;
  if (read_share) *read_share = rows ? static_cast<double>(read) / static_cast<double>(rows) : 0.0;
  std::vector<int> out;
  for (Eigen::Index r = 0; r < rows; ++r)
    if (negative[static_cast<size_t>(r)]) out.push_back(static_cast<int>(r));
  return out;
}

std::array<double, 3> MeanBlendToNonNegative(const TablesRef& tables, const std::vector<int>& members,
                                             const Eigen::MatrixXd& wJ, const std::vector<int>& rows) {
  const Eigen::Index k = static_cast<Eigen::Index>(members.size());
  BRDFSHOT_CHECK(k > 0 && wJ.rows() == k && wJ.cols() == 3, "MeanBlendToNonNegative: weights are members × 3");
  // The values as the checks sum them; the mean is the sum at weights 1/k.
  const BinWeights weights(members, wJ), mean_weights(members, Eigen::MatrixXd::Constant(k, 3, 1.0 / k));
  std::array<double, 3> t{};
  for (int r : rows) {
    BRDFSHOT_CHECK(r >= 0 && r < tables.rows(), "MeanBlendToNonNegative: row out of range");
    double value[3], mean[3];
    weights.IsNegative(tables.row(r).data(), value);
    mean_weights.IsNegative(tables.row(r).data(), mean);
    // (1 − t) v + t m ≥ 0 for t ≥ −v / (m − v); m > 0 wherever v < 0, the
    // tables being non-negative.
    for (int c = 0; c < 3; ++c)
      if (value[c] < 0) t[c] = std::max(t[c], mean[c] > value[c] ? -value[c] / (mean[c] - value[c]) : 1.0);
  }
  // A hair more, so that the rounding of the blended sums lands above zero.
  for (double& x : t)
    if (x > 0) x = std::min(1.0, x * (1 + 1e-6) + 1e-12);
  return t;
}

TableCheckSource::TableCheckSource(const TablesRef& tables, const TableCheck* given)
    : tables_(MapOf(tables)), given_(given) {
  BRDFSHOT_CHECK(!given || (given->tables().data() == tables.data() && given->tables().rows() == tables.rows() &&
                            given->tables().cols() == tables.cols()),
                 "TableCheckSource: the summary is of other tables");
}

const TableCheck& TableCheckSource::Summary() {
  if (!summary()) built_ = std::make_unique<TableCheck>(tables_, TableCheck::kDefaultBlockRows, 0);
  return *summary();
}

TableKeep KeepNonNegativeOnTable(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls,
                                 const Observation& obs, double lambda, TableCheckSource* checks, BinRows* bins,
                                 ClassSolution* s, int max_solves) {
  BRDFSHOT_CHECK(checks && bins && s, "KeepNonNegativeOnTable: no checks, bins or solution");
  WeightConstraint constraint;
  constraint.kind = WeightConstraint::Kind::kBins;
  constraint.bins = bins;
  std::unique_ptr<TableCheckSequence> sequence;
  TableKeep keep;
  const double k = static_cast<double>(cls.members.size());
  // A blend lifts every bin it is given to zero or above, and leaves the
  // others within the tolerance; the check after it confirms that, and a
  // further blend covers what rounding could leave.
  constexpr int kMaxBlends = 3;
  for (int n = 0, blends = 0;; ++n) {
    Eigen::MatrixXd wJ = s->weights(cls.members, Eigen::all);
    if (!sequence && (checks->summary() || n > 0))
      sequence = std::make_unique<TableCheckSequence>(checks->Summary(), cls.members);
    const std::vector<int> negative =
        sequence ? sequence->NegativeBins(wJ) : NegativeBins(checks->tables(), cls.members, wJ);
    if (negative.empty()) break;
    if (keep.solves < max_solves) {
      keep.bins_added += static_cast<int>(negative.size());
      bins->Append(checks->tables(), cls.members, negative);
      *s = SolveClass(f, cls, obs, lambda, constraint);
      ++keep.solves;
      continue;
    }
    BRDFSHOT_CHECK(blends < kMaxBlends, "KeepNonNegativeOnTable: " << negative.size()
                                                                   << " bins stay below zero after blending toward "
                                                                      "the class's mean");
    ++blends;
    const std::array<double, 3> t = MeanBlendToNonNegative(checks->tables(), cls.members, wJ, negative);
    for (int c = 0; c < 3; ++c) {
      wJ.col(c) = (1 - t[c]) * wJ.col(c).array() + t[c] / k;
      keep.mean_blend[c] = 1 - (1 - keep.mean_blend[c]) * (1 - t[c]);  // blends compose
    }
    s->weights(cls.members, Eigen::all) = wJ;
    s->residual = ClassResidual(cls, obs, wJ);
  }
  return keep;
}

}  // namespace brdfshot
