#include "fit/loo_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "fit/joint_photos.h"
#include "fit/photo_noise.h"
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

// The relit error from Gram matrices against the images themselves,
// ‖Y w − Y e_m‖ / ‖Y e_m‖ over RGB, for weights on a few bases (a class's
// fit) and on all of them.
TEST(MaterialImage, TakesEachChannelFromTheMaterialsOwnColumn) {
  std::array<MatrixXfR, 3> images;
  for (int c = 0; c < 3; ++c) {
    images[c].resize(2, 6);  // two materials, two pixels
    for (int j = 0; j < 6; ++j) images[c](0, j) = 100.0f * c + j, images[c](1, j) = -(100.0f * c + j);
  }
  const Eigen::MatrixXd y = MaterialImage(images, 1);
  ASSERT_EQ(y.rows(), 2);
  ASSERT_EQ(y.cols(), 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(y(0, c), 100.0 * c + 3 + c) << c;
    EXPECT_EQ(y(1, c), -(100.0 * c + 3 + c)) << c;
  }
}

TEST(RelativeError, IsTheRelativeImageErrorOfTheWeights) {
  std::mt19937 rng(3);
  std::normal_distribution<double> u(0, 1);
  const int pixels = 40, n = 12, m = 1;
  std::array<Eigen::MatrixXd, 3> Y, G;
  for (int c = 0; c < 3; ++c) {
    Y[c] = Eigen::MatrixXd::NullaryExpr(pixels, n, [&]() { return u(rng); });
    G[c] = Y[c].transpose() * Y[c];
  }
  std::vector<Eigen::MatrixXd> w(5, Eigen::MatrixXd::Zero(n, 3));
  for (int c = 0; c < 3; ++c) w[0](3 * m + c, c) = 1;  // the material itself: no error
  w[1] = Eigen::MatrixXd::NullaryExpr(n, 3, [&]() { return u(rng); });
  for (int c = 0; c < 3; ++c) w[3](3 * m + c, c) = 2;  // twice the material: error 1
  for (int j : {0, 7, 11}) w[4].row(j) = Eigen::RowVector3d(u(rng), u(rng), u(rng));
  // Each alone, and all five at once, against the images themselves.
  std::vector<const Eigen::MatrixXd*> all;
  for (const Eigen::MatrixXd& wi : w) all.push_back(&wi);
  const std::vector<double> together = RelativeErrors({&G[0], &G[1], &G[2]}, all, m);
  ASSERT_EQ(together.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    double num = 0, den = 0;
    for (int c = 0; c < 3; ++c) {
      num += (Y[c] * w[i].col(c) - Y[c].col(3 * m + c)).squaredNorm();
      den += Y[c].col(3 * m + c).squaredNorm();
    }
    EXPECT_NEAR(RelativeError({&G[0], &G[1], &G[2]}, w[i], m), std::sqrt(num / den), 1e-12) << "weight set " << i;
    EXPECT_NEAR(together[i], std::sqrt(num / den), 1e-12) << "weight set " << i;
  }
  EXPECT_NEAR(RelativeError({&G[0], &G[1], &G[2]}, w[0], m), 0, 1e-7);
  EXPECT_NEAR(RelativeError({&G[0], &G[1], &G[2]}, w[2], m), 1, 1e-12);  // no weights: the whole image is missed
  EXPECT_NEAR(RelativeError({&G[0], &G[1], &G[2]}, w[3], m), 1, 1e-12);
}

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
  std::map<std::pair<std::string, std::string>, std::map<std::string, double>>
      relit;  // (material, probe) → method → error
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

// The joint scene of the evaluation is StackPhotos' stack without the
// pixels: the Gram matrices of the two photos' stacked, RMS-scaled basis
// images, fold by fold, and the stack's pooled pixel noise.
TEST(JointOfScenes, IsTheGramOfThePhotosStackedByStackPhotos) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(8);
  const int n = 12, K = 4, m = 2;
  std::array<MatrixXfR, 3> ya = RandomBasisImages(g, n, rng), yb = RandomBasisImages(g, n, rng);
  for (auto& y : yb) y *= 40.0f;  // probe B forty times as bright: the scales must even the photos out
  LooInputs in = Inputs(g, {ya, yb});
  std::vector<BasisImages> bases(2);
  std::vector<Eigen::MatrixXd> photos(2);
  for (int s = 0; s < 2; ++s) {
    bases[s].geometry = g;
    bases[s].Y = s ? yb : ya;
    bases[s].header = {{"probe", "p.exr"},
                       {"probe_name", "p"},
                       {"database_kind", "standin"},
                       {"grid", {1, 1, 1}},
                       {"bases", std::vector<std::string>(n, "b")}};
    photos[s].resize(static_cast<Eigen::Index>(g.size()), 3);
    for (int c = 0; c < 3; ++c) photos[s].col(c) = bases[s].Y[c].col(3 * m + c).cast<double>();
    in.scenes[s].photo_noise.assign(n / 3, RelativePixelNoise(g, photos[s]));
  }
  const JointPhotos stack = StackPhotos(bases, photos, {"a.bsbi", "b.bsbi"}, K);
  const auto grams = FactorBasisImages(stack.basis.Y);
  const auto folds = FoldGrams(stack.basis.Y, stack.fold_of_pixel, K);

  const JointScene joint = JointOfScenes(in.scenes[0], in.scenes[1], m);
  EXPECT_EQ(joint.pixels, stack.y.rows());
  EXPECT_NEAR(joint.photo_noise, stack.relative_noise, 1e-12);
  for (int c = 0; c < 3; ++c) {
    const double scale = grams[c].gram.norm();
    EXPECT_LT((joint.f[c].gram - grams[c].gram).norm(), 1e-6 * scale) << "channel " << c;
    for (int k = 0; k < K; ++k)
      EXPECT_LT((joint.fold_gram[k][c] - folds[k][c]).norm(), 1e-6 * scale) << "fold " << k << ", channel " << c;
    // The photo is its basis column: the stack's projection of its own pixels.
    const Eigen::VectorXd z = ProjectRows(stack.basis.Y[c], stack.y.col(c));
    EXPECT_LT((joint.f[c].gram.col(3 * m + c) - z).norm(), 1e-6 * z.norm());
  }
}

// Each fitted scene is paired with the next fitted one, cyclically; two
// fitted scenes make one pair, and a scoring-only scene none.
TEST(JointPartner, PairsEachFittedSceneWithTheNextOnce) {
  std::vector<SceneFactors> scenes(4);
  scenes[1].scoring_only = true;
  EXPECT_EQ(JointPartner(scenes, 0), 2);
  EXPECT_EQ(JointPartner(scenes, 1), -1);
  EXPECT_EQ(JointPartner(scenes, 2), 3);
  EXPECT_EQ(JointPartner(scenes, 3), 0);
  std::vector<SceneFactors> two(3);
  two[2].scoring_only = true;
  EXPECT_EQ(JointPartner(two, 0), 1);
  EXPECT_EQ(JointPartner(two, 1), -1) << "the pair 0+1 is counted once";
  EXPECT_EQ(JointPartner(std::vector<SceneFactors>(1), 0), -1) << "no other fitted scene";
}

// Two photos that say the same thing (the second scene is the first at twice
// the brightness) fit as one photo does: the joint rows relight exactly as
// either photo's own fit, under the probe neither was taken under.
TEST(LeaveOneOut, JointRowsOfProportionalScenesEqualTheSinglePhotos) {
  const PixelGeometry g = OrthographicSphere(24, 80);
  std::mt19937 rng(9);
  const auto Y = RandomBasisImages(g, 15, rng);
  std::array<MatrixXfR, 3> twice = Y;
  for (auto& y : twice) y *= 2.0f;
  LooOptions opt = Options();
  opt.joint = true;
  const LooResult r = RunLeaveOneOut(Inputs(g, {Y, twice, RandomBasisImages(g, 15, rng)}), opt);
  int pairs = 0;
  for (const LooRow& row : r.rows) {
    if (row.method != "auto-joint" || row.probe != "p0+p1") continue;
    ++pairs;
    int singles = 0;
    for (const LooRow& one : r.rows)
      if (one.method == "auto-one" && one.material == row.material &&
          (one.probe == "p0 (p0+p1)" || one.probe == "p1 (p0+p1)")) {
        EXPECT_NEAR(one.relit_mean, row.relit_mean, 1e-6 * row.relit_mean) << row.material << ", " << one.probe;
        ++singles;
      }
    EXPECT_EQ(singles, 2) << row.material;
  }
  EXPECT_EQ(pairs, 5);
  // Three fitted scenes: pairs p0+p1, p1+p2, p2+p0, each with its two photos.
  EXPECT_EQ(std::count_if(r.rows.begin(), r.rows.end(), [](const LooRow& x) { return x.method == "auto-joint"; }), 15);
  EXPECT_EQ(std::count_if(r.rows.begin(), r.rows.end(), [](const LooRow& x) { return x.method == "auto-one"; }), 30);
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
