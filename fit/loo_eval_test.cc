#include "fit/loo_eval.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "fit/test_databases.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {

namespace {

// Leave-one-out inputs over `materials` materials: one scene per entry of
// `images` (the basis images under that probe), factored as the evaluation
// factors them.
LooInputs Inputs(const PixelGeometry& g, const std::vector<std::array<MatrixXfR, 3>>& images) {
  LooInputs in;
  const int n = static_cast<int>(images[0][0].cols()), K = 4;
  const std::vector<int> fold = WedgeFolds(g, K);
  for (size_t s = 0; s < images.size(); ++s) {
    SceneFactors sf;
    sf.probe = "p" + std::to_string(s);
    sf.f = FactorBasisImages(images[s], true);
    sf.fold_gram = FoldGrams(images[s], fold, K);
    sf.pixels = g.size();
    in.scenes.push_back(std::move(sf));
  }
  for (int m = 0; m < n / 3; ++m) in.materials.push_back("m" + std::to_string(m));
  in.gram = in.scenes[0].f[1].gram;
  in.gram_cos = Eigen::MatrixXd::Identity(n, n) + 0.1 * in.gram / in.gram.trace();
  return in;
}

LooOptions Options() {
  LooOptions opt;
  opt.gmm.classes = 2;
  opt.gmm.dims = 2;
  opt.constraint = WeightConstraint::Kind::kNone;
  return opt;
}

}  // namespace

// When every probe sees the same images up to a scale, the relit error of any
// weights is one quadratic form, which least squares under the fitted probe
// and the relit-space oracle both minimise: the oracle equals least squares
// and no method relights better.
TEST(LeaveOneOut, WithProportionalScenesTheRelitOracleIsLeastSquaresAndTheFloor) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(5);
  const auto Y = RandomBasisImages(g, 15, rng);
  std::vector<std::array<MatrixXfR, 3>> images;
  for (float scale : {1.0f, 2.0f, 0.5f}) {
    std::array<MatrixXfR, 3> Ys = Y;
    for (auto& y : Ys) y *= scale;
    images.push_back(Ys);
  }
  const LooResult r = RunLeaveOneOut(Inputs(g, images), Options());
  std::map<std::pair<std::string, std::string>, std::map<std::string, double>> relit;  // (material, probe) → method → error
  for (const LooRow& row : r.rows) relit[{row.material, row.probe}][row.method] = row.relit_mean;
  ASSERT_EQ(relit.size(), 5u * 3u);
  for (const auto& [key, by_method] : relit) {
    ASSERT_TRUE(by_method.count("relit-oracle") && by_method.count("lsq")) << key.first;
    const double floor = by_method.at("relit-oracle");
    EXPECT_GT(floor, 1e-3) << "a left-out material is not in the others' span";
    EXPECT_NEAR(floor, by_method.at("lsq"), 1e-6 * floor) << key.first << " under " << key.second;
    for (const auto& [method, e] : by_method) EXPECT_GE(e, floor * (1 - 1e-9)) << method << ", " << key.first;
  }
}

// Under independent probes the oracle uses the other probes' true images, so
// a left-out material that another material duplicates is relit exactly.
TEST(LeaveOneOut, TheRelitOracleRelightsAMaterialInTheSpanExactly) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(6);
  std::vector<std::array<MatrixXfR, 3>> images;
  for (int s = 0; s < 3; ++s) {
    auto Y = RandomBasisImages(g, 15, rng);
    for (auto& y : Y) y.middleCols(12, 3) = y.middleCols(9, 3);  // material 4 duplicates material 3
    images.push_back(Y);
  }
  const LooResult r = RunLeaveOneOut(Inputs(g, images), Options());
  int checked = 0;
  for (const LooRow& row : r.rows) {
    if (row.method != "relit-oracle") continue;
    if (row.material == "m4" || row.material == "m3") {
      EXPECT_LT(row.relit_mean, 1e-4) << row.material << " under " << row.probe;
      ++checked;
    } else {
      EXPECT_GT(row.relit_mean, 1e-3) << row.material;
    }
  }
  EXPECT_EQ(checked, 2 * 3);
}

// The analytic baseline's row: a material that is exactly kd/π + q[F0(1 − s) + s]
// GGX under every scene is fitted from one and relit exactly under the others
// (and the scoring-only one); a material outside the model is not.
TEST(LambertGgxRow, AMaterialOfTheModelRelightsExactlyAndOneOutsideItDoesNot) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.1f, 1.0f);
  LooInputs in;
  in.lobes.alphas = {0.1, 0.3};
  const int P = 200, A = in.lobes.columns();
  Eigen::MatrixXd truth = Eigen::MatrixXd::Zero(A, 3);  // material 0, at α = 0.3
  for (int c = 0; c < 3; ++c) truth(0, c) = 0.2 + 0.1 * c, truth(3, c) = 0.05 * (c + 1), truth(4, c) = 0.5;
  for (int s = 0; s < 3; ++s) {
    SceneFactors sf;
    sf.probe = "p" + std::to_string(s);
    sf.scoring_only = s == 2;
    in.scenes.push_back(sf);
    std::array<MatrixXfR, 3> L, images;
    for (int c = 0; c < 3; ++c) {
      L[c] = MatrixXfR::NullaryExpr(P, A, [&] { return u(rng); });
      images[c] = MatrixXfR::NullaryExpr(P, 6, [&] { return u(rng); });  // two materials
      images[c].col(c) = (L[c].cast<double>() * truth.col(c)).cast<float>();
    }
    in.lobe_scenes.push_back(MakeLobeScene(images, L));
  }
  in.materials = {"in-model", "random"};
  const LooRow exact = LambertGgxRow(in, 0, 0, "in-model");
  EXPECT_EQ(exact.method, "lambert-ggx");
  EXPECT_EQ(exact.probe, "p0");
  EXPECT_LT(exact.insample, 1e-5);
  EXPECT_LT(exact.relit_mean, 1e-5) << "relit under p1";
  EXPECT_LT(exact.relit_directional, 1e-5) << "relit under the scoring-only p2";
  EXPECT_EQ(exact.negative_bins, 0);
  const LooRow other = LambertGgxRow(in, 1, 1, "random");
  EXPECT_GT(other.relit_mean, 0.05);
}

}  // namespace brdfshot
