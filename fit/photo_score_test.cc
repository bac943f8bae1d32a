#include "fit/photo_score.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "util/check.h"

namespace brdfshot {

TEST(ComparePrediction, ClosedFormsOfTheErrorAndTheBestScale) {
  Eigen::MatrixXd y = Eigen::MatrixXd::Ones(4, 3);
  Eigen::MatrixXd p = y;
  p(2, 1) += 0.3;  // one value off by 0.3 over 12 values of 1
  PredictionError e = ComparePrediction(y, p);
  EXPECT_NEAR(e.relative_rmse, 0.3 / std::sqrt(12.0), 1e-12);
  // Best scale s = ⟨p, y⟩ / ⟨p, p⟩ = 12.3 / (11 + 1.3²).
  const double s = 12.3 / (11 + 1.69);
  EXPECT_NEAR(e.scale, s, 1e-12);
  EXPECT_NEAR(e.relative_rmse_scaled, std::sqrt((11 * (s - 1) * (s - 1) + (1.3 * s - 1) * (1.3 * s - 1)) / 12), 1e-12);
  EXPECT_LT(e.relative_rmse_scaled, e.relative_rmse);

  e = ComparePrediction(y, 2 * y);  // twice too bright: error 1, nothing left after scaling by 1/2
  EXPECT_NEAR(e.relative_rmse, 1.0, 1e-12);
  EXPECT_NEAR(e.scale, 0.5, 1e-12);
  EXPECT_NEAR(e.relative_rmse_scaled, 0.0, 1e-12);

  e = ComparePrediction(y, Eigen::MatrixXd::Zero(4, 3));  // a black prediction misses everything
  EXPECT_NEAR(e.relative_rmse, 1.0, 1e-12);
  EXPECT_EQ(e.scale, 1.0);

  EXPECT_THROW(ComparePrediction(Eigen::MatrixXd::Zero(4, 3), y), Error);  // nothing to score against
  EXPECT_THROW(ComparePrediction(y, Eigen::MatrixXd::Ones(5, 3)), Error);
}

namespace {
// Four bases under two lightings: the basis images of the photo held out.
BasisImages HeldOutBasis(unsigned seed, bool with_lobes) {
  BasisImages b;
  b.geometry = OrthographicSphere(16, 80);
  const Eigen::Index P = static_cast<Eigen::Index>(b.geometry.size());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const LambertGgxLobes lobes;
  for (int c = 0; c < 3; ++c) {
    b.Y[c] = MatrixXfR::NullaryExpr(P, 4, [&]() { return u(rng); });
    if (with_lobes) b.lobes[c] = MatrixXfR::NullaryExpr(P, lobes.columns(), [&]() { return u(rng); });
  }
  b.header = {{"database", "test db"}, {"grid", {9, 9, 18}}, {"bases", {"a", "b", "c", "d"}}};
  if (with_lobes) b.header["lobes"] = lobes.ToJson();
  return b;
}
}  // namespace

TEST(ScoreFitOnPhoto, TheFitsBasesAreFoundByNameAndAWrongWeightShowsAsItsOwnImage) {
  const BasisImages basis = HeldOutBasis(3, true);
  const Eigen::MatrixXd w_true = (Eigen::MatrixXd(4, 3) << 0.2, 0.3, 0.1,  // a
                                  0.0, 0.1, 0.4,                           // b
                                  0.5, 0.2, 0.2,                           // c
                                  0.1, 0.0, 0.3)                           // d
                                     .finished();
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(basis.Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < 4; ++j) y.col(c) += w_true(j, c) * basis.Y[c].col(j).cast<double>();

  // The record lists its bases in another order than the basis images.
  FitRecord fit;
  fit.database = "test db";
  fit.grid = MerlGrid{9, 9, 18};
  fit.bases = {"d", "a", "c", "b"};
  fit.weights.resize(4, 3);
  const int order[4] = {3, 0, 2, 1};
  for (int i = 0; i < 4; ++i) fit.weights.row(i) = w_true.row(order[i]);
  PhotoScore s = ScoreFitOnPhoto(fit, "fit.json", basis, "held.bsbi", y, "held.exr");
  EXPECT_EQ(s.pixels, basis.geometry.size());
  EXPECT_LT(s.fit.relative_rmse, 1e-6);
  EXPECT_FALSE(s.lambert_ggx.has_value());  // the record holds no baseline

  // c's green weight 0.1 too high: the prediction is off by 0.1 × c's green image.
  fit.weights(2, 1) += 0.1;
  s = ScoreFitOnPhoto(fit, "fit.json", basis, "held.bsbi", y, "held.exr");
  EXPECT_NEAR(s.fit.relative_rmse, 0.1 * basis.Y[1].col(2).cast<double>().norm() / y.norm(), 1e-6);
}

TEST(ScoreFitOnPhoto, TheAnalyticBaselineIsScoredOnTheSameLobesOnly) {
  const BasisImages basis = HeldOutBasis(4, true);
  FitRecord fit;
  fit.database = "test db";
  fit.grid = MerlGrid{9, 9, 18};
  fit.bases = {"a", "b", "c", "d"};
  fit.weights = Eigen::MatrixXd::Constant(4, 3, 0.25);
  LambertGgxFit lggx;
  lggx.weights = Eigen::MatrixXd::Zero(fit.lobes.columns(), 3);
  lggx.weights.row(0).setConstant(0.5);  // the diffuse lobe
  lggx.weights.row(7).setConstant(0.1);  // one specular lobe
  fit.lambert_ggx = lggx;
  Eigen::MatrixXd y(basis.Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c)
    y.col(c) = 0.5 * basis.lobes[c].col(0).cast<double>() + 0.1 * basis.lobes[c].col(7).cast<double>();
  const PhotoScore s = ScoreFitOnPhoto(fit, "fit.json", basis, "held.bsbi", y, "held.exr");
  ASSERT_TRUE(s.lambert_ggx.has_value());
  EXPECT_LT(s.lambert_ggx->relative_rmse, 1e-6);
  EXPECT_GT(s.fit.relative_rmse, 0.01);  // the weights are not those of this photo

  fit.lobes.alphas.pop_back();  // lobes other than the basis images': not comparable
  EXPECT_FALSE(ScoreFitOnPhoto(fit, "fit.json", basis, "held.bsbi", y, "held.exr").lambert_ggx.has_value());
}

TEST(ScoreFitOnPhoto, ErrorsNameTheBasisFileAndTheMismatch) {
  const BasisImages basis = HeldOutBasis(5, false);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Ones(basis.Y[0].rows(), 3);
  FitRecord fit;
  fit.database = "test db";
  fit.grid = MerlGrid{9, 9, 18};
  fit.bases = {"a", "e"};
  fit.weights = Eigen::MatrixXd::Ones(2, 3);
  auto message = [&](const FitRecord& f, const Eigen::MatrixXd& photo) {
    try {
      ScoreFitOnPhoto(f, "fit.json", basis, "held.bsbi", photo, "held.exr");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(fit, y).find("held.bsbi: has no basis image of the fit's basis e"), std::string::npos)
      << message(fit, y);
  fit.bases = {"a", "b"};
  EXPECT_EQ(message(fit, y), "no error");
  EXPECT_NE(message(fit, Eigen::MatrixXd::Ones(3, 3)).find("held.bsbi: has"), std::string::npos);
  EXPECT_NE(message(fit, Eigen::MatrixXd::Zero(y.rows(), 3)).find("held.exr: is black"), std::string::npos);
  FitRecord other = fit;
  other.database = "another db";
  EXPECT_NE(message(other, y).find("fitted with \"another db\""), std::string::npos) << message(other, y);
  other = fit;
  other.grid = MerlGrid{90, 90, 180};
  EXPECT_NE(message(other, y).find("another grid"), std::string::npos) << message(other, y);
}

}  // namespace brdfshot
