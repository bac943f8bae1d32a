#include "fit/fit_confidence.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <cmath>
#include <random>

#include "fit/database.h"

namespace brdfshot {
namespace {

// The channel factors of a photo whose Gram matrix is `gram` in every channel.
std::array<ChannelFactor, 3> Factors(const Eigen::MatrixXd& gram) {
  std::array<ChannelFactor, 3> f;
  for (auto& c : f) c.gram = gram;
  return f;
}

Observation ObservationOf(const Eigen::MatrixXd& gram, const Eigen::VectorXd& w) {
  Observation obs;
  for (int c = 0; c < 3; ++c) obs.z[c] = gram * w, obs.norm2[c] = w.dot(gram * w);
  return obs;
}

}  // namespace

// One basis, Gram e = 1, z = 2, ‖y‖² = 4, prior 1: w(λ_j) = 1 + 1/(1 + λ_j)
// with λ_j = 4λ. At λ = 0.1: w = 1 + 1/1.4, at λ/10 1 + 1/1.04, at 10λ 1 + 1/5;
// the metric's scale cancels.
TEST(PriorSensitivity, OneBasisMatchesTheClosedForm) {
  const Eigen::MatrixXd G = Eigen::MatrixXd::Identity(1, 1);
  const ClassSpectrum cls = FactorClasses(Factors(G), {{0}})[0];
  Observation obs;
  for (int c = 0; c < 3; ++c) obs.z[c] = Eigen::VectorXd::Constant(1, 2.0), obs.norm2[c] = 4;
  const double w = 1 + 1 / 1.4, down = 1 + 1 / 1.04, up = 1 + 1 / 5.0;
  const double expected = std::hypot((down - w) / w, (up - w) / w);
  EXPECT_NEAR(PriorSensitivity(cls, obs, 0.1, 7.0 * G), expected, 1e-12);
  EXPECT_THROW(PriorSensitivity(cls, obs, 0.1, Eigen::MatrixXd::Identity(2, 2)), std::exception)
      << "a metric over other bases";
}

// A photo that excites both weights strongly pins them: λ barely moves the
// BRDF. The same photo with one direction hardly excited (eigenvalue 10⁻²
// against 10²) leaves that direction to the prior, and the BRDF follows λ.
TEST(PriorSensitivity, GrowsWhereThePhotoHardlyExcitesADirection) {
  const Eigen::Vector2d w(0.3, 0.7);
  const Eigen::MatrixXd metric = Eigen::MatrixXd::Identity(2, 2);
  Eigen::MatrixXd strong = 100 * Eigen::MatrixXd::Identity(2, 2), weak = strong;
  weak(1, 1) = 0.01;
  const double s_strong =
      PriorSensitivity(FactorClasses(Factors(strong), {{0, 1}})[0], ObservationOf(strong, w), 0.01, metric);
  const double s_weak =
      PriorSensitivity(FactorClasses(Factors(weak), {{0, 1}})[0], ObservationOf(weak, w), 0.01, metric);
  EXPECT_LT(s_strong, 0.01);
  EXPECT_GT(s_weak, 10 * s_strong);
}

// A class held tridiagonal against the definition, solved densely: w(λ) =
// μ' + (G + λ_j I)⁻¹ (z − G μ') at λ, λ/10 and max(10λ, 10⁻⁴), the moves
// measured in the metric relative to w, for a full-rank Gram matrix of
// eigenvalues spread over eight decades.
TEST(PriorSensitivity, ATridiagonalClassMatchesTheDenseDefinition) {
  const int k = 10;
  std::mt19937 rng(12);
  std::normal_distribution<double> g;
  Eigen::MatrixXd A(k, k), B(k, k);
  for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = g(rng), B(i) = g(rng);
  const Eigen::MatrixXd U = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ();
  Eigen::VectorXd ev(k);
  for (int i = 0; i < k; ++i) ev[i] = std::pow(10.0, -8.0 + 8.0 * i / (k - 1));
  const Eigen::MatrixXd G = U * ev.asDiagonal() * U.transpose();
  const Eigen::MatrixXd metric = B * B.transpose() + Eigen::MatrixXd::Identity(k, k);
  Eigen::VectorXd w(k);
  for (int i = 0; i < k; ++i) w[i] = 0.1 + 0.05 * i;
  const Observation obs = ObservationOf(G, w);
  std::vector<int> J(k);
  for (int i = 0; i < k; ++i) J[i] = i;
  const ClassSpectrum tri = FactorClasses(Factors(G), {J}, SpectrumParts::kTridiagonal)[0];
  ASSERT_TRUE(tri.tridiagonal());
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(k, 1.0 / k);
  const auto fit = [&](double lambda) {
    Eigen::MatrixXd H = G;
    H.diagonal().array() += lambda * obs.norm2[0] / k;
    return Eigen::VectorXd(prior + H.llt().solve(obs.z[0] - G * prior));
  };
  for (double lambda : {0.01, 1e-5, 0.0}) {
    const Eigen::VectorXd w0 = fit(lambda), down = fit(lambda / 10) - w0, up = fit(std::max(10 * lambda, 1e-4)) - w0;
    const double n2 = w0.dot(metric * w0);
    const double want = std::sqrt(down.dot(metric * down) / n2 + up.dot(metric * up) / n2);
    EXPECT_GT(want, 1e-6) << "λ " << lambda;
    EXPECT_NEAR(PriorSensitivity(tri, obs, lambda, metric), want, 1e-7 * want) << "λ " << lambda;
  }
}

// λ = 0 has no decade below it; its step up is to 10⁻⁴, the grid's scale, so
// the sensitivity of an unregularised fit is still measured.
TEST(PriorSensitivity, ZeroLambdaStepsUpToTheGridsScale) {
  const Eigen::MatrixXd G = Eigen::MatrixXd::Identity(1, 1);
  const ClassSpectrum cls = FactorClasses(Factors(G), {{0}})[0];
  Observation obs;
  for (int c = 0; c < 3; ++c) obs.z[c] = Eigen::VectorXd::Constant(1, 2.0), obs.norm2[c] = 4;
  const double w = 2, up = 1 + 1 / (1 + 4e-4);
  EXPECT_NEAR(PriorSensitivity(cls, obs, 0, G), std::abs(up - w) / w, 1e-12);
}

// A blend of two parts of the one-basis class above, at λ = 0.1 (weight
// 0.75, held-out error 0.02) and at λ = 0 (weight 0.25, held-out error 0.04):
// each part's predicted relit error is its held-out error plus its own
// sensitivity (the closed forms above), and the fit's are the weighted means.
TEST(ConfidenceOf, AddsEachPartsSensitivityToItsHeldOutErrorAndWeighsTheParts) {
  const Eigen::MatrixXd G = Eigen::MatrixXd::Identity(1, 1);
  const ClassSpectrum cls = FactorClasses(Factors(G), {{0}})[0];
  Observation obs;
  for (int c = 0; c < 3; ++c) obs.z[c] = Eigen::VectorXd::Constant(1, 2.0), obs.norm2[c] = 4;
  const double w = 1 + 1 / 1.4;
  const double s_a = std::hypot((1 + 1 / 1.04 - w) / w, (1 + 1 / 5.0 - w) / w);
  const double s_b = std::abs(1 + 1 / (1 + 4e-4) - 2) / 2;
  LambdaChoice choice;
  // The parts' own sensitivities are the penalty's, in another metric: not used.
  choice.parts = {{0, 0.1, 0.75, 0, 123.0, 0.02}, {0, 0.0, 0.25, 0, 456.0, 0.04}};
  int asked = 0;
  const FitConfidence conf = ConfidenceOf({choice}, {cls}, obs, [&](int j) {
    EXPECT_EQ(j, 0);
    ++asked;
    return Eigen::MatrixXd(3.0 * G);
  });
  EXPECT_EQ(asked, 2);
  ASSERT_EQ(conf.part_predicted_relit_error.size(), 2u);
  EXPECT_NEAR(conf.part_predicted_relit_error[0], 0.02 + s_a, 1e-12);
  EXPECT_NEAR(conf.part_predicted_relit_error[1], 0.04 + s_b, 1e-12);
  EXPECT_NEAR(conf.prior_sensitivity, 0.75 * s_a + 0.25 * s_b, 1e-12);
  EXPECT_NEAR(conf.predicted_relit_error, 0.75 * (0.02 + s_a) + 0.25 * (0.04 + s_b), 1e-12);
  EXPECT_THROW(ConfidenceOf(LambdaChoice{}, {cls}, obs, [&](int) { return Eigen::MatrixXd(G); }), std::exception);
}

// Every bin (stride 1) gives database.h's GramMatrix with the cosine weights
// over the chosen columns; every 7th bin, the same sum over those bins alone
// (to float precision: GramMatrix sums each block of bins in float).
TEST(SampledCosineGram, IsTheCosineWeightedGramOverTheSampledBins) {
  const MerlGrid grid{6, 6, 12};
  MatrixXfR B(static_cast<Eigen::Index>(grid.size()), 5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    for (Eigen::Index j = 0; j < B.cols(); ++j) B(i, j) = u(rng);
  const std::vector<float> w = grid.CosineWeightTable();
  const std::vector<int> members = {4, 1, 2};
  const Eigen::MatrixXd full = GramMatrix(B, &w);
  EXPECT_LT((SampledCosineGram(B, grid, members, 1) - full(members, members)).norm(), 1e-5 * full.norm());
  MatrixXfR every7((B.rows() + 6) / 7, B.cols());
  std::vector<float> w7;
  for (Eigen::Index i = 0; i < B.rows(); i += 7) every7.row(i / 7) = B.row(i), w7.push_back(w[i]);
  const Eigen::MatrixXd sampled = GramMatrix(every7, &w7);
  EXPECT_LT((SampledCosineGram(B, grid, members, 7) - sampled(members, members)).norm(), 1e-5 * sampled.norm());
}

// A constant BRDF ρ = 1 (a Lambertian of albedo π) under a unit sun l shows
// radiance max(0, n·l) on the sphere, so the image Gram is ∫_disk max(0, n·l)² dA:
// for l = v, ∫ (1 − r²) dA = π/2; for l straight up, ∫_{y>0} y² dA = π/8.
// A second basis twice the first gives the matrix's other entries exactly.
TEST(DirectionalImageGram, AConstantBrdfMatchesTheClosedForms) {
  const MerlGrid grid{6, 6, 12};
  MatrixXfR B(static_cast<Eigen::Index>(grid.size()), 2);
  B.col(0).setOnes();
  B.col(1).setConstant(2);
  const Eigen::MatrixXd facing = DirectionalImageGram(B, grid, {Vec3(0, 0, 1)}, 400);
  EXPECT_NEAR(facing(0, 0), kPi / 2, 2e-3 * kPi / 2);
  EXPECT_NEAR(facing(0, 1), 2 * facing(0, 0), 1e-9);
  EXPECT_NEAR(facing(1, 0), 2 * facing(0, 0), 1e-9);
  EXPECT_NEAR(facing(1, 1), 4 * facing(0, 0), 1e-9);
  const Eigen::MatrixXd above = DirectionalImageGram(B, grid, {Vec3(0, 1, 0)}, 400);
  EXPECT_NEAR(above(0, 0), kPi / 8, 1e-2 * kPi / 8);
  // Suns add: both together are the sum of each alone.
  const Eigen::MatrixXd both = DirectionalImageGram(B, grid, {Vec3(0, 0, 1), Vec3(0, 1, 0)}, 400);
  EXPECT_NEAR(both(0, 0), facing(0, 0) + above(0, 0), 1e-9);
}

// Radiance is read where the sun and the view put it: a table that is zero
// except in the first θ_h cell (θ_h < (1/4)² · 90° ≈ 5.6°, the mirror
// direction) lights only the normals within that angle of the half vector.
// Seen head-on (sun at the view) they cover a disk of radius ≤ sin 5.6° lit
// at cos θ_i ≈ 1. With the sun straight up the half vector is 45° from the
// view: the same cone of normals, foreshortened by cos 45° on the raster and
// lit at cos θ_i = cos 45°, gives (cos 45°)³ of the head-on integral.
TEST(DirectionalImageGram, ReadsTheTableAtEachPixelsHalfVector) {
  const MerlGrid grid{4, 6, 12};
  MatrixXfR B = MatrixXfR::Zero(static_cast<Eigen::Index>(grid.size()), 1);
  for (int j = 0; j < grid.n_td; ++j)
    for (int k = 0; k < grid.n_pd; ++k) B(static_cast<Eigen::Index>(grid.Index(0, j, k)), 0) = 1;
  const double head_on = DirectionalImageGram(B, grid, {Vec3(0, 0, 1)}, 400)(0, 0);
  const double radius = std::sin(kPi / 2 / 16);
  EXPECT_GT(head_on, 0.05 * kPi * radius * radius);
  EXPECT_LT(head_on, kPi * radius * radius);
  const double above = DirectionalImageGram(B, grid, {Vec3(0, 1, 0)}, 400)(0, 0);
  EXPECT_NEAR(above / head_on, std::pow(std::sqrt(0.5), 3), 0.03);
}

TEST(ConfidenceSuns, AreUnitVectorsAboveTheHorizonFrontSideAndBack) {
  const std::vector<Vec3> suns = ConfidenceSuns();
  ASSERT_EQ(suns.size(), 8u);
  bool front = false, back = false;
  for (const Vec3& s : suns) {
    EXPECT_NEAR(Length(s), 1, 1e-12);
    EXPECT_GT(s.y, 0.4);
    front = front || s.z > 0.4;
    back = back || s.z < -0.4;
  }
  EXPECT_TRUE(front && back);
}

}  // namespace brdfshot
