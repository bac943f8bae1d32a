#include "fit/photo_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit/bin_constraints.h"
#include "fit/fit_confidence.h"
#include "util/check.h"

namespace brdfshot {

namespace {
// Twelve bases in two classes on a 32-px sphere; each basis image a random
// smooth function of the normal plus a little texture (full column rank).
struct Scene {
  BasisImages basis;
  ClassModel model;
  BasisTables tables;  // 400 bins × 12 bases, non-negative like every database's
};
Scene MakeScene() {
  Scene s;
  s.basis.geometry = OrthographicSphere(32, 80);
  const PixelGeometry& g = s.basis.geometry;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.1, 1.0);
  for (int c = 0; c < 3; ++c) {
    s.basis.Y[c].resize(static_cast<Eigen::Index>(g.size()), 12);
    for (int j = 0; j < 12; ++j) {
      const double a = u(rng), bx = u(rng) - .5, by = u(rng) - .5, q = u(rng);
      for (size_t p = 0; p < g.size(); ++p)
        s.basis.Y[c](static_cast<Eigen::Index>(p), j) = static_cast<float>(
            a + bx * g.normal[p].x + by * g.normal[p].y + q * g.normal[p].z * g.normal[p].y + 0.05 * u(rng));
    }
  }
  s.tables = BasisTables(MatrixXfR::NullaryExpr(400, 12, [&]() { return static_cast<float>(u(rng) - 0.1); }));
  s.model.mix = Eigen::VectorXd::Constant(2, 0.5);
  s.model.label = {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
  return s;
}
Eigen::MatrixXd Render(const BasisImages& b, const Eigen::MatrixXd& w) {
  Eigen::MatrixXd y(b.Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = b.Y[c].cast<double>() * w.col(c);
  return y;
}
}  // namespace

TEST(FitPhoto, ExactCombinationOfAClassIsFoundAndPredictedToRelightWell) {
  const Scene s = MakeScene();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  w.block(6, 0, 6, 3).setConstant(0.1);
  w(8, 0) = 0.6, w(10, 2) = 0.5;
  const Eigen::MatrixXd y = Render(s.basis, w);
  for (const char* rule : {"cv", "gcv", "fixed"}) {
    SCOPED_TRACE(rule);
    PhotoFitOptions opt;
    opt.lambda.rule = rule;
    opt.lambda.fixed = 1e-3;
    opt.lambda.all_bases_candidate = false;  // the model's classes only: which one is the question
    const PhotoFit fit = FitPhoto(s.basis, s.model, y, opt, &s.tables);
    EXPECT_EQ(fit.fit.chosen, 1);
    EXPECT_EQ(fit.choice.chosen_class, 1);
    EXPECT_LT(fit.relative_residual, 0.01);
    EXPECT_LT(fit.choice.predicted_error, 0.02) << "noise-free data in the span must predict well";
    EXPECT_LT((fit.reconstruction - y).norm(), 0.01 * y.norm());
    EXPECT_TRUE(fit.weights.topRows(6).isZero()) << "weights outside the class stay zero";
  }
}

TEST(FitPhoto, AMaterialAcrossTheClassesIsFoundByTheEveryBasisCandidate) {
  // A truth that mixes both classes: no class spans it, every basis does.
  const Scene s = MakeScene();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  for (int c = 0; c < 3; ++c) w.col(c) << 0.3, 0, 0.1, 0, 0, 0.2, 0, 0.25, 0, 0.1, 0, 0.05;
  const Eigen::MatrixXd y = Render(s.basis, w);
  Scene gridded = s;  // the tables' grid gives the BRDF metric, and with it the penalty
  gridded.basis.header["grid"] = {4, 5, 20};
  PhotoFitOptions classes_only;
  classes_only.lambda.all_bases_candidate = false;
  const PhotoFit every = FitPhoto(gridded.basis, s.model, y, PhotoFitOptions{}, &s.tables);
  const PhotoFit classes = FitPhoto(gridded.basis, s.model, y, classes_only, &s.tables);
  ASSERT_EQ(every.fit.classes.size(), 3u) << "the two classes, then every basis";
  EXPECT_EQ(every.fit.chosen, 2);
  EXPECT_EQ(every.fit.classes[2].members, 12);
  EXPECT_LT(every.relative_residual, 0.01);
  EXPECT_GT(classes.relative_residual, 10 * every.relative_residual);
  EXPECT_LT(every.choice.predicted_error, classes.choice.predicted_error);
  // The penalty looked at the pick: its sensitivity is the one fit.json reports.
  size_t at = 0;
  while (every.choice.grid[at] != every.choice.lambda) ++at;
  ASSERT_EQ(every.choice.sensitivity.size(), 3u);
  EXPECT_EQ(every.choice.sensitivity_penalty, 1);
  EXPECT_EQ(classes.choice.sensitivity_penalty, 1) << "the penalty weighs the classes too";
  ASSERT_TRUE(std::isfinite(every.choice.sensitivity[2][at]));
  // fit.json's confidence weighs the same moves in the image metric of a
  // sphere under the confidence's suns, not in the penalty's BRDF metric.
  ASSERT_EQ(every.choice.parts.size(), 1u);
  const std::array<ChannelFactor, 3> f = FactorBasisImages(gridded.basis.Y);
  std::vector<int> all(12);
  for (int i = 0; i < 12; ++i) all[i] = i;
  const ClassSpectrum cls = FactorClasses(f, {all})[0];
  const Eigen::MatrixXd suns = DirectionalImageGram(s.tables, gridded.basis.Grid(), ConfidenceSuns());
  EXPECT_NEAR(every.confidence.prior_sensitivity,
              PriorSensitivity(cls, MakeObservation(f, gridded.basis.Y, y), every.choice.lambda, suns), 1e-9);
}

TEST(FitPhoto, ABlendIsItsPartsWeightedAndRelightsNoWorseThanTheirMean) {
  // A truth mostly in class 1 with a little of class 0, under noise: the
  // class and every basis both explain it, neither exactly.
  Scene s = MakeScene();
  s.basis.header["grid"] = {4, 5, 20};  // the tables' grid: the penalty, and with it the blend
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  for (int c = 0; c < 3; ++c) w.col(c) << 0.03, 0, 0.02, 0, 0, 0.01, 0.3, 0.05, 0.2, 0.1, 0.25, 0.1;
  std::mt19937 rng(21);
  std::normal_distribution<double> noise(0, 0.05);
  Eigen::MatrixXd y = Render(s.basis, w);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += noise(rng);
  PhotoFitOptions opt;
  opt.constraint = WeightConstraint::Kind::kNone;
  opt.lambda.min_blend_weight = 0;
  const PhotoFit fit = FitPhoto(s.basis, s.model, y, opt, &s.tables);
  ASSERT_EQ(fit.choice.parts.size(), 2u);
  EXPECT_EQ(std::max(fit.choice.parts[0].cls, fit.choice.parts[1].cls), 2) << "one part every basis (2)";
  EXPECT_LT(std::min(fit.choice.parts[0].cls, fit.choice.parts[1].cls), 2) << "the other a class";
  // Each part is its class's ridge solve at its own λ.
  const std::array<ChannelFactor, 3> f = FactorBasisImages(s.basis.Y);
  const std::vector<ClassSpectrum> classes =
      FactorClasses(f, {s.model.Members(0), s.model.Members(1), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}});
  const Observation obs = MakeObservation(f, s.basis.Y, y);
  Eigen::MatrixXd blend = Eigen::MatrixXd::Zero(12, 3);
  std::vector<Eigen::MatrixXd> parts;
  for (const LambdaChoice::Part& p : fit.choice.parts) {
    parts.push_back(SolveClass(f, classes[p.cls], obs, p.lambda).weights);
    blend += p.weight * parts.back();
  }
  EXPECT_LT((fit.weights - blend).norm(), 1e-9 * blend.norm());
  EXPECT_LT((fit.reconstruction - Render(s.basis, fit.weights)).norm(), 1e-9 * y.norm());
  // Under other lighting (another scene's basis images) the blend relights
  // no worse than its parts' weighted mean: the error is a norm.
  const Scene other = [] {
    Scene o = MakeScene();
    std::mt19937 r(99);
    std::uniform_real_distribution<float> u(0.5f, 1.5f);
    for (int c = 0; c < 3; ++c)
      for (Eigen::Index j = 0; j < o.basis.Y[c].cols(); ++j) o.basis.Y[c].col(j) *= u(r);
    return o;
  }();
  const Eigen::MatrixXd truth = Render(other.basis, w);
  const auto relit = [&](const Eigen::MatrixXd& v) { return (Render(other.basis, v) - truth).norm(); };
  EXPECT_LE(relit(fit.weights),
            fit.choice.parts[0].weight * relit(parts[0]) + fit.choice.parts[1].weight * relit(parts[1]) + 1e-12);
  // With the bin constraint each part keeps the whole table non-negative, and so does the blend.
  PhotoFitOptions bins = opt;
  bins.constraint = WeightConstraint::Kind::kBins;
  bins.constraint_stride = 7;
  const PhotoFit b = FitPhoto(s.basis, s.model, y, bins, &s.tables);
  ASSERT_EQ(b.choice.parts.size(), 2u);
  EXPECT_TRUE(NegativeBins(s.tables, classes[2].members, b.weights).empty());
}

TEST(FitPhoto, NoiseRaisesTheChosenLambdaAndThePredictedError) {
  const Scene s = MakeScene();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  for (int c = 0; c < 3; ++c) w.col(c).tail(6) << 0.3, 0.05, 0.2, 0.1, 0.25, 0.1;  // near the class mean, not on it
  const Eigen::MatrixXd clean = Render(s.basis, w);
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0, 0.2);
  Eigen::MatrixXd noisy = clean;
  for (Eigen::Index i = 0; i < noisy.size(); ++i) noisy(i) += noise(rng);
  const PhotoFit a = FitPhoto(s.basis, s.model, clean, PhotoFitOptions{}, &s.tables);
  const PhotoFit b = FitPhoto(s.basis, s.model, noisy, PhotoFitOptions{}, &s.tables);
  EXPECT_GT(b.choice.lambda, a.choice.lambda);
  EXPECT_GT(b.choice.predicted_error, 5 * a.choice.predicted_error);
  // No grid for the tables, so no image metric: the confidence is the wedges' error.
  EXPECT_EQ(b.confidence.prior_sensitivity, -1);
  EXPECT_EQ(b.confidence.predicted_relit_error, b.choice.held_out_error);
  EXPECT_GT(b.confidence.predicted_relit_error, 5 * a.confidence.predicted_relit_error);
  // With the noise, the fit stays nearer the truth than the noisy photo is.
  EXPECT_LT((b.reconstruction - clean).norm(), 0.5 * (noisy - clean).norm());
}

TEST(FitPhoto, TheConditionBoundFollowsThePhotosNoiseUnlessFixed) {
  const Scene s = MakeScene();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  for (int c = 0; c < 3; ++c) w.col(c).tail(6) << 0.3, 0.05, 0.2, 0.1, 0.25, 0.1;
  const Eigen::MatrixXd clean = Render(s.basis, w);
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0, 0.05);
  Eigen::MatrixXd noisy = clean;
  for (Eigen::Index i = 0; i < noisy.size(); ++i) noisy(i) += noise(rng);
  PhotoFitOptions opt;
  opt.lambda.noise_bound.min_bound = 1;  // this scene's photos are too noisy for the default floor to show
  const PhotoFit a = FitPhoto(s.basis, s.model, clean, opt, &s.tables);
  const PhotoFit b = FitPhoto(s.basis, s.model, noisy, opt, &s.tables);
  // The basis images carry a texture of their own, which the estimate reads
  // as the clean photo's noise; the added noise comes on top.
  EXPECT_GT(b.relative_noise, 1.5 * a.relative_noise);
  // The clean photo is in the span: the fit of every basis leaves nothing, so
  // the noise the bound follows is far below the texture's reading. The noisy
  // one's pixel noise is all noise: the fit leaves about as much.
  EXPECT_LT(a.bound_noise, 0.01 * a.relative_noise);
  EXPECT_LE(b.bound_noise, b.relative_noise);
  EXPECT_GT(b.bound_noise, 0.5 * b.relative_noise);
  for (const PhotoFit* f : {&a, &b})
    EXPECT_DOUBLE_EQ(f->choice.condition_bound, ConditionBoundForNoise(f->bound_noise, opt.lambda.noise_bound));
  EXPECT_LT(b.choice.condition_bound, a.choice.condition_bound);
  // A fixed bound is taken as given, whatever the noise.
  PhotoFitOptions fixed;
  fixed.lambda.max_condition = 123.0;
  EXPECT_EQ(FitPhoto(s.basis, s.model, noisy, fixed, &s.tables).choice.condition_bound, 123.0);
}

TEST(FitPhoto, BinConstraintKeepsTheWholeTableNonNegative) {
  // A truth with negative weights: its own BRDF dips below zero at some bins,
  // so the unconstrained fit (which finds it) does too; the constrained fit
  // must not, at any bin of the table — sampled or not — and pays for it
  // with a larger residual.
  const Scene s = MakeScene();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  for (int c = 0; c < 3; ++c) w.col(c).tail(6) << 0.6, -0.4, 0.3, -0.3, 0.2, 0.1;
  const Eigen::MatrixXd y = Render(s.basis, w);
  const std::vector<int> members = {6, 7, 8, 9, 10, 11};
  ASSERT_FALSE(NegativeBins(s.tables, members, w.bottomRows(6)).empty()) << "the truth must go negative";
  PhotoFitOptions free, bins;
  free.lambda.all_bases_candidate = bins.lambda.all_bases_candidate = false;  // class 1 is the one to constrain
  free.constraint = WeightConstraint::Kind::kNone;
  bins.constraint = WeightConstraint::Kind::kBins;
  bins.constraint_stride = 7;  // most bins are not in the sample
  const PhotoFit a = FitPhoto(s.basis, s.model, y, free, &s.tables);
  const PhotoFit b = FitPhoto(s.basis, s.model, y, bins, &s.tables);
  ASSERT_EQ(a.fit.chosen, 1);
  ASSERT_EQ(b.fit.chosen, 1);
  EXPECT_FALSE(NegativeBins(s.tables, members, a.weights.bottomRows(6)).empty());
  EXPECT_TRUE(NegativeBins(s.tables, members, b.weights.bottomRows(6)).empty());
  EXPECT_GT(b.negative_bins_added, 0) << "the sampled bins alone must miss some, so the whole-table check had work";
  EXPECT_EQ(b.fit.classes[1].path, "nonneg-bins");
  EXPECT_GT(b.relative_residual, a.relative_residual);
  EXPECT_THROW(FitPhoto(s.basis, s.model, y, bins, nullptr), Error) << "the constraint needs the tables";
}

}  // namespace brdfshot
