#include "fit/table_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

// Per channel, the least t with every given bin of (1 − t) w + t μ' at or
// above zero, against a bisection on the blended values in double; a channel
// not below zero there is left alone.
TEST(MeanBlend, IsTheLeastBlendThatLiftsTheBinsAndItLiftsTheWholeTable) {
  const MatrixXfR t = SmoothTable(1024, 10, 21);
  const std::vector<int> members = Members(10, 1);
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  Eigen::MatrixXd w(10, 3);
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = 0.1 + g(rng);
  w.col(2) = w.col(2).cwiseAbs();  // non-negative weights: nothing to lift
  const std::vector<int> negative = NegativeBins(t, members, w);
  ASSERT_GT(negative.size(), 10u) << "the weights must go negative for the test to mean anything";
  const std::array<double, 3> blend = MeanBlendToNonNegative(t, members, w, negative);
  const Eigen::MatrixXd dense = t.cast<double>();
  const auto lowest = [&](int c, double x) {
    const Eigen::VectorXd v = (1 - x) * w.col(c).array() + x / 10.0;
    double m = std::numeric_limits<double>::infinity();
    for (int r : negative) m = std::min(m, dense.row(r).dot(v));
    return m;
  };
  for (int c = 0; c < 2; ++c) {
    double lo = 0, hi = 1;
    for (int it = 0; it < 100; ++it) ((lowest(c, 0.5 * (lo + hi)) < 0) ? lo : hi) = 0.5 * (lo + hi);
    EXPECT_GE(blend[c], hi) << "channel " << c;
    EXPECT_LE(blend[c], hi * (1 + 1e-5) + 1e-11) << "channel " << c;
    EXPECT_GT(blend[c], 0.01) << "channel " << c;
  }
  EXPECT_EQ(blend[2], 0);
  Eigen::MatrixXd lifted = w;
  for (int c = 0; c < 3; ++c) lifted.col(c) = (1 - blend[c]) * w.col(c).array() + blend[c] / 10.0;
  EXPECT_TRUE(NegativeBins(t, members, lifted).empty());
}

// A class whose fit dips below zero between the sampled bins: after
// KeepNonNegativeOnTable no bin of the table is below zero, with or without
// a check given, by solves with the bins found or, with no solve allowed, by
// the blend toward the class's mean alone; the residual is the blended
// weights' own.
TEST(KeepNonNegativeOnTable, LeavesNoBinOfTheTableBelowZero) {
  constexpr int kBases = 12, kPixels = 400;
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0.1f, 1.0f);
  std::array<MatrixXfR, 3> Y;
  for (int c = 0; c < 3; ++c) {
    Y[c].resize(kPixels, kBases);
    for (Eigen::Index i = 0; i < Y[c].size(); ++i) Y[c].data()[i] = u(rng);
  }
  const auto render = [&](const Eigen::MatrixXd& w) {
    Eigen::MatrixXd y(kPixels, 3);
    for (int c = 0; c < 3; ++c) y.col(c) = Y[c].cast<double>() * w.col(c);
    return y;
  };
  // A difference of bases, as a material outside the database is.
  Eigen::MatrixXd truth = Eigen::MatrixXd::Constant(kBases, 3, 0.15);
  truth.row(4).setConstant(-0.9);
  truth.row(7).setConstant(-0.6);
  const Eigen::MatrixXd y = render(truth);
  const auto f = FactorBasisImages(Y, true);
  const std::vector<int> members = Members(kBases, 1);
  const ClassSpectrum cls = FactorClasses(f, {members})[0];
  const Observation obs = MakeObservation(f, Y, y);
  const MatrixXfR tables = SmoothTable(4096, kBases, 3);
  ASSERT_FALSE(NegativeBins(tables, members, truth).empty());
  const TableCheck given(tables, 64, 16);
  for (const int max_solves : {3, 0})
    for (const TableCheck* check : {static_cast<const TableCheck*>(nullptr), &given}) {
      SCOPED_TRACE(testing::Message() << "max_solves " << max_solves << (check ? ", a check given" : ""));
      BinRows bins = BinRows::EveryNth(tables, members, 97);
      WeightConstraint constraint;
      constraint.kind = WeightConstraint::Kind::kBins;
      constraint.bins = &bins;
      ClassSolution s = SolveClass(f, cls, obs, 1e-6, constraint);
      const Eigen::MatrixXd sampled = s.weights;
      ASSERT_FALSE(NegativeBins(tables, members, sampled).empty()) << "the sample must miss bins below zero";
      TableCheckSource checks(tables, check);
      const TableKeep keep = KeepNonNegativeOnTable(f, cls, obs, 1e-6, &checks, &bins, &s, max_solves);
      EXPECT_TRUE(NegativeBins(tables, members, s.weights).empty());
      EXPECT_LE(keep.solves, max_solves);
      EXPECT_NEAR(s.residual, (render(s.weights) - y).squaredNorm(), 1e-9 * y.squaredNorm());
      if (max_solves == 0) {
        EXPECT_EQ(keep.bins_added, 0);
        EXPECT_GT(keep.largest_mean_blend(), 0);
        for (int c = 0; c < 3; ++c)
          EXPECT_LT((s.weights.col(c) - ((1 - keep.mean_blend[c]) * sampled.col(c).array() + keep.mean_blend[c] / kBases)
                                            .matrix())
                        .norm(),
                    1e-12)
              << "channel " << c;
      } else {
        EXPECT_GT(keep.solves, 0);
        EXPECT_GT(keep.bins_added, 0);
      }
      // A fit checked twice leaves a summary for the next fit of these tables
      // (the given one where there is one).
      ASSERT_NE(checks.summary(), nullptr);
      if (check) EXPECT_EQ(checks.summary(), check);
    }
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
