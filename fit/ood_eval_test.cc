#include "fit/ood_eval.h"

#include <gtest/gtest.h>

#include <random>
#include <utility>

#include "fit/test_databases.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {


TEST(OutOfDatabase, TargetsInTheSpanAreRelitExactlyByLeastSquaresAndTheOracle) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(3);
  // Three scenes to fit from and one directional scene that only scores.
  const int n = 12, S = 3, T = 2, K = 4;
  const std::vector<int> fold = WedgeFolds(g, K);
  // Two targets, each exactly a combination of the bases (the same weights under every probe).
  std::normal_distribution<double> gauss;
  std::vector<Eigen::MatrixXd> W(T, Eigen::MatrixXd(n, 3));
  for (auto& w : W)
    for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = 0.2 * gauss(rng);
  LooInputs bases;
  std::vector<TargetScene> scenes;
  for (int s = 0; s <= S; ++s) {
    const bool scoring_only = s == S;
    const auto Y = RandomBasisImages(g, n, rng);
    std::array<MatrixXfR, 3> Yt;
    for (int c = 0; c < 3; ++c) {
      Yt[c] = MatrixXfR::Zero(Y[c].rows(), 3 * T);
      for (int t = 0; t < T; ++t) Yt[c].col(3 * t + c) = (Y[c].cast<double>() * W[t].col(c)).cast<float>();
    }
    SceneFactors sf;
    sf.probe = "p" + std::to_string(s);
    sf.scoring_only = scoring_only;
    sf.f = FactorBasisImages(Y, !scoring_only);
    if (!scoring_only) sf.fold_gram = FoldGrams(Y, fold, K);
    sf.pixels = g.size();
    scenes.push_back(scoring_only ? MakeTargetScene(sf.f, Y, Yt, std::vector<int>(g.size(), 0), 1)
                                  : MakeTargetScene(sf.f, Y, Yt, fold, K));
    for (int c = 0; c < 3; ++c)  // against a dense product
      for (int t = 0; t < T; ++t) {
        const Eigen::VectorXd want = Y[c].cast<double>().transpose() * Yt[c].col(3 * t + c).cast<double>();
        EXPECT_LT((scenes.back().cross[c].col(t) - want).norm(), 1e-9 * want.norm());
        double parts = 0;
        for (size_t k = 0; k < scenes.back().fold_self.size(); ++k) parts += scenes.back().fold_self[k][c][t];
        EXPECT_NEAR(parts, scenes.back().self[c][t], 1e-9 * parts);
      }
    bases.scenes.push_back(std::move(sf));
  }
  bases.materials = {"a", "b", "c", "d"};
  bases.gram = bases.scenes[0].f[1].gram;
  // Non-negative "tables": 50 bins of 12 bases.
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  bases.bin_sample = MatrixXfR::NullaryExpr(50, n, [&]() { return u(rng); });
  bases.constraint_sample = bases.bin_sample;
  LooOptions opt;
  opt.gmm.classes = 2;
  opt.gmm.dims = 2;
  const LooResult r = RunOutOfDatabase(bases, scenes, {"t0", "t1"}, opt);
  ASSERT_EQ(r.rows.size(), static_cast<size_t>(T * S * 6)) << "six methods, fitted under the three scenes only";
  for (const LooRow& row : r.rows) {
    EXPECT_TRUE(std::isfinite(row.relit_mean)) << row.method;
    EXPECT_NE(row.probe, "p3") << "a scoring-only scene is never fitted from";
    EXPECT_GE(row.relit_directional, 0) << row.method;
    EXPECT_GE(row.negative_bins, 0) << row.method;
    if (row.method == "lsq" || row.method == "relit-oracle") {
      // In the span: exact under the other fitted scenes; least squares also
      // under the directional one (the oracle only knows the fitted scenes,
      // but the targets are in the span so it is exact there too).
      EXPECT_LT(row.relit_mean, 1e-5) << row.method;
      EXPECT_LT(row.relit_directional, 1e-5) << row.method;
    }
    if (row.method == "auto") {
      EXPECT_GE(row.predicted, 0) << "auto predicts its error";
      EXPECT_EQ(row.negative_bins, 0.0) << "auto keeps the BRDF non-negative at the constrained bins";
    }
  }
  // The targets' weights have both signs: least squares reproduces them, and
  // its BRDF goes negative somewhere on the sampled bins.
  double lsq_negative = 0;
  for (const LooRow& row : r.rows)
    if (row.method == "lsq") lsq_negative += row.negative_bins;
  EXPECT_GT(lsq_negative, 0);
}

// Two photos that say the same thing (scene 1 is scene 0 at twice the
// brightness, targets included) fit as one photo does: each target's joint
// row relights as either photo's own fit under the scene neither was taken
// under; every other pair is scored there too, and only there.
TEST(OutOfDatabase, JointRowsOfProportionalScenesEqualTheSinglePhotos) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(4);
  const int n = 12, T = 2, K = 4;
  const std::vector<int> fold = WedgeFolds(g, K);
  std::normal_distribution<double> gauss;
  // Targets outside the bases' span: a basis image plus the square of another.
  const auto targets_of = [&](const std::array<MatrixXfR, 3>& Y) {
    std::array<MatrixXfR, 3> Yt;
    for (int c = 0; c < 3; ++c) {
      Yt[c] = MatrixXfR::Zero(Y[c].rows(), 3 * T);
      for (int t = 0; t < T; ++t)
        Yt[c].col(3 * t + c) = Y[c].col(t + c).array() + 0.3f * Y[c].col(n - 1 - t).array().square();
    }
    return Yt;
  };
  std::vector<std::pair<std::array<MatrixXfR, 3>, std::array<MatrixXfR, 3>>> images;
  images.emplace_back(RandomBasisImages(g, n, rng), std::array<MatrixXfR, 3>{});
  images[0].second = targets_of(images[0].first);
  images.push_back(images[0]);
  for (int c = 0; c < 3; ++c) images[1].first[c] *= 2.0f, images[1].second[c] *= 2.0f;
  images.emplace_back(RandomBasisImages(g, n, rng), std::array<MatrixXfR, 3>{});
  images[2].second = targets_of(images[2].first);
  LooInputs bases;
  std::vector<TargetScene> scenes;
  int s = 0;
  for (const auto& [Y, Yt] : images) {
    SceneFactors sf;
    sf.probe = "p" + std::to_string(s++);
    sf.f = FactorBasisImages(Y, true);
    sf.fold_gram = FoldGrams(Y, fold, K);
    sf.pixels = g.size();
    scenes.push_back(MakeTargetScene(sf.f, Y, Yt, fold, K));
    bases.scenes.push_back(std::move(sf));
  }
  bases.materials = {"a", "b", "c", "d"};
  bases.gram = bases.scenes[0].f[1].gram;
  LooOptions opt;
  opt.gmm.classes = 2;
  opt.gmm.dims = 2;
  opt.constraint = WeightConstraint::Kind::kNone;
  opt.joint = true;
  const LooResult r = RunOutOfDatabase(bases, scenes, {"t0", "t1"}, opt);
  ASSERT_EQ(r.rows.size(), static_cast<size_t>(T * 3 * 6 + T * 3 * 3)) << "six methods per photo, three rows per pair";
  int pairs = 0;
  for (const LooRow& row : r.rows) {
    if (row.method != "auto-joint") continue;
    EXPECT_TRUE(row.probe == "p0+p1" || row.probe == "p1+p2" || row.probe == "p2+p0") << row.probe;
    EXPECT_TRUE(std::isfinite(row.relit_mean) && row.relit_mean > 0) << row.probe;
    if (row.probe != "p0+p1") continue;
    ++pairs;
    for (const LooRow& one : r.rows) {
      if (one.method == "auto-one" && one.material == row.material &&
          (one.probe == "p0 (p0+p1)" || one.probe == "p1 (p0+p1)")) {
        EXPECT_NEAR(one.relit_mean, row.relit_mean, 1e-6 * row.relit_mean) << row.material << ", " << one.probe;
      }
    }
  }
  EXPECT_EQ(pairs, T);
}

}  // namespace brdfshot

namespace brdfshot {

TEST(NegativeBinShare, CountsBinChannelPairsBelowZero) {
  MatrixXfR bins(2, 3);
  // clang-format off
  bins << 1, 0, 2,
          0, 1, 1;
  // clang-format on
  Eigen::MatrixXd w(3, 3);
  // clang-format off
  w << 1, -1, 1,
       -2, 1, 0,
       0, 0, -1;
  // clang-format on
  // Values per bin and channel: bin 0 (1, -1, -1), bin 1 (-2, 1, -1): 4 of 6 negative.
  EXPECT_DOUBLE_EQ(NegativeBinShare(bins, w), 4.0 / 6.0);
  EXPECT_EQ(NegativeBinShare(MatrixXfR(), w), -1.0) << "nothing sampled: not counted";
  EXPECT_EQ(SampleBins(bins, 2).rows(), 1);
  EXPECT_EQ(SampleBins(bins, 1), bins);
}

TEST(Spearman, RanksWithTiesAgainstHandComputedValues) {
  EXPECT_DOUBLE_EQ(SpearmanCorrelation({0.1, 0.5, 0.2, 9}, {1, 100, 2, 1e6}), 1.0);  // any monotone map
  EXPECT_DOUBLE_EQ(SpearmanCorrelation({1, 2, 3}, {3, 2, 1}), -1.0);
  // Ties take their mean rank: ranks (0, 1.5, 1.5, 3) and (0, 2, 1, 3) give 4.5 / √(4.5 · 5).
  EXPECT_NEAR(SpearmanCorrelation({1, 2, 2, 3}, {1, 3, 2, 4}), 4.5 / std::sqrt(22.5), 1e-12);
  EXPECT_EQ(SpearmanCorrelation({1, 1, 1}, {1, 2, 3}), 0.0) << "a constant sample has no ranking";
}

}  // namespace brdfshot
