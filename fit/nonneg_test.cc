#include "fit/nonneg.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>
#include <random>
#include <vector>

namespace brdfshot {
namespace {

double Objective(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  return 0.5 * x.dot(H * x) - b.dot(x);
}

// The optimum by enumeration: the minimiser lies on some face {x_i = 0, i ∉ P}
// where it solves H_PP x_P = b_P with x_P > 0.
double BruteForceOptimum(const Eigen::MatrixXd& H, const Eigen::VectorXd& b) {
  const int n = static_cast<int>(b.size());
  double best = 0;  // x = 0
  for (int mask = 1; mask < (1 << n); ++mask) {
    std::vector<int> P;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1) P.push_back(i);
    const Eigen::VectorXd xp = H(P, P).llt().solve(b(P));
    if (xp.minCoeff() <= 0) continue;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    x(P) = xp;
    best = std::min(best, Objective(H, b, x));
  }
  return best;
}

void ExpectKkt(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, const Eigen::VectorXd& x, double tol) {
  const Eigen::VectorXd g = H * x - b;
  const double scale = b.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    EXPECT_GE(x[i], 0.0) << i;
    if (x[i] > 0)
      EXPECT_NEAR(g[i], 0.0, tol * scale) << i;
    else
      EXPECT_GE(g[i], -tol * scale) << i;
  }
}

TEST(SolveNonNegative, EqualsTheUnconstrainedSolutionWhenThatIsPositive) {
  Eigen::MatrixXd A(12, 5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.2, 1.0);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = u(rng);
  const Eigen::MatrixXd H = A.transpose() * A;
  const Eigen::VectorXd truth = (Eigen::VectorXd(5) << 0.5, 1.0, 2.0, 0.1, 0.3).finished();
  const Eigen::VectorXd b = H * truth;
  const NonNegativeResult r = SolveNonNegative(H, b);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.x - truth).norm(), 1e-9 * truth.norm());
}

TEST(SolveNonNegative, MatchesEnumerationOfEveryActiveSet) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 6;
    Eigen::MatrixXd A(n + 3, n);
    for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = g(rng);
    Eigen::MatrixXd H = A.transpose() * A;
    H.diagonal().array() += 0.01 * (trial % 3);  // with and without a ridge
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = g(rng);
    const NonNegativeResult r = SolveNonNegative(H, b);
    ASSERT_TRUE(r.converged) << trial;
    ExpectKkt(H, b, r.x, 1e-8);
    const double best = BruteForceOptimum(H, b);
    EXPECT_NEAR(Objective(H, b, r.x), best, 1e-9 * (1 + std::abs(best))) << trial;
  }
}

TEST(SolveNonNegative, ResumingFromASubproblemsSolutionReachesTheSameOptimum) {
  // As the bin constraint grows its dual: the solution over the first m
  // variables, padded with zeros, is where the solve of all n resumes.
  std::mt19937 rng(17);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 4 + trial % 5, m = 2 + trial % 3;
    Eigen::MatrixXd A(n + 2, n);
    for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = g(rng);
    const Eigen::MatrixXd H = A.transpose() * A;
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = g(rng);
    const NonNegativeResult sub = SolveNonNegative(H.topLeftCorner(m, m), b.head(m));
    Eigen::VectorXd start = Eigen::VectorXd::Zero(n);
    start.head(m) = sub.x;
    const NonNegativeResult r = SolveNonNegative(H, b, 1e-10, 0, &start);
    ASSERT_TRUE(r.converged) << trial;
    ExpectKkt(H, b, r.x, 1e-8);
    const double best = BruteForceOptimum(H, b);
    EXPECT_NEAR(Objective(H, b, r.x), best, 1e-9 * (1 + std::abs(best))) << trial;
  }
  const Eigen::VectorXd wrong_size = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(SolveNonNegative(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(2), 1e-10, 0, &wrong_size),
               std::exception);
}

TEST(SolveNonNegative, SingularSystemReachesTheOptimumOfItsDistinctColumns) {
  // Column 3 duplicates column 1: H is singular, its minimisers form a line,
  // and the optimum value is that of the problem without the duplicate.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  Eigen::MatrixXd A(9, 4);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = g(rng);
  A.col(3) = A.col(1);
  Eigen::VectorXd y(9);
  for (int i = 0; i < 9; ++i) y[i] = g(rng) + 2 * A(i, 1);
  const Eigen::MatrixXd H = A.transpose() * A;
  const Eigen::VectorXd b = A.transpose() * y;
  const NonNegativeResult r = SolveNonNegative(H, b);
  EXPECT_TRUE(r.converged);
  EXPECT_GE(r.x.minCoeff(), 0.0);
  const std::vector<int> distinct = {0, 1, 2};
  const double reduced = BruteForceOptimum(H(distinct, distinct), b(distinct));
  EXPECT_NEAR(Objective(H, b, r.x), reduced, 1e-9 * std::abs(reduced));
}

TEST(SolveNonNegative, AllGradientsPointOutwardGivesZero) {
  const Eigen::MatrixXd H = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd b = -Eigen::VectorXd::Ones(3);
  const NonNegativeResult r = SolveNonNegative(H, b);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.x, Eigen::VectorXd::Zero(3));
}

TEST(SolveNonNegative, RefusesMismatchedSizes) {
  EXPECT_ANY_THROW(SolveNonNegative(Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Ones(2)));
  EXPECT_ANY_THROW(SolveNonNegative(Eigen::MatrixXd::Zero(3, 2), Eigen::VectorXd::Ones(3)));
}

}  // namespace
}  // namespace brdfshot
