#include "fit/fit_confidence.h"

#include <gtest/gtest.h>

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
  const std::vector<float> w = CosineWeights(grid);
  const std::vector<int> members = {4, 1, 2};
  const Eigen::MatrixXd full = GramMatrix(B, &w);
  EXPECT_LT((SampledCosineGram(B, grid, members, 1) - full(members, members)).norm(), 1e-5 * full.norm());
  MatrixXfR every7((B.rows() + 6) / 7, B.cols());
  std::vector<float> w7;
  for (Eigen::Index i = 0; i < B.rows(); i += 7) every7.row(i / 7) = B.row(i), w7.push_back(w[i]);
  const Eigen::MatrixXd sampled = GramMatrix(every7, &w7);
  EXPECT_LT((SampledCosineGram(B, grid, members, 7) - sampled(members, members)).norm(), 1e-5 * sampled.norm());
}

}  // namespace brdfshot
