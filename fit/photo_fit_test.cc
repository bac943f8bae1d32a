#include "fit/photo_fit.h"

#include <gtest/gtest.h>

#include <random>

namespace brdfshot {

namespace {
// Twelve bases in two classes on a 32-px sphere; each basis image a random
// smooth function of the normal plus a little texture (full column rank).
struct Scene {
  BasisImages basis;
  ClassModel model;
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
    const PhotoFit fit = FitPhoto(s.basis, s.model, y, opt);
    EXPECT_EQ(fit.fit.chosen, 1);
    EXPECT_EQ(fit.choice.chosen_class, 1);
    EXPECT_LT(fit.relative_residual, 0.01);
    EXPECT_LT(fit.choice.predicted_error, 0.02) << "noise-free data in the span must predict well";
    EXPECT_LT((fit.reconstruction - y).norm(), 0.01 * y.norm());
    EXPECT_TRUE(fit.fit.weights().topRows(6).isZero()) << "weights outside the class stay zero";
  }
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
  const PhotoFit a = FitPhoto(s.basis, s.model, clean, PhotoFitOptions{});
  const PhotoFit b = FitPhoto(s.basis, s.model, noisy, PhotoFitOptions{});
  EXPECT_GT(b.choice.lambda, a.choice.lambda);
  EXPECT_GT(b.choice.predicted_error, 5 * a.choice.predicted_error);
  // With the noise, the fit stays nearer the truth than the noisy photo is.
  EXPECT_LT((b.reconstruction - clean).norm(), 0.5 * (noisy - clean).norm());
}

}  // namespace brdfshot
