#include "fit/bin_constraints.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fit/nonneg.h"
#include "util/check.h"

namespace brdfshot {

BinRows::BinRows(const TablesRef& tables, const std::vector<int>& members, const std::vector<int>& rows) {
  Append(tables, members, rows);
}

BinRows BinRows::EveryNth(const TablesRef& tables, const std::vector<int>& members, int stride) {
  BRDFSHOT_CHECK(stride >= 1);
  std::vector<int> rows;
  for (Eigen::Index i = 0; i < tables.rows(); i += stride) rows.push_back(static_cast<int>(i));
  return BinRows(tables, members, rows);
}

BinRows BinRows::AllRows(const TablesRef& tables, const std::vector<int>& members) {
  if (10 * members.size() < 9 * static_cast<size_t>(tables.cols())) return EveryNth(tables, members, 1);
  for (int m : members) BRDFSHOT_CHECK(m >= 0 && m < tables.cols(), "BinRows: member out of range");
  BinRows b;
  b.source_ = tables.data();
  b.source_rows_ = tables.rows(), b.source_cols_ = tables.cols(), b.source_stride_ = tables.outerStride();
  b.members_ = members;
  b.AddRowNorms(0);
  return b;
}

void BinRows::AddRowNorms(Eigen::Index from) {
  const TablesRef a = in_place() ? TablesRef(Source()) : TablesRef(a_);
  norms_.conservativeResize(a.rows());
  for (Eigen::Index i = from; i < a.rows(); ++i) norms_[i] = a.row(i).cast<double>().norm();
}

void BinRows::Append(const TablesRef& tables, const std::vector<int>& members, const std::vector<int>& table_rows) {
  if (in_place()) *this = EveryNth(Source(), members_, 1);  // the rows read in place become a copy that can grow
  BRDFSHOT_CHECK(a_.size() == 0 || a_.cols() == static_cast<Eigen::Index>(members.size()),
                 "BinRows: appended rows over other members");
  for (int m : members) BRDFSHOT_CHECK(m >= 0 && m < tables.cols(), "BinRows: member out of range");
  const Eigen::Index old = a_.rows(), k = static_cast<Eigen::Index>(members.size());
  a_.conservativeResize(old + static_cast<Eigen::Index>(table_rows.size()), k);
  for (int r : table_rows) BRDFSHOT_CHECK(r >= 0 && r < tables.rows(), "BinRows: row out of range");
  // The rows over the threads: the sampled rows lie far apart in the tables,
  // and each thread's gathers wait on memory.
  const Eigen::Index count = static_cast<Eigen::Index>(table_rows.size());
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < count; ++i) {
    const float* row = tables.row(table_rows[static_cast<size_t>(i)]).data();
    float* out = a_.row(old + i).data();
    for (Eigen::Index j = 0; j < k; ++j) out[j] = row[members[j]];
  }
  AddRowNorms(old);
}

Eigen::MatrixXd BinRows::Times(const Eigen::MatrixXd& w) const {
  std::vector<int> every(static_cast<size_t>(rows()));
  for (size_t i = 0; i < every.size(); ++i) every[i] = static_cast<int>(i);
  return TimesRows(w, every);
}

Eigen::MatrixXd BinRows::TimesRows(const Eigen::MatrixXd& w, const std::vector<int>& which) const {
  BRDFSHOT_CHECK(w.rows() == cols());
  const TablesRef a = in_place() ? TablesRef(Source()) : TablesRef(a_);
  // Each column of w contiguous, for the dot products; in place, spread over
  // every column of the source with zeros outside the members.
  MatrixXdR wt;
  if (in_place()) {
    wt = MatrixXdR::Zero(w.cols(), a.cols());
    for (size_t k = 0; k < members_.size(); ++k) wt.col(members_[k]) = w.row(static_cast<Eigen::Index>(k)).transpose();
  } else {
    wt = w.transpose();
  }
  for (int r : which) BRDFSHOT_CHECK(r >= 0 && r < rows(), "BinRows: row out of range");
  const Eigen::Index count = static_cast<Eigen::Index>(which.size());
  Eigen::MatrixXd out(count, w.cols());
  // The rows over the threads: one thread's reads of the float rows wait on
  // memory, most of the time a solve keeps its bins non-negative.
#pragma omp parallel
  {
    Eigen::RowVectorXd row(a.cols());
#pragma omp for schedule(static)
    for (Eigen::Index r = 0; r < count; ++r) {
      row = a.row(which[static_cast<size_t>(r)]).cast<double>();
      for (Eigen::Index j = 0; j < w.cols(); ++j) out(r, j) = row.dot(wt.row(j));
    }
  }
  return out;
}

Eigen::MatrixXd BinRows::Rows(const std::vector<int>& which) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(which.size()), cols());
  for (size_t i = 0; i < which.size(); ++i) {
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    if (in_place())
      for (size_t k = 0; k < members_.size(); ++k) out(r, static_cast<Eigen::Index>(k)) = Source()(which[i], members_[k]);
    else
      out.row(r) = a_.row(which[i]).cast<double>();
  }
  return out;
}

double BinRows::RowSum(Eigen::Index i) const {
  if (!in_place()) return a_.row(i).cast<double>().sum();
  const TablesMap source = Source();
  double sum = 0;
  for (int m : members_) sum += source(i, m);
  return sum;
}

BinWeights::BinWeights(const std::vector<int>& members, const Eigen::MatrixXd& wJ) : members_(members) {
  BRDFSHOT_CHECK(wJ.rows() == static_cast<Eigen::Index>(members.size()) && wJ.cols() == 3,
                 "BinWeights: weights are members × 3");
  for (int c = 0; c < 3; ++c) w_[c].assign(wJ.col(c).data(), wJ.col(c).data() + wJ.rows());
}

bool BinWeights::IsNegative(const float* row, double value[3]) const {
  // Four partial sums per channel, one per member of each group of four,
  // are independent chains the compiler keeps in vector registers. The sum
  // of the terms' magnitudes (the tolerance's scale) is needed only where a
  // channel's value is below zero, which few bins are: a second loop.
  constexpr int kLanes = 4;
  const size_t k = members_.size();
  const int* m = members_.data();
  const auto sum = [&](bool magnitudes, double out[3]) {
    double acc[3][kLanes] = {};
    size_t i = 0;
    for (; i + kLanes <= k; i += kLanes) {
      double v[kLanes];
      for (int l = 0; l < kLanes; ++l) v[l] = row[m[i + static_cast<size_t>(l)]];
      for (int c = 0; c < 3; ++c) {
        const double* w = w_[c].data() + i;
        for (int l = 0; l < kLanes; ++l) acc[c][l] += magnitudes ? std::abs(v[l] * w[l]) : v[l] * w[l];
      }
    }
    for (; i < k; ++i) {
      const double v = row[m[i]];
      for (int c = 0; c < 3; ++c) acc[c][0] += magnitudes ? std::abs(v * w_[c][i]) : v * w_[c][i];
    }
    for (int c = 0; c < 3; ++c) out[c] = (acc[c][0] + acc[c][1]) + (acc[c][2] + acc[c][3]);
  };
  double s[3];
  sum(false, s);
  if (value) std::copy_n(s, 3, value);
  if (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) return false;
  double a[3];
  sum(true, a);
  for (int c = 0; c < 3; ++c)
    if (s[c] < -kNegativeBinTolerance * a[c]) return true;
  return false;
}

std::vector<int> NegativeBins(const TablesRef& tables, const std::vector<int>& members, const Eigen::MatrixXd& wJ) {
  const BinWeights weights(members, wJ);
  const Eigen::Index rows = tables.rows();
  std::vector<char> negative(rows, 0);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < rows; ++i) negative[i] = weights.IsNegative(tables.row(i).data());
  std::vector<int> out;
  for (Eigen::Index i = 0; i < rows; ++i)
    if (negative[i]) out.push_back(static_cast<int>(i));
  return out;
}

namespace {
// One channel's cutting-plane state: the dual over its bins, grown by each
// round's bins and shrunk by the bins left without a multiplier instead of
// formed again (Q = A_C K A_Cᵀ, its linear term A_C w₀, and the last round's
// multipliers, from which the next round's solve starts).
struct ChannelRounds {
  Eigen::VectorXd w0, values;  // values: A w at w_values, or a lower bound of it that is at least zero
  Eigen::VectorXd w_values;
  double threshold = 0;
  std::vector<char> in;         // the bins in the dual
  std::vector<int> bins;        // the dual's bins, in its order
  Eigen::MatrixXd K;            // from inverse(), at the first round
  Eigen::MatrixXd AcT, KAt, Q;  // AcT: the bins' rows as columns (k × r), so that they grow without a copy
  Eigen::VectorXd linear, mu;
  BinConstrainedSolution s;
};

// Bins whose multiplier is zero leave the dual before a round adds its own:
// w is still optimal without them (its KKT conditions hold), and every
// round's bins, each below zero at w, raise the dual's optimum, so no set of
// bins recurs and the rounds still end. The dual then stays near the size of
// the active set (tens of bins) instead of growing by a round's bins each
// time (hundreds), which is most of a large class's cost. A dropped bin that
// falls below zero again comes back like any other.
void DropInactiveBins(ChannelRounds& ch) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < ch.mu.size(); ++i) {
    if (ch.mu[i] > 0)
      keep.push_back(i);
    else
      ch.in[static_cast<size_t>(ch.bins[static_cast<size_t>(i)])] = 0;
  }
  if (keep.size() == static_cast<size_t>(ch.mu.size())) return;
  ch.AcT = Eigen::MatrixXd(ch.AcT(Eigen::all, keep));
  ch.KAt = Eigen::MatrixXd(ch.KAt(Eigen::all, keep));
  ch.Q = Eigen::MatrixXd(ch.Q(keep, keep));
  ch.linear = Eigen::VectorXd(ch.linear(keep));
  ch.mu = Eigen::VectorXd(ch.mu(keep));
  std::vector<int> bins;
  for (Eigen::Index i : keep) bins.push_back(ch.bins[static_cast<size_t>(i)]);
  ch.bins = std::move(bins);
}

// One round of one channel: drops the bins without a multiplier, adds the
// bins below zero that are not in the dual and solves it again. False when
// there are none (the channel is complete).
bool AddBinsAndSolve(ChannelRounds& ch, const std::function<Eigen::MatrixXd()>& inverse, const BinRows& A,
                     int bins_per_round) {
  const Eigen::Index k = ch.w0.size();
  DropInactiveBins(ch);
  std::vector<int> negative;
  for (Eigen::Index i = 0; i < ch.values.size(); ++i)
    if (ch.values[i] < ch.threshold && !ch.in[i]) negative.push_back(static_cast<int>(i));
  if (negative.empty()) return false;
  const size_t take = std::min<size_t>(negative.size(), static_cast<size_t>(bins_per_round));
  std::partial_sort(negative.begin(), negative.begin() + take, negative.end(),
                    [&](int a, int b) { return ch.values[a] < ch.values[b]; });
  negative.resize(take);
  for (int i : negative) ch.in[i] = 1;
  ch.bins.insert(ch.bins.end(), negative.begin(), negative.end());
  if (ch.K.size() == 0) {
    ch.K = inverse();
    BRDFSHOT_CHECK(ch.K.rows() == k && ch.K.cols() == k, "ConstrainToNonNegativeBins: the inverse's size differs");
  }
  const Eigen::Index old = ch.AcT.cols(), r = old + static_cast<Eigen::Index>(take);
  const Eigen::MatrixXd new_rows = A.Rows(negative);
  const Eigen::MatrixXd new_KAt = ch.K * new_rows.transpose();
  ch.AcT.conservativeResize(Eigen::NoChange, r);
  ch.AcT.rightCols(r - old) = new_rows.transpose();
  ch.KAt.conservativeResize(Eigen::NoChange, r);
  ch.KAt.rightCols(r - old) = new_KAt;
  ch.Q.conservativeResize(r, r);
  ch.Q.rightCols(r - old).noalias() = ch.AcT.transpose() * new_KAt;
  ch.Q.bottomLeftCorner(r - old, old) = ch.Q.topRightCorner(old, r - old).transpose();
  ch.linear.conservativeResize(r);
  ch.linear.tail(r - old) = -(new_rows * ch.w0);
  ch.mu.conservativeResize(r);
  ch.mu.tail(r - old).setZero();
  ch.mu = SolveNonNegative(ch.Q, ch.linear, 1e-10, 0, &ch.mu).x;
  ch.s.w = ch.w0 + ch.KAt * ch.mu;
  ch.s.active = static_cast<int>((ch.mu.array() > 0).count());
  return true;
}

// The active bins sit at zero only up to the dual's rounding (~1e-11 of w₀'s
// scale), which is a visible "negative" wherever the whole fit is near zero.
// Tables are non-negative, so adding a multiple of the all-ones weights
// raises every bin: the smallest multiple that lifts them all is of rounding
// size and changes the fit by as little.
void LiftRoundingNegatives(ChannelRounds& ch, const BinRows& A) {
  const Eigen::Index k = ch.w0.size();
  double t = 0;
  for (Eigen::Index i = 0; i < ch.values.size(); ++i)
    if (ch.values[i] < 0) {
      const double lift = A.RowSum(i);  // only where a bin is below zero: most fits have none
      if (lift > 0) t = std::max(t, -ch.values[i] / lift);
    }
  if (t > 0 && t * std::sqrt(static_cast<double>(k)) <= 1e-6 * std::max(ch.w0.norm(), 1e-300)) ch.s.w.array() += 2 * t;
}
}  // namespace

std::vector<BinConstrainedSolution> ConstrainChannelsToNonNegativeBins(
    const std::function<Eigen::MatrixXd(int)>& inverse, const Eigen::MatrixXd& W0, const BinRows& A, double tolerance,
    int max_rounds, int bins_per_round, const Eigen::MatrixXd* given_V0) {
  const Eigen::Index k = W0.rows(), channels = W0.cols();
  BRDFSHOT_CHECK(A.cols() == k, "ConstrainToNonNegativeBins: sizes differ");
  std::vector<ChannelRounds> ch(static_cast<size_t>(channels));
  for (Eigen::Index c = 0; c < channels; ++c) ch[c].s.w = ch[c].w0 = W0.col(c);
  if (A.rows() == 0 || k == 0) {
    std::vector<BinConstrainedSolution> out;
    for (ChannelRounds& x : ch) x.s.complete = true, out.push_back(x.s);
    return out;
  }
  const Eigen::MatrixXd V0 = given_V0 ? *given_V0 : A.Times(W0);
  BRDFSHOT_CHECK(V0.rows() == A.rows() && V0.cols() == channels);
  for (Eigen::Index c = 0; c < channels; ++c) {
    ChannelRounds& x = ch[c];
    x.values = V0.col(c);
    x.w_values = x.w0;
    x.threshold = -tolerance * std::max(x.values.maxCoeff(), 1e-300);
    x.in.assign(static_cast<size_t>(A.rows()), 0);
    x.AcT.resize(k, 0), x.KAt.resize(k, 0), x.Q.resize(0, 0), x.linear.resize(0), x.mu.resize(0);
  }
  // Each channel runs its own rounds; the channels still going share each
  // round's product over the bins, which streams the rows of A it reads and is
  // most of a round's cost.
  for (;;) {
    std::vector<Eigen::Index> going;
    for (Eigen::Index c = 0; c < channels; ++c) {
      ChannelRounds& x = ch[c];
      if (x.s.complete || x.s.rounds >= max_rounds) continue;  // done, or at the cap (incomplete)
      if (!AddBinsAndSolve(
              x, [&] { return inverse(static_cast<int>(c)); }, A, bins_per_round)) {
        x.s.complete = true;  // bins in the set sit at zero up to the dual's rounding
        continue;
      }
      ++x.s.rounds;
      going.push_back(c);
    }
    if (going.empty()) break;
    // Each going channel's step since its values were computed; a bin whose
    // value, less norm × step, stays at or above zero can not have crossed
    // zero (Cauchy–Schwarz) and keeps that lower bound; only the others are
    // computed again, and a round reads only their rows of A.
    Eigen::MatrixXd W(k, static_cast<Eigen::Index>(going.size()));
    std::vector<double> step(going.size());
    for (size_t j = 0; j < going.size(); ++j) {
      ChannelRounds& x = ch[going[j]];
      W.col(static_cast<Eigen::Index>(j)) = x.s.w;
      // Rounding of the products below stays far inside this margin.
      step[j] = (x.s.w - x.w_values).norm() * (1 + 1e-9);
      x.w_values = x.s.w;
    }
    const Eigen::VectorXd& norms = A.RowNorms();
    std::vector<int> near;
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      bool is_near = false;
      for (size_t j = 0; j < going.size() && !is_near; ++j) is_near = ch[going[j]].values[i] < norms[i] * step[j];
      if (is_near)
        near.push_back(static_cast<int>(i));
      else
        for (size_t j = 0; j < going.size(); ++j) ch[going[j]].values[i] -= norms[i] * step[j];
    }
    const Eigen::MatrixXd values = A.TimesRows(W, near);
    for (size_t j = 0; j < going.size(); ++j)
      for (size_t r = 0; r < near.size(); ++r)
        ch[going[j]].values[near[r]] = values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j));
  }
  std::vector<BinConstrainedSolution> out;
  for (ChannelRounds& x : ch) {
    LiftRoundingNegatives(x, A);
    out.push_back(x.s);
  }
  return out;
}

BinConstrainedSolution ConstrainToNonNegativeBins(const std::function<Eigen::MatrixXd()>& inverse,
                                                  const Eigen::VectorXd& w0, const BinRows& A, double tolerance,
                                                  int max_rounds, int bins_per_round, const Eigen::VectorXd* given_v0) {
  const Eigen::MatrixXd V0 = given_v0 ? Eigen::MatrixXd(*given_v0) : Eigen::MatrixXd();
  return ConstrainChannelsToNonNegativeBins([&](int) { return inverse(); }, w0, A, tolerance, max_rounds,
                                            bins_per_round, given_v0 ? &V0 : nullptr)[0];
}

}  // namespace brdfshot
