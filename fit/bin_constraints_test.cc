#include "fit/bin_constraints.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <limits>
#include <random>
#include <vector>

#include "fit/nonneg.h"

namespace brdfshot {
namespace {

// A dense A as the constraint reads it: a float table and all its rows.
struct Table {
  MatrixXfR values;
  BinRows rows;
  explicit Table(const Eigen::MatrixXd& A) : values(A.cast<float>()) {
    std::vector<int> all_columns(static_cast<size_t>(values.cols()));
    for (size_t i = 0; i < all_columns.size(); ++i) all_columns[i] = static_cast<int>(i);
    rows = BinRows::EveryNth(values, all_columns, 1);
  }
  Eigen::MatrixXd dense() const { return values.cast<double>(); }
};

double Objective(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, const Eigen::VectorXd& w) {
  return 0.5 * w.dot(H * w) - b.dot(w);
}

// The optimum by enumeration of active sets: for every subset S of the bins,
// the minimiser with A_S w = 0 (its KKT system solved directly); the best of
// those that keep every bin ≥ 0 is the constrained optimum.
double BruteForceOptimum(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, const Eigen::MatrixXd& A) {
  const int m = static_cast<int>(A.rows()), k = static_cast<int>(H.rows());
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> S;
    for (int i = 0; i < m; ++i)
      if (mask >> i & 1) S.push_back(i);
    const int s = static_cast<int>(S.size());
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(k + s, k + s);
    kkt.topLeftCorner(k, k) = H;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k + s);
    rhs.head(k) = b;
    for (int r = 0; r < s; ++r)
      kkt.block(k + r, 0, 1, k) = A.row(S[r]), kkt.block(0, k + r, k, 1) = A.row(S[r]).transpose();
    const Eigen::VectorXd sol = kkt.completeOrthogonalDecomposition().solve(rhs);
    const Eigen::VectorXd w = sol.head(k);
    if ((kkt * sol - rhs).norm() > 1e-8 * (1 + rhs.norm())) continue;  // inconsistent system
    if ((A * w).minCoeff() < -1e-9) continue;
    best = std::min(best, Objective(H, b, w));
  }
  return best;
}

TEST(ConstrainToNonNegativeBins, LeavesAFeasibleSolutionAlone) {
  const Eigen::MatrixXd H = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd w0 = Eigen::Vector3d(1, 2, 0.5);
  const Table A((Eigen::MatrixXd(2, 3) << 1, 0, 0, 0.5, 0.5, 1).finished());
  bool asked = false;
  const BinConstrainedSolution s = ConstrainToNonNegativeBins(
      [&] {
        asked = true;
        return H;
      },
      w0, A.rows);
  EXPECT_FALSE(asked) << "no bin below zero: the inverse is never needed";
  EXPECT_TRUE(s.complete);
  EXPECT_EQ(s.active, 0);
  EXPECT_EQ(s.w, w0);
}

TEST(ConstrainToNonNegativeBins, MatchesEnumerationOfActiveSets) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  int constrained = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int k = 2 + trial % 4, m = 4 + trial % 5;
    Eigen::MatrixXd X(k + 4, k);
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = g(rng);
    Eigen::MatrixXd H = X.transpose() * X;
    H.diagonal().array() += 0.05;
    Eigen::VectorXd b(k);
    for (int i = 0; i < k; ++i) b[i] = g(rng);
    // Non-negative "tables", as every database's are (float, as they are kept).
    Eigen::MatrixXd random(m, k);
    for (Eigen::Index i = 0; i < random.size(); ++i) random.data()[i] = u(rng);
    const Table table(random);
    const Eigen::MatrixXd A = table.dense();
    const Eigen::MatrixXd K = H.inverse();
    const Eigen::VectorXd w0 = K * b;
    const BinConstrainedSolution s = ConstrainToNonNegativeBins([&] { return K; }, w0, table.rows, 1e-12);
    ASSERT_TRUE(s.complete) << trial;
    EXPECT_GE((A * s.w).minCoeff(), -1e-9 * (A * w0).cwiseAbs().maxCoeff()) << trial;
    const double best = BruteForceOptimum(H, b, A);
    EXPECT_NEAR(Objective(H, b, s.w), best, 1e-8 * (1 + std::abs(best))) << trial;
    constrained += (A * w0).minCoeff() < 0;
  }
  EXPECT_GT(constrained, 10) << "most trials must need the constraint for the test to mean anything";
}

TEST(ConstrainToNonNegativeBins, OppositeBinsPinTheWeightAtZero) {
  // Bins w and −w can only both be ≥ 0 at w = 0, whatever the data want.
  const Eigen::MatrixXd K = Eigen::MatrixXd::Identity(1, 1);
  const Eigen::VectorXd w0 = Eigen::VectorXd::Constant(1, 3.0);
  const Table A((Eigen::MatrixXd(2, 1) << 1, -1).finished());
  const BinConstrainedSolution s = ConstrainToNonNegativeBins([&] { return K; }, w0, A.rows);
  EXPECT_TRUE(s.complete);
  EXPECT_NEAR(s.w[0], 0.0, 1e-12);
}

TEST(ConstrainChannelsToNonNegativeBins, EachChannelIsWhatItsOwnSolveGives) {
  // Three channels with their own K, one feasible from the start and two that
  // take different numbers of rounds (few bins per round): solved together
  // they share each round's product over the bins, and each must come out
  // bit for bit as it does alone, with the cap on rounds too.
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  const int k = 6, m = 300;
  Eigen::MatrixXd random(m, k);
  for (Eigen::Index i = 0; i < random.size(); ++i) random.data()[i] = u(rng);
  const Table table(random);
  std::array<Eigen::MatrixXd, 3> K;
  Eigen::MatrixXd W0(k, 3);
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd X(k + 3, k);
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = g(rng);
    Eigen::MatrixXd H = X.transpose() * X;
    H.diagonal().array() += 0.1;
    K[c] = H.inverse();
    // Channel 0 positive, 1 with one negative weight, 2 with many.
    for (int i = 0; i < k; ++i) W0(i, c) = c == 2 ? 3 * g(rng) : 1.0 + u(rng);
    if (c == 1) W0(0, c) = -1.5;
  }
  for (const int cap : {30, 2}) {
    const std::vector<BinConstrainedSolution> together =
        ConstrainChannelsToNonNegativeBins([&](int c) { return K[c]; }, W0, table.rows, 1e-12, cap, 3);
    ASSERT_EQ(together.size(), 3u);
    std::vector<int> rounds;
    for (int c = 0; c < 3; ++c) {
      const BinConstrainedSolution alone =
          ConstrainToNonNegativeBins([&] { return K[c]; }, W0.col(c), table.rows, 1e-12, cap, 3);
      EXPECT_EQ(together[c].rounds, alone.rounds) << c;
      EXPECT_EQ(together[c].active, alone.active) << c;
      EXPECT_EQ(together[c].complete, alone.complete) << c;
      for (int i = 0; i < k; ++i) EXPECT_EQ(together[c].w[i], alone.w[i]) << c << " " << i;
      rounds.push_back(alone.rounds);
    }
    EXPECT_EQ(rounds[0], 0) << "the first channel is feasible as it is";
    EXPECT_NE(rounds[1], rounds[2])
        << "the channels must take different numbers of rounds for the test to mean anything";
    if (cap == 2) EXPECT_FALSE(together[1].complete && together[2].complete) << "the cap must stop a channel";
  }
}

TEST(ConstrainToNonNegativeBins, ManyRoundsOfFewBinsReachTheDualOfEveryBin) {
  // Two bins a round over 2000 bins: many rounds, bins leaving the dual and
  // coming back, and most of each round's products skipped by their bound.
  // The optimum is the one dual over every bin at once gives.
  std::mt19937 rng(17);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  const int k = 12, m = 2000;
  // Each bin mostly two bases (a faint floor of the others), so the bins
  // below zero are many and unlike: fixing two leaves the rest negative.
  std::uniform_int_distribution<int> pick(0, k - 1);
  Eigen::MatrixXd random = Eigen::MatrixXd::Constant(m, k, 1e-3);
  for (int i = 0; i < m; ++i) random(i, pick(rng)) += u(rng), random(i, pick(rng)) += u(rng);
  const Table table(random);
  const Eigen::MatrixXd A = table.dense();
  Eigen::MatrixXd X(k + 5, k);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = g(rng);
  Eigen::MatrixXd H = X.transpose() * X;
  H.diagonal().array() += 0.05;
  const Eigen::MatrixXd K = H.inverse();
  Eigen::VectorXd w0(k);
  for (int i = 0; i < k; ++i) w0[i] = 1 + g(rng);
  w0[0] = -2, w0[1] = -1, w0[2] = -0.5, w0[3] = -1.5;
  ASSERT_LT((A * w0).minCoeff(), 0) << "the start must go negative";
  const BinConstrainedSolution s = ConstrainToNonNegativeBins([&] { return K; }, w0, table.rows, 1e-12, 1000, 2);
  ASSERT_TRUE(s.complete);
  EXPECT_GT(s.rounds, 5) << "the test needs many rounds to mean anything";
  const Eigen::VectorXd mu = SolveNonNegative(A * K * A.transpose(), -(A * w0), 1e-14).x;
  const Eigen::VectorXd w = w0 + K * A.transpose() * mu;
  const Eigen::VectorXd b = H * w0;
  EXPECT_NEAR(Objective(H, b, s.w), Objective(H, b, w), 1e-9 * std::abs(Objective(H, b, w)));
  EXPECT_LT((s.w - w).norm(), 1e-6 * w.norm());
  EXPECT_GE((A * s.w).minCoeff(), -1e-9 * (A * w0).cwiseAbs().maxCoeff());
}

TEST(BinRows, RowNormsBoundEveryRowsProductAndTimesRowsIsTimesAtThoseRows) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  MatrixXfR tables(30, 10);
  for (Eigen::Index i = 0; i < tables.size(); ++i) tables.data()[i] = u(rng);
  for (const std::vector<int>& members : {std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8}, std::vector<int>{1, 4, 6}}) {
    BinRows A = BinRows::AllRows(tables, members);
    A.Append(tables, members, {3});  // a copy, with one more row
    for (const bool in_place : {true, false}) {
      const BinRows& B = in_place ? BinRows::AllRows(tables, members) : A;
      const Eigen::MatrixXd dense = B.Rows([&] {
        std::vector<int> all(static_cast<size_t>(B.rows()));
        for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
        return all;
      }());
      Eigen::MatrixXd d = Eigen::MatrixXd::Random(static_cast<Eigen::Index>(members.size()), 2);
      const Eigen::MatrixXd Ad = dense * d;
      ASSERT_EQ(B.RowNorms().size(), B.rows());
      for (Eigen::Index i = 0; i < B.rows(); ++i) {
        EXPECT_GE(B.RowNorms()[i], dense.row(i).norm() * (1 - 1e-6));
        for (int c = 0; c < 2; ++c) EXPECT_LE(std::abs(Ad(i, c)), B.RowNorms()[i] * d.col(c).norm() * (1 + 1e-6));
      }
      const std::vector<int> which = {B.rows() - 1, 0, 7, 7};
      const Eigen::MatrixXd all = B.Times(d), some = B.TimesRows(d, which);
      for (size_t r = 0; r < which.size(); ++r)
        EXPECT_EQ(some.row(static_cast<Eigen::Index>(r)), all.row(which[r])) << r;
    }
  }
}

TEST(BinRows, ReadsEveryStrideThRowOfTheMembersInPlace) {
  MatrixXfR tables(5, 3);
  // clang-format off
  tables << 0, 1, 2,
            3, 4, 5,
            6, 7, 8,
            9, 10, 11,
            12, 13, 14;
  // clang-format on
  BinRows A = BinRows::EveryNth(tables, {2, 0}, 2);
  ASSERT_EQ(A.rows(), 3);
  ASSERT_EQ(A.cols(), 2);
  EXPECT_EQ(A.Rows({0, 1, 2}), (Eigen::MatrixXd(3, 2) << 2, 0, 8, 6, 14, 12).finished());
  EXPECT_EQ(A.Times(Eigen::Vector2d(1, -1)), Eigen::MatrixXd(Eigen::Vector3d(2, 2, 2)));
  EXPECT_EQ(A.Times((Eigen::MatrixXd(2, 2) << 1, 0, -1, 1).finished()),
            (Eigen::MatrixXd(3, 2) << 2, 0, 2, 6, 2, 12).finished());
  EXPECT_EQ(A.RowSum(2), 26.0);
  A.Append(tables, {2, 0}, {3});
  EXPECT_EQ(A.Rows({3}), (Eigen::MatrixXd(1, 2) << 11, 9).finished());
}

// A class of nearly every column is read in place, in the members' order; its
// products, rows and sums are those of the table's columns themselves, and
// rows appended to it make it a copy holding the same rows and the new ones.
TEST(BinRows, AClassOfNearlyEveryColumnIsReadInPlace) {
  std::mt19937 rng(5);
  std::normal_distribution<float> n01;
  MatrixXfR tables(40, 20);
  for (Eigen::Index i = 0; i < tables.size(); ++i) tables.data()[i] = n01(rng);
  std::vector<int> members;
  for (int j = 19; j >= 0; --j)
    if (j != 7 && j != 3) members.push_back(j);  // 18 of 20, out of order
  BinRows A = BinRows::AllRows(tables, members);
  EXPECT_TRUE(A.in_place());
  ASSERT_EQ(A.rows(), 40);
  ASSERT_EQ(A.cols(), 18);
  const Eigen::MatrixXd dense = tables.cast<double>()(Eigen::all, members);
  Eigen::MatrixXd w(18, 3);
  for (Eigen::Index i = 0; i < w.size(); ++i) w.data()[i] = n01(rng);
  EXPECT_LT((A.Times(w) - dense * w).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(A.Rows({4, 0, 39}), dense(std::vector<int>{4, 0, 39}, Eigen::all));
  EXPECT_NEAR(A.RowSum(11), dense.row(11).sum(), 1e-12);
  A.Append(tables, members, {6, 6});
  EXPECT_FALSE(A.in_place());
  ASSERT_EQ(A.rows(), 42);
  EXPECT_EQ(A.Rows({40, 41, 2}), dense(std::vector<int>{6, 6, 2}, Eigen::all));

  // Half the columns: copied.
  const BinRows half = BinRows::AllRows(tables, {0, 2, 4, 6, 8, 10, 12, 14, 16, 18});
  EXPECT_FALSE(half.in_place());
  EXPECT_EQ(half.rows(), 40);
  EXPECT_EQ(half.Rows({5}),
            tables.cast<double>()(std::vector<int>{5}, std::vector<int>{0, 2, 4, 6, 8, 10, 12, 14, 16, 18}));
}

}  // namespace
}  // namespace brdfshot
