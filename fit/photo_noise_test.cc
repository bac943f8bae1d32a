#include "fit/photo_noise.h"

#include <gtest/gtest.h>

#include <random>

namespace brdfshot {
namespace {

// A disc of pixels (the shape of a sphere's photo) and a photo on it.
PixelGeometry Disc(int radius) {
  PixelGeometry g;
  g.width = g.height = 2 * radius + 1;
  for (int y = 0; y <= 2 * radius; ++y)
    for (int x = 0; x <= 2 * radius; ++x)
      if ((x - radius) * (x - radius) + (y - radius) * (y - radius) <= radius * radius) g.x.push_back(x), g.y.push_back(y);
  return g;
}

// Shading quadratic along each axis with a bilinear term: the kernel
// [1 −2 1] ⊗ [1 −2 1] is zero on it, so only the added noise is measured.
Eigen::MatrixXd Smooth(const PixelGeometry& g) {
  Eigen::MatrixXd y(g.size(), 3);
  for (size_t i = 0; i < g.size(); ++i) {
    const double u = g.x[i] / 40.0, v = g.y[i] / 40.0;
    for (int c = 0; c < 3; ++c) y(i, c) = (1.0 + c) * (2.0 + u - 0.5 * v + 0.3 * u * u - 0.2 * v * v + 0.1 * u * v);
  }
  return y;
}

double Rms(const Eigen::MatrixXd& y) { return std::sqrt(y.squaredNorm() / static_cast<double>(y.size())); }

TEST(PhotoNoise, ANoiseFreeSmoothPhotoReadsZero) {
  const PixelGeometry g = Disc(40);
  EXPECT_LT(RelativePixelNoise(g, Smooth(g)), 1e-12);
}

TEST(PhotoNoise, GaussianNoiseIsMeasuredAtItsStandardDeviation) {
  const PixelGeometry g = Disc(40);
  for (double sigma : {0.001, 0.01, 0.1}) {
    Eigen::MatrixXd y = Smooth(g);
    const double rms = Rms(y);
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0, sigma);
    for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] += n(rng);
    // ~5000 pixels × 3 channels: the median's spread is a few per cent.
    EXPECT_NEAR(RelativePixelNoise(g, y), sigma / Rms(y), 0.06 * sigma / rms) << sigma;
  }
}

TEST(PhotoNoise, ScalingThePhotoLeavesItsRelativeNoiseAsItIs) {
  const PixelGeometry g = Disc(30);
  Eigen::MatrixXd y = Smooth(g);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 0.02);
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] += n(rng);
  EXPECT_NEAR(RelativePixelNoise(g, 250.0 * y), RelativePixelNoise(g, y), 1e-12);
}

TEST(PhotoNoise, IsolatedHighlightsDoNotReadAsNoise) {
  // A few saturated pixels (a specular highlight) on a clean photo: the
  // median response ignores them, a mean would not.
  const PixelGeometry g = Disc(40);
  Eigen::MatrixXd y = Smooth(g);
  for (size_t i = 0; i < g.size(); i += 97) y.row(i).array() += 50.0;
  EXPECT_LT(RelativePixelNoise(g, y), 1e-12);
}

// Fine detail everywhere (a one-pixel checkerboard of ±10 % on the shading)
// reads as noise on the photo; what a fit that holds the detail leaves is the
// noise alone, relative to the photo's RMS.
TEST(PhotoNoise, WhatAFitLeavesReadsTheNoiseWithoutTheDetail) {
  const PixelGeometry g = Disc(40);
  Eigen::MatrixXd clean = Smooth(g);
  for (size_t i = 0; i < g.size(); ++i) clean.row(static_cast<Eigen::Index>(i)) *= (g.x[i] + g.y[i]) % 2 ? 1.1 : 0.9;
  const double sigma = 0.005;
  Eigen::MatrixXd y = clean;
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, sigma);
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] += n(rng);
  const double truth = sigma / Rms(y);
  EXPECT_GT(RelativePixelNoise(g, y), 10 * truth);
  EXPECT_NEAR(ResidualPixelNoise(g, y, clean), truth, 0.06 * truth);
  EXPECT_LT(ResidualPixelNoise(g, y, y), 1e-12);
  EXPECT_EQ(ResidualPixelNoise(g, Eigen::MatrixXd::Zero(y.rows(), 3), Eigen::MatrixXd::Zero(y.rows(), 3)),
            kUnknownNoise);
}

TEST(PhotoNoise, BlackOrTooSmallPhotosReadUnknownAndGetTheCautiousBound) {
  const PixelGeometry g = Disc(10);
  EXPECT_EQ(RelativePixelNoise(g, Eigen::MatrixXd::Zero(g.size(), 3)), kUnknownNoise);
  const PixelGeometry line = [] {
    PixelGeometry l;
    for (int x = 0; x < 20; ++x) l.x.push_back(x), l.y.push_back(0);
    return l;
  }();
  EXPECT_EQ(RelativePixelNoise(line, Eigen::MatrixXd::Ones(20, 3)), kUnknownNoise);
  EXPECT_EQ(ConditionBoundForNoise(kUnknownNoise), NoiseBoundOptions{}.min_bound);
}

TEST(PhotoNoise, TheBoundIsTheMarginOverTheNoiseSquaredWithinItsRange) {
  NoiseBoundOptions o;
  o.margin = 2, o.min_bound = 1e3, o.max_bound = 1e9;
  EXPECT_DOUBLE_EQ(ConditionBoundForNoise(1e-3, o), 4e6);
  EXPECT_DOUBLE_EQ(ConditionBoundForNoise(2e-2, o), 1e4);
  EXPECT_DOUBLE_EQ(ConditionBoundForNoise(1.0, o), 1e3);   // clamped below
  EXPECT_DOUBLE_EQ(ConditionBoundForNoise(1e-6, o), 1e9);  // clamped above
  EXPECT_DOUBLE_EQ(ConditionBoundForNoise(0.0, o), 1e9);   // noise-free
  // A noisier photo is never trusted further.
  EXPECT_LT(ConditionBoundForNoise(2e-3, o), ConditionBoundForNoise(1e-3, o));
}

}  // namespace
}  // namespace brdfshot
