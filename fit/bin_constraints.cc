#include "fit/bin_constraints.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fit/nonneg.h"
#include "util/check.h"

namespace brdfshot {

BinRows::BinRows(const MatrixXfR& tables, const std::vector<int>& members, const std::vector<int>& rows) {
  Append(tables, members, rows);
}

BinRows BinRows::EveryNth(const MatrixXfR& tables, const std::vector<int>& members, int stride) {
  BRDFSHOT_CHECK(stride >= 1);
  std::vector<int> rows;
  for (Eigen::Index i = 0; i < tables.rows(); i += stride) rows.push_back(static_cast<int>(i));
  return BinRows(tables, members, rows);
}

BinRows BinRows::AllRows(const MatrixXfR& tables, const std::vector<int>& members) {
  if (10 * members.size() < 9 * static_cast<size_t>(tables.cols())) return EveryNth(tables, members, 1);
  for (int m : members) BRDFSHOT_CHECK(m >= 0 && m < tables.cols(), "BinRows: member out of range");
  BinRows b;
  b.source_ = &tables;
  b.members_ = members;
  return b;
}

void BinRows::Append(const MatrixXfR& tables, const std::vector<int>& members, const std::vector<int>& table_rows) {
  if (source_) *this = EveryNth(*source_, members_, 1);  // the rows read in place become a copy that can grow
  BRDFSHOT_CHECK(a_.size() == 0 || a_.cols() == static_cast<Eigen::Index>(members.size()),
                 "BinRows: appended rows over other members");
  for (int m : members) BRDFSHOT_CHECK(m >= 0 && m < tables.cols(), "BinRows: member out of range");
  const Eigen::Index old = a_.rows(), k = static_cast<Eigen::Index>(members.size());
  a_.conservativeResize(old + static_cast<Eigen::Index>(table_rows.size()), k);
  for (size_t i = 0; i < table_rows.size(); ++i) {
    BRDFSHOT_CHECK(table_rows[i] >= 0 && table_rows[i] < tables.rows(), "BinRows: row out of range");
    const float* row = tables.row(table_rows[i]).data();
    float* out = a_.row(old + static_cast<Eigen::Index>(i)).data();
    for (Eigen::Index j = 0; j < k; ++j) out[j] = row[members[j]];
  }
}

Eigen::MatrixXd BinRows::Times(const Eigen::MatrixXd& w) const {
  BRDFSHOT_CHECK(w.rows() == cols());
  const MatrixXfR& a = source_ ? *source_ : a_;
  // Each column of w contiguous, for the dot products; in place, spread over
  // every column of the source with zeros outside the members.
  MatrixXdR wt;
  if (source_) {
    wt = MatrixXdR::Zero(w.cols(), a.cols());
    for (size_t k = 0; k < members_.size(); ++k) wt.col(members_[k]) = w.row(static_cast<Eigen::Index>(k)).transpose();
  } else {
    wt = w.transpose();
  }
  Eigen::MatrixXd out(rows(), w.cols());
  Eigen::RowVectorXd row(a.cols());
  for (Eigen::Index i = 0; i < rows(); ++i) {
    row = a.row(i).cast<double>();
    for (Eigen::Index j = 0; j < w.cols(); ++j) out(i, j) = row.dot(wt.row(j));
  }
  return out;
}

Eigen::MatrixXd BinRows::Rows(const std::vector<int>& which) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(which.size()), cols());
  for (size_t i = 0; i < which.size(); ++i) {
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    if (source_)
      for (size_t k = 0; k < members_.size(); ++k)
        out(r, static_cast<Eigen::Index>(k)) = (*source_)(which[i], members_[k]);
    else
      out.row(r) = a_.row(which[i]).cast<double>();
  }
  return out;
}

double BinRows::RowSum(Eigen::Index i) const {
  if (!source_) return a_.row(i).cast<double>().sum();
  double sum = 0;
  for (int m : members_) sum += (*source_)(i, m);
  return sum;
}

bool IsNegativeBin(const float* row, const std::vector<int>& members, const double* w3) {
  double value[3] = {0, 0, 0}, magnitude[3] = {0, 0, 0};
  for (size_t k = 0; k < members.size(); ++k) {
    const double v = row[members[k]];
    for (int c = 0; c < 3; ++c) {
      const double term = v * w3[3 * k + static_cast<size_t>(c)];
      value[c] += term, magnitude[c] += std::abs(term);
    }
  }
  for (int c = 0; c < 3; ++c)
    if (value[c] < -kNegativeBinTolerance * magnitude[c]) return true;
  return false;
}

std::vector<int> NegativeBins(const MatrixXfR& tables, const std::vector<int>& members, const Eigen::MatrixXd& wJ) {
  BRDFSHOT_CHECK(wJ.rows() == static_cast<Eigen::Index>(members.size()) && wJ.cols() == 3);
  const MatrixXdR w3 = wJ;  // row-major: member k's three channels side by side
  const Eigen::Index rows = tables.rows();
  std::vector<char> negative(rows, 0);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < rows; ++i) negative[i] = IsNegativeBin(tables.row(i).data(), members, w3.data());
  std::vector<int> out;
  for (Eigen::Index i = 0; i < rows; ++i)
    if (negative[i]) out.push_back(static_cast<int>(i));
  return out;
}

BinConstrainedSolution ConstrainToNonNegativeBins(const std::function<Eigen::MatrixXd()>& inverse,
                                                  const Eigen::VectorXd& w0, const BinRows& A, double tolerance,
                                                  int max_rounds, int bins_per_round, const Eigen::VectorXd* given_v0) {
  const Eigen::Index k = w0.size();
  BRDFSHOT_CHECK(A.cols() == k, "ConstrainToNonNegativeBins: sizes differ");
  BinConstrainedSolution s;
  s.w = w0;
  if (A.rows() == 0 || k == 0) {
    s.complete = true;
    return s;
  }
  const Eigen::VectorXd v0 = given_v0 ? *given_v0 : Eigen::VectorXd(A.Times(w0));
  BRDFSHOT_CHECK(v0.size() == A.rows());
  const double threshold = -tolerance * std::max(v0.maxCoeff(), 1e-300);
  std::vector<char> in(A.rows(), 0);  // the bins with a multiplier so far
  Eigen::VectorXd values = v0;
  Eigen::MatrixXd K;  // from inverse(), at the first round
  // The dual over the bins so far, grown by each round's bins instead of
  // formed again: Q = A_C K A_Cᵀ, its linear term A_C w₀, and the last
  // round's multipliers, from which the next round's solve starts.
  Eigen::MatrixXd Ac(0, k), KAt(k, 0), Q(0, 0);
  Eigen::VectorXd linear(0), mu(0);
  for (s.rounds = 0; s.rounds < max_rounds; ++s.rounds) {
    std::vector<int> negative;
    for (Eigen::Index i = 0; i < values.size(); ++i)
      if (values[i] < threshold && !in[i]) negative.push_back(static_cast<int>(i));
    if (negative.empty()) {
      s.complete = true;  // bins in the set sit at zero up to the dual's rounding
      break;
    }
    const size_t take = std::min<size_t>(negative.size(), static_cast<size_t>(bins_per_round));
    std::partial_sort(negative.begin(), negative.begin() + take, negative.end(),
                      [&](int a, int b) { return values[a] < values[b]; });
    negative.resize(take);
    for (int i : negative) in[i] = 1;
    if (K.size() == 0) {
      K = inverse();
      BRDFSHOT_CHECK(K.rows() == k && K.cols() == k, "ConstrainToNonNegativeBins: the inverse's size differs");
    }
    const Eigen::Index old = Ac.rows(), r = old + static_cast<Eigen::Index>(take);
    const Eigen::MatrixXd new_rows = A.Rows(negative);
    const Eigen::MatrixXd new_KAt = K * new_rows.transpose();
    Ac.conservativeResize(r, Eigen::NoChange);
    Ac.bottomRows(r - old) = new_rows;
    KAt.conservativeResize(Eigen::NoChange, r);
    KAt.rightCols(r - old) = new_KAt;
    Q.conservativeResize(r, r);
    Q.rightCols(r - old) = Ac * new_KAt;
    Q.bottomLeftCorner(r - old, old) = Q.topRightCorner(old, r - old).transpose();
    linear.conservativeResize(r);
    linear.tail(r - old) = -(new_rows * w0);
    mu.conservativeResize(r);
    mu.tail(r - old).setZero();
    mu = SolveNonNegative(Q, linear, 1e-10, 0, &mu).x;
    s.w = w0 + KAt * mu;
    s.active = static_cast<int>((mu.array() > 0).count());
    values = A.Times(s.w);  // one column
  }
  // The active bins sit at zero only up to the dual's rounding (~1e-11 of
  // w₀'s scale), which is a visible "negative" wherever the whole fit is near
  // zero. Tables are non-negative, so adding a multiple of the all-ones
  // weights raises every bin: the smallest multiple that lifts them all is
  // of rounding size and changes the fit by as little.
  double t = 0;
  for (Eigen::Index i = 0; i < values.size(); ++i)
    if (values[i] < 0) {
      const double lift = A.RowSum(i);  // only where a bin is below zero: most fits have none
      if (lift > 0) t = std::max(t, -values[i] / lift);
    }
  if (t > 0 && t * std::sqrt(static_cast<double>(k)) <= 1e-6 * std::max(w0.norm(), 1e-300)) s.w.array() += 2 * t;
  return s;
}

}  // namespace brdfshot
