#include "fit/table_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>


namespace brdfshot {
namespace {

// A table shaped like a BRDF database's: every column smooth along the rows
// (a slow ramp) with a narrow peak of its own height (a highlight), all
// values ≥ 0.
MatrixXfR SmoothTable(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  MatrixXfR t(rows, cols);
  for (int i = 0; i < cols; ++i) {
    const double base = 0.05 + u(rng), slope = u(rng), centre = u(rng) * rows, width = 1 + 6 * u(rng),
                 height = 20 * u(rng);
    for (int r = 0; r < rows; ++r) {
      const double x = static_cast<double>(r) / rows, d = (r - centre) / width;
      t(r, i) = static_cast<float>(base * (1 + slope * std::sin(6 * x)) + height * std::exp(-d * d));
    }
  }
  return t;
}

std::vector<int> Members(int cols, int step) {
  std::vector<int> m;
  for (int i = 0; i < cols; i += step) m.push_back(i);
  return m;
}

}  // namespace

TEST(TableCheck, FindsExactlyTheBinsTheWholeTableCheckFinds) {
  // Weights from all positive to both signs (negative at a few bins, then
  // at many), and blocks that do and do not divide the rows: the bound may
  // only spare bins, never change the answer.
  MatrixXfR t = SmoothTable(1003, 40, 3);
  t.middleRows(500, 70).setZero();  // bins no material was measured at, across block edges
  const std::vector<int> members = Members(40, 2);  // 20 of the 40 columns, not in a block
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 1);
  int cases_with_negatives = 0, cases_without = 0;
  // Blocks with and without sub-blocks (0: one level).
  for (const auto [block, sub] : std::vector<std::pair<int, int>>{{1, 0}, {7, 0}, {32, 0}, {32, 8}, {1003, 0}, {2000, 0}, {2000, 16}}) {
    const TableCheck check(t, block, sub);
    EXPECT_EQ(check.blocks(), (1003 + block - 1) / block);
    EXPECT_EQ(check.subs(), sub ? (1003 + sub - 1) / sub : check.blocks());
    for (int trial = 0; trial < 30; ++trial) {
      Eigen::MatrixXd w(static_cast<Eigen::Index>(members.size()), 3);
      const double spread = 0.1 * trial;  // from all weights near 1/k to weights of both signs
      for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = (1 + spread * g(rng)) / static_cast<double>(members.size());
      const std::vector<int> expected = NegativeBins(t, members, w);
      double cleared = -1;
      EXPECT_EQ(check.NegativeBins(members, w, &cleared), expected) << "block " << block << "/" << sub << ", trial " << trial;
      EXPECT_GE(cleared, 0.0);
      EXPECT_LE(cleared, 1.0);
      (expected.empty() ? cases_without : cases_with_negatives)++;
    }
  }
  EXPECT_GT(cases_with_negatives, 20);
  EXPECT_GT(cases_without, 5);
}

TEST(TableCheck, ASequenceOfNearbyWeightsFindsWhatEachCheckAloneFinds) {
  // A fit solved again moves its weights a little; a fit of another
  // material moves them far. Either way the sequence must return the bins
  // of a fresh check, and reading few bins is only allowed where the change
  // is small.
  MatrixXfR t = SmoothTable(1003, 40, 5);
  t.middleRows(130, 40).setZero();  // not measured
  const std::vector<int> members = Members(40, 1);
  std::mt19937 rng(6);
  std::normal_distribution<double> g(0, 1);
  for (const auto [block, sub] : std::vector<std::pair<int, int>>{{32, 0}, {32, 8}, {128, 16}}) {
    const TableCheck check(t, block, sub);
    TableCheckSequence sequence(check, members);
    Eigen::MatrixXd w(40, 3);
    int with_negatives = 0;
    for (int step = 0; step < 24; ++step) {
      if (step % 6 == 0)  // another fit: weights of both signs
        for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = (1 + 1.5 * g(rng)) / 40.0;
      else  // the same fit, nudged
        for (Eigen::Index i = 0; i < w.size(); ++i) w(i) += 1e-3 * g(rng) / 40.0;
      const std::vector<int> expected = NegativeBins(t, members, w);
      double read = -1;
      EXPECT_EQ(sequence.NegativeBins(w, &read), expected) << "block " << block << "/" << sub << ", step " << step;
      if (step % 6 != 0) EXPECT_LT(read, 0.2) << "a nudge re-reads most bins, step " << step;
      with_negatives += !expected.empty();
    }
    EXPECT_GT(with_negatives, 12);
  }
}

TEST(TableCheck, OneNegativeBinAmongLargeValuesIsFound) {
  // Two columns equal but at one bin, where the second is larger: their
  // difference is zero everywhere but there, where it is negative, and the
  // block's mean hides it.
  MatrixXfR t = SmoothTable(640, 2, 7);
  t.col(1) = t.col(0);
  t(333, 1) += 0.5f;
  const Eigen::MatrixXd w = (Eigen::MatrixXd(2, 3) << 1, 1, 1, -1, -1, -1).finished();
  EXPECT_EQ(TableCheck(t, 32).NegativeBins({0, 1}, w), std::vector<int>{333});
}

TEST(TableCheck, NonNegativeWeightsOnASmoothTableNeedFewBinsLookedAt) {
  // A sum of non-negative columns is ≥ 0; on tables whose blocks vary little
  // the bound sees it without reading the bins.
  const MatrixXfR t = SmoothTable(4096, 12, 9);
  const std::vector<int> members = Members(12, 1);
  const Eigen::MatrixXd w = Eigen::MatrixXd::Constant(12, 3, 1.0 / 12);
  double cleared = 0;
  EXPECT_TRUE(TableCheck(t, 32).NegativeBins(members, w, &cleared).empty());
  EXPECT_GT(cleared, 0.9);
}

TEST(TableCheck, RefusesWeightsOfTheWrongShapeAndMembersOutOfRange) {
  const MatrixXfR t = SmoothTable(64, 4, 1);
  const TableCheck check(t, 8);
  EXPECT_THROW(check.NegativeBins({0, 1}, Eigen::MatrixXd::Ones(3, 3)), std::logic_error);
  EXPECT_THROW(check.NegativeBins({0, 4}, Eigen::MatrixXd::Ones(2, 3)), std::logic_error);
  EXPECT_THROW(TableCheck(t, 0), std::logic_error);
  EXPECT_THROW(TableCheck(t, 32, 5), std::logic_error);  // sub-blocks that do not divide the blocks
}

}  // namespace brdfshot
