#include "fit/joint_photos.h"

#include <gtest/gtest.h>

#include <random>

#include "fit/photo_fit.h"
#include "fit/test_databases.h"
#include "util/check.h"

namespace brdfshot {

namespace {

BasisImages Scene(std::mt19937& rng, int twin_of, int twin) {
  BasisImages b;
  b.geometry = OrthographicSphere(24, 80);
  b.Y = RandomBasisImages(b.geometry, 12, rng);
  for (auto& y : b.Y) y.col(twin) = y.col(twin_of);  // this probe cannot tell the two bases apart
  b.header = {{"probe", "p.exr"}, {"probe_name", "p"}, {"database_kind", "standin"}, {"grid", {1, 1, 1}},
              {"bases", std::vector<std::string>(12, "b")}};
  return b;
}

Eigen::MatrixXd Render(const BasisImages& b, const Eigen::MatrixXd& w) {
  Eigen::MatrixXd y(b.Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = b.Y[c].cast<double>() * w.col(c);
  return y;
}

double RelativeRmse(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

}  // namespace

// Probe A cannot tell bases 0 and 1 apart, probe B bases 2 and 3: one photo
// under either leaves the material undetermined and relights a third probe
// wrongly; the two photos fitted jointly determine it and relight it exactly.
TEST(JointPhotos, TwoPhotosDetermineWhatNeitherDoesAlone) {
  std::mt19937 rng(11);
  const BasisImages a = Scene(rng, 0, 1), c = Scene(rng, 5, 5);
  BasisImages b = Scene(rng, 2, 3);
  for (auto& y : b.Y) y *= 1e-3f;  // probe B a thousandth as bright: the scaling gives its photo equal weight
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(12, 3);
  w.topRows(4) << 0.5, 0.2, 0.1, 0.1, 0.4, 0.3, 0.3, 0.1, 0.2, 0.2, 0.3, 0.4;
  ClassModel model;
  model.mix = Eigen::VectorXd::Ones(1);
  model.label.assign(12, 0);
  PhotoFitOptions opt;
  opt.lambda.rule = "fixed";
  opt.lambda.fixed = 0;
  opt.constraint = WeightConstraint::Kind::kNone;
  const Eigen::MatrixXd ya = Render(a, w), yb = Render(b, w);
  const JointPhotos j = StackPhotos({a, b}, {ya, yb}, {"a.bsbi", "b.bsbi"}, opt.folds);
  ASSERT_EQ(j.pixels, (std::vector<size_t>{a.geometry.size(), b.geometry.size()}));
  EXPECT_NEAR(j.y.topRows(ya.rows()).squaredNorm() / (3.0 * ya.rows()), 1.0, 1e-9) << "each photo scaled to RMS 1";
  EXPECT_NEAR(j.y.bottomRows(yb.rows()).squaredNorm() / (3.0 * yb.rows()), 1.0, 1e-9);
  EXPECT_LT(RelativeRmse(Render(j.basis, w), j.y), 1e-6) << "each photo's basis images are scaled with it";
  EXPECT_EQ(j.fold_of_pixel.size(), ya.rows() + yb.rows());

  const PhotoFit joint = FitPhoto(j.basis, model, j.y, opt, nullptr, &j.fold_of_pixel);
  const PhotoFit only_a = FitPhoto(a, model, ya, opt), only_b = FitPhoto(b, model, yb, opt);
  const Eigen::MatrixXd truth_c = Render(c, w);
  const double e_joint = RelativeRmse(Render(c, joint.weights), truth_c);
  const double e_a = RelativeRmse(Render(c, only_a.weights), truth_c);
  const double e_b = RelativeRmse(Render(c, only_b.weights), truth_c);
  EXPECT_LT(e_joint, 1e-4);
  EXPECT_GT(e_a, 100 * e_joint + 1e-3) << "one photo under A leaves bases 0 and 1 apart undetermined";
  EXPECT_GT(e_b, 100 * e_joint + 1e-3);
}

TEST(JointPhotos, BasisImagesOfAnotherDatabaseAreRefusedByName) {
  std::mt19937 rng(12);
  const BasisImages a = Scene(rng, 0, 1);
  BasisImages b = Scene(rng, 2, 3);
  b.header["bases"][4] = "other";
  const Eigen::MatrixXd y = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(a.geometry.size()), 3);
  try {
    StackPhotos({a, b}, {y, y}, {"a.bsbi", "b.bsbi"}, 6);
    ADD_FAILURE() << "other bases are refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.bsbi"), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot
