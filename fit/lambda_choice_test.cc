#include "fit/lambda_choice.h"

#include <gtest/gtest.h>

#include <functional>
#include <map>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>

#include "fit/fit_confidence.h"
#include "fit/photo_fit.h"
#include "util/check.h"

namespace brdfshot {

namespace {
struct Scene {
  PixelGeometry g;
  std::array<MatrixXfR, 3> Y;
};
// A 24-px orthographic sphere with smooth random "basis images": each basis is
// a random quadratic in the normal, so neighbouring pixels are correlated as
// real ones are.
Scene MakeScene(int n, uint32_t seed) {
  Scene s;
  s.g = OrthographicSphere(24, 80);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.2, 1.0);
  for (int c = 0; c < 3; ++c) {
    s.Y[c].resize(static_cast<Eigen::Index>(s.g.size()), n);
    for (int j = 0; j < n; ++j) {
      const double a = u(rng), bx = u(rng) - 0.6, by = u(rng) - 0.6, bz = u(rng), q = u(rng) - 0.6;
      for (size_t p = 0; p < s.g.size(); ++p) {
        const Vec3& m = s.g.normal[p];
        s.Y[c](static_cast<Eigen::Index>(p), j) =
            static_cast<float>(a + bx * m.x + by * m.y + bz * m.z + q * m.x * m.y);
      }
    }
  }
  return s;
}
Eigen::MatrixXd Render(const Scene& s, const Eigen::MatrixXd& w) {
  Eigen::MatrixXd y(s.Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = s.Y[c].cast<double>() * w.col(c);
  return y;
}
// A scene's wedges, factors and the folds' systems of `members`.
struct Folded {
  std::vector<int> fold;
  std::array<ChannelFactor, 3> f;
  CvSystem cv;
};
Folded FoldScene(const Scene& s, const std::vector<std::vector<int>>& members, int K) {
  Folded x;
  x.fold = WedgeFolds(s.g, K);
  x.f = FactorBasisImages(s.Y);
  x.cv = FactorFolds(x.f, FoldGrams(s.Y, x.fold, K), members);
  return x;
}
// The render plus white Gaussian noise of standard deviation `sigma` per value.
Eigen::MatrixXd NoisyRender(const Scene& s, const Eigen::MatrixXd& w, double sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  Eigen::MatrixXd y = Render(s, w);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += noise(rng);
  return y;
}
// The wedges' held-out squared error of class `J` at λ, refitted on the
// other wedges' pixels directly (dense, QR on the training rows); each
// wedge's error relative to its ‖y‖² times the mean wedge's where `relative`.
// Wedge `prior_only`, if any, scores the prior's weights instead of a refit.
double DenseHeldOutError(const Scene& s, const Eigen::MatrixXd& y, const std::vector<int>& fold, int K,
                         const std::vector<int>& J, double lambda, bool relative, int prior_only = -1) {
  double error = 0;
  for (int k = 0; k < K; ++k) {
    std::vector<int> train, test;
    for (size_t p = 0; p < fold.size(); ++p) (fold[p] == k ? test : train).push_back(static_cast<int>(p));
    const double weight = relative ? y.squaredNorm() / K / y(test, Eigen::all).squaredNorm() : 1.0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::MatrixXd A = s.Y[c].cast<double>()(train, J);
      const Eigen::VectorXd b = y.col(c)(train);
      const double cj = static_cast<double>(J.size());
      const Eigen::VectorXd prior = Eigen::VectorXd::Constant(J.size(), 1.0 / cj);
      const Eigen::VectorXd wj = k == prior_only ? prior : SolveRidge(A, b, lambda * b.squaredNorm() / cj, prior);
      error += weight * (s.Y[c].cast<double>()(test, J) * wj - y.col(c)(test)).squaredNorm();
    }
  }
  return error;
}
}  // namespace

TEST(LambdaChoice, WedgesCoverTheSphereEvenlyAndTheirGramsAddUp) {
  const Scene s = MakeScene(8, 1);
  const std::vector<int> fold = WedgeFolds(s.g, 6);
  std::vector<int> count(6, 0);
  for (int k : fold) count[k]++;
  for (int k = 0; k < 6; ++k)  // a centred disc: six equal wedges, up to the pixel grid
    EXPECT_NEAR(count[k], s.g.size() / 6.0, 0.08 * s.g.size() / 6.0) << "wedge " << k;
  const auto f = FactorBasisImages(s.Y);
  const auto held = FoldGrams(s.Y, fold, 6);
  const auto of_folds = FactorOfFolds(held);
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(8, 8);
    for (const auto& h : held) sum += h[c];
    EXPECT_LT((sum - f[c].gram).norm(), 1e-9 * f[c].gram.norm());
    // and YᵀY in double, row by row, against the folds' sum
    Eigen::MatrixXd direct = Eigen::MatrixXd::Zero(8, 8);
    for (Eigen::Index p = 0; p < s.Y[c].rows(); ++p) {
      const Eigen::RowVectorXd row = s.Y[c].row(p).cast<double>();
      direct += row.transpose() * row;
    }
    EXPECT_LT((of_folds[c].gram - direct).norm(), 1e-9 * direct.norm());
    EXPECT_FALSE(of_folds[c].has_qr());
  }
}

TEST(LambdaChoice, FoldObservationsAreEachWedgesOwnProjection) {
  // Each wedge's z_c = Y_c(rows)ᵀ y_c(rows) and ‖y_c(rows)‖², against the
  // dense double product over the wedge's rows picked out one by one.
  const Scene s = MakeScene(7, 3);
  const int K = 5;
  const std::vector<int> fold = WedgeFolds(s.g, K);
  const Eigen::MatrixXd y = NoisyRender(s, Eigen::MatrixXd::Constant(7, 3, 0.2), 0.01, 4);
  const std::vector<Observation> held = FoldObservations(s.Y, y, fold, K);
  ASSERT_EQ(held.size(), static_cast<size_t>(K));
  for (int k = 0; k < K; ++k)
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd z = Eigen::VectorXd::Zero(7);
      double norm2 = 0;
      for (size_t p = 0; p < fold.size(); ++p) {
        if (fold[p] != k) continue;
        const Eigen::Index r = static_cast<Eigen::Index>(p);
        z += y(r, c) * s.Y[c].row(r).transpose().cast<double>();
        norm2 += y(r, c) * y(r, c);
      }
      EXPECT_LT((held[k].z[c] - z).norm(), 1e-12 * z.norm()) << "wedge " << k << " channel " << c;
      EXPECT_NEAR(held[k].norm2[c], norm2, 1e-12 * norm2);
    }
  std::vector<int> bad = fold;
  bad[0] = K;  // a wedge that does not exist
  EXPECT_THROW(FoldObservations(s.Y, y, bad, K), std::logic_error);
}
TEST(LambdaChoice, ProjectRowsByFoldIsProjectRowsOverEachFoldsRows) {
  // The same sums in the same order: equal to the bit, over the whole image
  // and over a range of its rows.
  const Scene s = MakeScene(7, 3);
  const int K = 5;
  const std::vector<int> fold = WedgeFolds(s.g, K);
  const Eigen::VectorXd y = NoisyRender(s, Eigen::MatrixXd::Constant(7, 3, 0.2), 0.01, 4).col(1);
  const Eigen::Index rows = s.Y[1].rows(), begin = rows / 3, end = 2 * rows / 3;
  const std::vector<Eigen::VectorXd> all = ProjectRowsByFold(s.Y[1], y, fold, K);
  const std::vector<Eigen::VectorXd> part = ProjectRowsByFold(s.Y[1], y, fold, K, begin, end);
  const std::vector<std::vector<int>> by_fold = RowsByFold(fold, K);
  ASSERT_EQ(all.size(), static_cast<size_t>(K));
  for (int k = 0; k < K; ++k) {
    ASSERT_FALSE(by_fold[k].empty());
    EXPECT_EQ(all[k], ProjectRows(s.Y[1], y, by_fold[k])) << "wedge " << k;
    std::vector<int> in_range;
    for (int r : by_fold[k])
      if (r >= begin && r < end) in_range.push_back(r);
    const Eigen::VectorXd expected =
        in_range.empty() ? Eigen::VectorXd::Zero(7) : ProjectRows(s.Y[1], y, in_range);
    EXPECT_EQ(part[k], expected) << "wedge " << k << " over rows " << begin << "–" << end;
  }
  std::vector<int> bad = fold;
  bad[0] = -1;
  EXPECT_THROW(ProjectRowsByFold(s.Y[1], y, bad, K), std::logic_error);
  EXPECT_THROW(ProjectRowsByFold(s.Y[1], y, fold, K, end, begin), std::logic_error);
}

TEST(LambdaChoice, CrossValidationScoreIsTheHeldOutErrorOfARefit) {
  // The score from the fold spectra must equal refitting on the other wedges'
  // pixels directly (dense, QR on the training rows) and measuring the wedge,
  // with the folds' Q formed or kept as reflectors, for a class of one basis
  // too; each wedge's error as it is, or relative to the wedge's ‖y‖² (times
  // the mean wedge's).
  const Scene s = MakeScene(10, 2);
  const int K = 4;
  Eigen::MatrixXd w = Eigen::MatrixXd::Constant(10, 3, 0.1);
  w(3, 0) = 0.7, w(6, 1) = 0.4;
  const Eigen::MatrixXd y = NoisyRender(s, w, 0.05, 7);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4}, {5, 6, 7, 8, 9}, {7}};
  const std::vector<int> fold = WedgeFolds(s.g, K);
  const std::array<ChannelFactor, 3> f = FactorBasisImages(s.Y);
  LambdaChoiceOptions opt;
  opt.rule = "cv";
  opt.grid = {0.001, 0.1, 1.0};
  opt.max_condition = 1e300;
  for (const bool relative : {false, true})
    for (const FoldQ q : {FoldQ::kFormed, FoldQ::kReflectors}) {
      SCOPED_TRACE(q == FoldQ::kFormed ? "Q formed" : "reflectors");
      SCOPED_TRACE(relative ? "relative wedges" : "wedges as they are");
      opt.relative_wedges = relative;
      const CvSystem cv = FactorFolds(f, FoldGrams(s.Y, fold, K), members, q);
      EXPECT_EQ(cv.train[0][0].Q[0].size() > 0, q == FoldQ::kFormed);
      const LambdaChoice ch = ChooseLambda(f, FactorClasses(f, members), &cv, MakeObservation(f, s.Y, y),
                                           FoldObservations(s.Y, y, fold, K), s.g.size(), opt);
      for (size_t j = 0; j < members.size(); ++j)
        for (size_t l = 0; l < opt.grid.size(); ++l) {
          const double want = DenseHeldOutError(s, y, fold, K, members[j], opt.grid[l], relative);
          EXPECT_NEAR(ch.score[j][l], want, 1e-7 * want) << "class " << j << " lambda " << opt.grid[l];
        }
    }
}

TEST(LambdaChoice, AWedgeSystemSingularAtOneLambdaLeavesTheOtherLambdasScoresAlone) {
  // A basis seen only inside wedge 0 leaves that wedge's training system
  // singular at λ = 0 (its row and column are zero), while the photo's own
  // system is not. That wedge then scores the prior alone at λ = 0, and the
  // grid's other λ, solved side by side with it, score as a dense refit does.
  Scene s = MakeScene(6, 5);
  const int K = 4;
  const std::vector<int> fold = WedgeFolds(s.g, K);
  for (int c = 0; c < 3; ++c)
    for (size_t p = 0; p < fold.size(); ++p)
      if (fold[p] != 0) s.Y[c](static_cast<Eigen::Index>(p), 5) = 0;
  const Eigen::MatrixXd y = NoisyRender(s, Eigen::MatrixXd::Constant(6, 3, 0.2), 0.05, 3);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5}};
  const Folded x = FoldScene(s, members, K);
  LambdaChoiceOptions opt;
  opt.rule = "cv";
  opt.grid = {0, 0.01, 1.0};
  opt.max_condition = 1e300;
  const LambdaChoice ch = ChooseLambda(x.f, FactorClasses(x.f, members), &x.cv, MakeObservation(x.f, s.Y, y),
                                       FoldObservations(s.Y, y, x.fold, K), s.g.size(), opt);
  for (size_t l = 0; l < opt.grid.size(); ++l) {
    const double want =
        DenseHeldOutError(s, y, x.fold, K, members[0], opt.grid[l], opt.relative_wedges, l == 0 ? 0 : -1);
    EXPECT_NEAR(ch.score[0][l], want, 1e-7 * want) << "lambda " << opt.grid[l];
  }
}

TEST(LambdaChoice, ADarkWedgeWeighsAsTheNoiseFloorItHolds) {
  // One wedge black, the others lit alike: the lit ones weigh the mean wedge's
  // ‖y‖² over their own, the black one as holding the floor's share.
  const Scene s = MakeScene(3, 4);
  const int K = 4;
  const std::vector<int> fold = WedgeFolds(s.g, K);
  Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(3, 3, 0.3));
  for (size_t p = 0; p < fold.size(); ++p)
    if (fold[p] == 2) y.row(static_cast<Eigen::Index>(p)).setZero();
  const auto f = FactorBasisImages(s.Y);
  const Observation obs = MakeObservation(f, s.Y, y);
  const std::vector<Observation> held = FoldObservations(s.Y, y, fold, K);
  const double relative_noise = 0.01;
  const LambdaChoiceOptions opt = ResolveConditionBound(LambdaChoiceOptions{}, relative_noise);
  EXPECT_EQ(opt.min_wedge_share, relative_noise * relative_noise) << "a wedge's noise holds ε² of the mean wedge";
  const std::vector<double> w = WedgeWeights(obs, held, opt);
  const double mean = y.squaredNorm() / K;
  ASSERT_EQ(w.size(), 4u);
  for (int k = 0; k < K; ++k) {
    std::vector<int> in;
    for (size_t p = 0; p < fold.size(); ++p)
      if (fold[p] == k) in.push_back(static_cast<int>(p));
    const double want = k == 2 ? 1 / opt.min_wedge_share : mean / y(in, Eigen::all).squaredNorm();
    EXPECT_NEAR(w[k], want, 1e-9 * want) << "wedge " << k;
  }
  // Each wedge as it is, and an unknown noise's cautious floor of a tenth.
  LambdaChoiceOptions plain = opt;
  plain.relative_wedges = false;
  for (double x : WedgeWeights(obs, held, plain)) EXPECT_EQ(x, 1);
  const LambdaChoiceOptions unknown = ResolveConditionBound(LambdaChoiceOptions{}, kUnknownNoise);
  EXPECT_NEAR(WedgeWeights(obs, held, unknown)[2], 10, 1e-9);
}

TEST(LambdaChoice, GcvScoreMatchesTheDenseHatMatrix) {
  const Scene s = MakeScene(6, 3);
  Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(6, 3, 0.3));
  y.array() += 0.02 * Eigen::ArrayXXd::Random(y.rows(), 3);
  const auto f = FactorBasisImages(s.Y);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5}};
  LambdaChoiceOptions opt;
  opt.rule = "gcv";
  opt.grid = {0.01, 0.3};
  opt.max_condition = 1e300;
  const Observation obs = MakeObservation(f, s.Y, y);
  const LambdaChoice ch = ChooseLambda(f, FactorClasses(f, members), nullptr, obs, {}, s.g.size(), opt);
  const double n = static_cast<double>(s.g.size());
  for (size_t l = 0; l < opt.grid.size(); ++l) {
    double want = 0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::MatrixXd A = s.Y[c].cast<double>();
      const double lj = opt.grid[l] * obs.norm2[c] / 6;
      const Eigen::MatrixXd inv = (A.transpose() * A + lj * Eigen::MatrixXd::Identity(6, 6)).inverse();
      const Eigen::VectorXd prior = Eigen::VectorXd::Constant(6, 1.0 / 6);
      const Eigen::VectorXd wl = prior + inv * A.transpose() * (y.col(c) - A * prior);
      const double rss = (A * wl - y.col(c)).squaredNorm();
      const double dof = (A * inv * A.transpose()).trace();
      want += n * rss / ((n - dof) * (n - dof));
    }
    EXPECT_NEAR(ch.score[0][l], want, 1e-8 * want) << "lambda " << opt.grid[l];
  }
}

TEST(LambdaChoice, ResidualScoreIsTheInSampleResidualOfTheDenseRidgeSolve) {
  const Scene s = MakeScene(8, 11);
  Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(8, 3, 0.2));
  y.array() += 0.03 * Eigen::ArrayXXd::Random(y.rows(), 3);
  const auto f = FactorBasisImages(s.Y);
  const std::vector<std::vector<int>> members = {{0, 1, 2}, {3, 4, 5, 6, 7}};
  LambdaChoiceOptions opt;
  opt.rule = "residual";
  opt.grid = {0, 0.01, 0.3};
  opt.max_condition = 1e300;
  const LambdaChoice ch =
      ChooseLambda(f, FactorClasses(f, members), nullptr, MakeObservation(f, s.Y, y), {}, s.g.size(), opt);
  for (size_t j = 0; j < members.size(); ++j)
    for (size_t l = 0; l < opt.grid.size(); ++l) {
      double want = 0;
      for (int c = 0; c < 3; ++c) {
        const Eigen::MatrixXd A = s.Y[c].cast<double>()(Eigen::all, members[j]);
        const double cj = static_cast<double>(members[j].size());
        const Eigen::VectorXd prior = Eigen::VectorXd::Constant(members[j].size(), 1.0 / cj);
        const Eigen::VectorXd wj = SolveRidge(A, y.col(c), opt.grid[l] * y.col(c).squaredNorm() / cj, prior);
        want += (A * wj - y.col(c)).squaredNorm();
      }
      EXPECT_NEAR(ch.score[j][l], want, 1e-7 * want) << "class " << j << " lambda " << opt.grid[l];
    }
}

// Rule residual takes, per class, the least λ the condition bound allows (the
// residual only grows with λ) and the class whose residual is least there; its
// predicted error is the wedges' held-out error of that one pick, the same
// number rule cv scores it with.
TEST(LambdaChoice, ResidualRuleTakesTheLeastLambdaWithinTheBoundAndTheWedgesScoreIt) {
  Scene s = MakeScene(6, 5);
  for (int c = 0; c < 3; ++c) s.Y[c].col(4) = s.Y[c].col(1) + 1e-5f * s.Y[c].col(2);  // almost collinear
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5}, {0, 3}};
  const auto f = FactorBasisImages(s.Y);
  const std::vector<int> fold = WedgeFolds(s.g, 4);
  const CvSystem cv = FactorFolds(f, FoldGrams(s.Y, fold, 4), members);
  // The prior plus noise: cross-validation asks for the largest λ here.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.2);
  Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(6, 3, 1.0 / 6));
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += noise(rng);
  const Observation obs = MakeObservation(f, s.Y, y);
  const std::vector<Observation> held = FoldObservations(s.Y, y, fold, 4);
  LambdaChoiceOptions opt;
  opt.grid = {0, 1e-6, 1e-2, 1, 100};
  opt.max_condition = 1e6;
  opt.rule = "residual";
  const LambdaChoice ch = ChooseLambda(f, FactorClasses(f, members), &cv, obs, held, s.g.size(), opt);
  EXPECT_TRUE(std::isinf(ch.score[0][0]) && std::isinf(ch.score[0][1])) << "beyond the bound";
  EXPECT_EQ(ch.chosen_class, 0) << "all six bases leave less residual than two";
  EXPECT_EQ(ch.lambda, 1e-2);
  opt.rule = "cv";
  const LambdaChoice by_cv = ChooseLambda(f, FactorClasses(f, members), &cv, obs, held, s.g.size(), opt);
  EXPECT_GT(by_cv.lambda, 1e-2);
  const double total = obs.norm2[0] + obs.norm2[1] + obs.norm2[2];
  EXPECT_NEAR(ch.predicted_error, std::sqrt(by_cv.score[0][2] / total), 1e-12);
}

// `n` basis images of full rank: a smooth quadratic in the normal plus an
// independent ripple per pixel, so that dozens of bases are not spanned by
// the quadratics' five parameters.
Scene MakeFullRankScene(int n, uint32_t seed) {
  Scene s = MakeScene(n, seed);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<float> ripple(-0.05f, 0.05f);
  for (int c = 0; c < 3; ++c)
    for (Eigen::Index i = 0; i < s.Y[c].size(); ++i) s.Y[c].data()[i] += ripple(rng);
  return s;
}

// The every-basis candidate of a leave-one-out fit, all bases but a few,
// solved on the factor of all bases with the left-out weights pinned to zero
// (the bordered system) scores every λ as its own tridiagonalisation does;
// so does a class whose left-out basis the others almost span, where the
// superset's system meets a singular pivot at λ = 0 and the class is
// factored on the spot.
TEST(LambdaChoice, AClassHeldOnItsSupersetsFactorScoresAsItsOwnFactor) {
  const int n = 40, K = 5;
  for (bool almost_spanned : {false, true}) {
    SCOPED_TRACE(almost_spanned ? "a left-out basis almost spanned" : "independent bases");
    Scene s = MakeFullRankScene(n, 21);
    if (almost_spanned)
      for (int c = 0; c < 3; ++c) s.Y[c].col(17) = s.Y[c].col(3) + 1e-6f * s.Y[c].col(30);
    std::vector<int> members;
    for (int i = 0; i < n; ++i)
      if (i != 5 && i != 17 && i != 18) members.push_back(i);
    const std::vector<std::vector<int>> classes = {members, {0, 1, 2, 3}};
    const auto f = FactorBasisImages(s.Y);
    const std::vector<int> fold = WedgeFolds(s.g, K);
    const auto fold_gram = FoldGrams(s.Y, fold, K);
    const std::vector<FoldClassFactor> all = FactorFoldsOfAll(f, fold_gram);
    const CvSystem own = FactorFolds(f, fold_gram, classes, FoldQ::kReflectors);
    const CvSystem held_on_all = FactorFolds(f, fold_gram, classes, FoldQ::kReflectors, &all);
    for (int k = 0; k < K; ++k) {
      EXPECT_TRUE(held_on_all.train[k][0].bordered());
      EXPECT_EQ(held_on_all.train[k][0].left_out, (std::vector<int>{5, 17, 18}));
      EXPECT_FALSE(held_on_all.train[k][1].bordered()) << "36 of 40 left out: factored on its own";
      EXPECT_FALSE(own.train[k][0].bordered());
    }
    Eigen::MatrixXd w = Eigen::MatrixXd::Constant(n, 3, 1.0 / n);
    w.row(7).setConstant(0.3), w.row(22).setConstant(-0.1);
    const Eigen::MatrixXd y = NoisyRender(s, w, 0.01, 4);
    LambdaChoiceOptions opt;
    opt.grid = {0, 1e-6, 1e-4, 1e-2, 1, 100};
    opt.max_condition = 1e300;
    const Observation obs = MakeObservation(f, s.Y, y);
    const std::vector<Observation> held = FoldObservations(s.Y, y, fold, K);
    const std::vector<ClassSpectrum> spectra = FactorClasses(f, classes);
    const LambdaChoice a = ChooseLambda(f, spectra, &own, obs, held, s.g.size(), opt);
    const LambdaChoice b = ChooseLambda(f, spectra, &held_on_all, obs, held, s.g.size(), opt);
    EXPECT_EQ(a.chosen_class, b.chosen_class);
    EXPECT_EQ(a.lambda, b.lambda);
    for (size_t j = 0; j < classes.size(); ++j)
      for (size_t l = 0; l < opt.grid.size(); ++l) {
        ASSERT_TRUE(std::isfinite(a.score[j][l])) << j << " " << l;
        EXPECT_NEAR(b.score[j][l], a.score[j][l], 1e-8 * a.score[j][l]) << "class " << j << ", λ " << opt.grid[l];
      }
  }
}

// A class the superset does not hold in order, or not within kMostLeftOut,
// is factored on its own.
TEST(LambdaChoice, OnlyAClassOfTheSupersetsMembersButAFewIsHeldOnIt) {
  const int n = 40, K = 3;
  const Scene s = MakeFullRankScene(n, 22);
  const auto f = FactorBasisImages(s.Y);
  const auto fold_gram = FoldGrams(s.Y, WedgeFolds(s.g, K), K);
  const std::vector<FoldClassFactor> all = FactorFoldsOfAll(f, fold_gram);
  std::vector<int> few_out, many_out, reordered;
  for (int i = 0; i < n; ++i) {
    if (i != 9) few_out.push_back(i);
    if (i >= kMostLeftOut + 1) many_out.push_back(i);
  }
  reordered = few_out;
  std::swap(reordered[0], reordered[1]);
  const CvSystem cv = FactorFolds(f, fold_gram, {few_out, many_out, reordered}, FoldQ::kReflectors, &all);
  EXPECT_TRUE(cv.train[0][0].bordered());
  EXPECT_EQ(cv.train[0][0].left_out, std::vector<int>{9});
  EXPECT_FALSE(cv.train[0][1].bordered());
  EXPECT_FALSE(cv.train[0][2].bordered());
  EXPECT_EQ(cv.train[0][2].diagonal[0].size(), n - 1) << "its own tridiagonal factor";
}

TEST(LambdaChoice, ExactDataPicksTheSmallestLambdaAndPriorPlusNoiseTheLargest) {
  const Scene s = MakeScene(8, 4);
  const std::vector<int> fold = WedgeFolds(s.g, 6);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5, 6, 7}};
  const auto f = FactorBasisImages(s.Y);
  const CvSystem cv = FactorFolds(f, FoldGrams(s.Y, fold, 6), members);
  LambdaChoiceOptions opt;
  opt.grid = {1e-4, 1e-2, 1.0, 100.0};
  opt.max_condition = 1e300;
  for (const char* rule : {"cv", "gcv"}) {
    SCOPED_TRACE(rule);
    opt.rule = rule;
    auto choose = [&](const Eigen::MatrixXd& y) {
      return ChooseLambda(f, FactorClasses(f, members), &cv, MakeObservation(f, s.Y, y),
                          FoldObservations(s.Y, y, fold, 6), s.g.size(), opt);
    };
    // Exactly a combination far from the prior: any pull towards it costs.
    Eigen::MatrixXd w = Eigen::MatrixXd::Zero(8, 3);
    w.row(2).setConstant(1.5);
    w.row(5).setConstant(-0.4);
    EXPECT_EQ(choose(Render(s, w)).lambda, 1e-4);
    // The prior itself plus noise: the prior is the best answer.
    std::mt19937 rng(9);
    std::normal_distribution<double> noise(0, 0.3);
    Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(8, 3, 1.0 / 8));
    for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += noise(rng);
    const LambdaChoice noisy = choose(y);
    EXPECT_EQ(noisy.lambda, 100.0);
    // Held out, the prior's prediction misses by the noise alone: σ √(3 pixels) / ‖y‖.
    const double want = 0.3 * std::sqrt(static_cast<double>(y.size())) / y.norm();
    EXPECT_NEAR(noisy.predicted_error, want, 0.1 * want);
  }
}

TEST(LambdaChoice, ConditionBoundRulesOutLambdasThatLetUnseenDirectionsSwing) {
  Scene s = MakeScene(6, 5);
  for (int c = 0; c < 3; ++c) s.Y[c].col(4) = s.Y[c].col(1) + 1e-5f * s.Y[c].col(2);  // almost collinear
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5}};
  const auto f = FactorBasisImages(s.Y);
  const std::vector<int> fold = WedgeFolds(s.g, 4);
  const CvSystem cv = FactorFolds(f, FoldGrams(s.Y, fold, 4), members);
  const Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(6, 3, 0.2));
  LambdaChoiceOptions opt;
  opt.grid = {0, 1e-6, 1e-2};
  opt.max_condition = 1e6;
  const LambdaChoice ch = ChooseLambda(f, FactorClasses(f, members), &cv, MakeObservation(f, s.Y, y),
                                       FoldObservations(s.Y, y, fold, 4), s.g.size(), opt);
  EXPECT_TRUE(std::isinf(ch.score[0][0]));
  EXPECT_TRUE(std::isinf(ch.score[0][1]));
  EXPECT_EQ(ch.lambda, 1e-2);
}

// A photo black in one channel (λ_j = 0 there at every λ) with an almost
// collinear class: no λ keeps the class within the bound. The choice falls
// back to the most regularised fit instead of failing.
TEST(LambdaChoice, NoLambdaWithinTheBoundFallsBackToTheLargest) {
  Scene s = MakeScene(6, 5);
  for (int c = 0; c < 3; ++c) s.Y[c].col(4) = s.Y[c].col(1) + 1e-5f * s.Y[c].col(2);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5}};
  const auto f = FactorBasisImages(s.Y);
  const std::vector<int> fold = WedgeFolds(s.g, 4);
  const CvSystem cv = FactorFolds(f, FoldGrams(s.Y, fold, 4), members);
  Eigen::MatrixXd y = Render(s, Eigen::MatrixXd::Constant(6, 3, 0.2));
  y.col(2).setZero();
  LambdaChoiceOptions opt;
  opt.grid = {0, 1e-2, 1};
  opt.max_condition = 1e6;
  const LambdaChoice ch = ChooseLambda(f, FactorClasses(f, members), &cv, MakeObservation(f, s.Y, y),
                                       FoldObservations(s.Y, y, fold, 4), s.g.size(), opt);
  EXPECT_EQ(ch.chosen_class, 0);
  EXPECT_EQ(ch.lambda, 1.0);
  EXPECT_TRUE(ch.beyond_condition_bound);
  EXPECT_TRUE(std::isfinite(ch.predicted_error));
}

namespace {
// Two classes and every basis (the last candidate); a noisy photo of a truth
// over the bases of both classes, equal weights but two; the BRDF metric of
// each candidate its members' block of the Gram matrix.
struct PenaltyCase {
  std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4}, {5, 6, 7, 8, 9}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}};
  Scene s = MakeScene(10, 11);
  Folded x;
  std::vector<ClassSpectrum> classes;
  Observation obs;
  std::vector<Observation> held;
  std::vector<Eigen::MatrixXd> metrics;
  Eigen::MatrixXd y;
  PenaltyCase() {
    Eigen::MatrixXd truth = Eigen::MatrixXd::Constant(10, 3, 0.1);
    truth(2, 0) = 0.5, truth(7, 2) = 0.3;
    y = NoisyRender(s, truth, 0.03, 12);
    x = FoldScene(s, members, 4);
    classes = FactorClasses(x.f, members);
    obs = MakeObservation(x.f, s.Y, y);
    held = FoldObservations(s.Y, y, x.fold, 4);
    for (const auto& J : members) metrics.push_back(x.f[0].gram(J, J));
  }
};

// By brute force: the (class, λ) of least held-out score times (1 + a·s)²
// among the candidates `ch` scored that `eligible` admits (all without one),
// s each one's PriorSensitivity.
std::pair<int, double> LeastPenalised(const PenaltyCase& c, const LambdaChoice& ch, double a,
                                      const std::function<bool(size_t j, size_t l)>& eligible = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  std::pair<int, double> pick{-1, -1.0};
  for (size_t j = 0; j < c.members.size(); ++j)
    for (size_t l = 0; l < ch.grid.size(); ++l) {
      if (!std::isfinite(ch.score[j][l]) || (eligible && !eligible(j, l))) continue;
      const double factor = 1 + a * PriorSensitivity(c.classes[j], c.obs, ch.grid[l], c.metrics[j]);
      if (ch.score[j][l] * factor * factor < best)
        best = ch.score[j][l] * factor * factor, pick = {static_cast<int>(j), ch.grid[l]};
    }
  return pick;
}
}  // namespace

// The penalised pick against a brute force over every candidate: the least
// held-out error times (1 + a·s)², s each candidate's prior sensitivity
// (PriorSensitivity, tested against closed forms in fit_confidence_test.cc).
// The search skips candidates whose error alone cannot win; it must still
// land where the brute force does, for a noisy photo where a weak and a
// strong prior compete.
TEST(LambdaChoice, SensitivityPenaltyPicksTheLeastPenalisedCandidate) {
  const PenaltyCase c;
  const auto& [members, s, x, classes, obs, held, metrics, y] = c;
  const auto& [fold, f, cv] = x;
  for (double a : {0.0, 1.0, 20.0}) {
    SCOPED_TRACE(a);
    LambdaChoiceOptions opt;
    opt.max_condition = 1e9;
    opt.sensitivity_penalty = a;
    opt.penalty_gate = -1;  // every candidate (the gate has its own test)
    const LambdaChoice ch = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), opt, &metrics);
    const auto [best_j, best_l] = LeastPenalised(c, ch, a);
    EXPECT_EQ(ch.chosen_class, best_j);
    EXPECT_EQ(ch.lambda, best_l);
  }
  // A strong penalty moves the pick to a more regularised or smaller fit
  // than the held-out error alone would take.
  LambdaChoiceOptions none, strong;
  none.max_condition = strong.max_condition = 1e9;
  none.sensitivity_penalty = 0, strong.sensitivity_penalty = 20;
  strong.penalty_gate = -1;
  const LambdaChoice plain = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), none, &metrics);
  const LambdaChoice penalised = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), strong, &metrics);
  EXPECT_TRUE(plain.sensitivity.empty()) << "no penalty, no sensitivities";
  EXPECT_TRUE(penalised.chosen_class != plain.chosen_class || penalised.lambda > plain.lambda);
}

TEST(LambdaChoice, WithinStandardErrorsIsAOneSidedPairedComparison) {
  EXPECT_TRUE(WithinStandardErrors({-1, -1}, 0));      // better on every wedge
  EXPECT_FALSE(WithinStandardErrors({1, 1, 1}, 100));  // worse on every wedge by the same: no spread to hide in
  // Mean 2, sample deviation √2, standard error of the mean √2 / √2 = 1.
  EXPECT_TRUE(WithinStandardErrors({1, 3}, 2));
  EXPECT_FALSE(WithinStandardErrors({1, 3}, 1.9));
  EXPECT_TRUE(WithinStandardErrors({5}, 0));  // one wedge: nothing to compare by
}

// The gate against a brute force: each wedge's held-out error of every
// candidate by a dense refit on the other wedges (as
// CrossValidationScoreIsTheHeldOutErrorOfARefit checks the scores), the
// candidates clearly worse than the least one dropped by the paired
// standard error computed here, the least penalised of the rest.
TEST(LambdaChoice, ThePenaltyGateOffersOnlyCandidatesNotClearlyWorseOnTheWedges) {
  const PenaltyCase c;
  const auto& [members, s, x, classes, obs, held, metrics, y] = c;
  const auto& [fold, f, cv] = x;
  const int K = 4;
  auto wedge_errors = [&](size_t j, double lambda) {
    std::vector<double> e(K, 0.0);
    for (int k = 0; k < K; ++k) {
      std::vector<int> train, test;
      for (size_t p = 0; p < fold.size(); ++p) (fold[p] == k ? test : train).push_back(static_cast<int>(p));
      const double weight = y.squaredNorm() / K / y(test, Eigen::all).squaredNorm();  // relative wedges
      for (int ch = 0; ch < 3; ++ch) {
        const Eigen::MatrixXd A = s.Y[ch].cast<double>()(train, members[j]);
        const Eigen::VectorXd b = y.col(ch)(train);
        const double cj = static_cast<double>(members[j].size());
        const Eigen::VectorXd prior = Eigen::VectorXd::Constant(members[j].size(), 1.0 / cj);
        const Eigen::VectorXd wj = SolveRidge(A, b, lambda * b.squaredNorm() / cj, prior);
        e[k] += weight * (s.Y[ch].cast<double>()(test, members[j]) * wj - y.col(ch)(test)).squaredNorm();
      }
    }
    return e;
  };
  std::map<std::pair<int, double>, int> picks;  // (class, λ) → times picked
  for (const double a : {1.0, 20.0})
    for (const double z : {-1.0, 0.0, 1.0}) {
      SCOPED_TRACE(testing::Message() << "a " << a << " z " << z);
      LambdaChoiceOptions opt;
      opt.max_condition = 1e9;
      opt.sensitivity_penalty = a;
      opt.penalty_gate = z;
      opt.blend_every_basis = false;  // one group: the pick alone
      const LambdaChoice ch = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), opt, &metrics);
      size_t j0 = 0, l0 = 0;
      for (size_t j = 0; j < members.size(); ++j)
        for (size_t l = 0; l < opt.grid.size(); ++l)
          if (ch.score[j][l] < ch.score[j0][l0]) j0 = j, l0 = l;
      const std::vector<double> e0 = wedge_errors(j0, opt.grid[l0]);
      const auto [best_j, best_l] = LeastPenalised(c, ch, a, [&](size_t j, size_t l) {
        if (z < 0) return true;
        const std::vector<double> e = wedge_errors(j, opt.grid[l]);
        double mean = 0, ss = 0;
        for (int k = 0; k < K; ++k) mean += (e[k] - e0[k]) / K;
        for (int k = 0; k < K; ++k) ss += std::pow(e[k] - e0[k] - mean, 2);
        return mean <= z * std::sqrt(ss / (K - 1) / K);
      });
      EXPECT_EQ(ch.chosen_class, best_j);
      EXPECT_EQ(ch.lambda, best_l);
      if (z == 0) {  // nothing beats the least error on average: the penalty has no say
        EXPECT_EQ(ch.chosen_class, static_cast<int>(j0));
        EXPECT_EQ(ch.lambda, opt.grid[l0]);
      }
      ++picks[{ch.chosen_class, ch.lambda}];
    }
  EXPECT_GE(picks.size(), 2u) << "the gate never changed the pick: the case does not test it";
}

TEST(LambdaChoice, TheBlendWeighsTheBestClassAndEveryBasisByTheirPenalisedScores) {
  const PenaltyCase c;
  const auto& [members, s, x, classes, obs, held, metrics, y] = c;
  const auto& [fold, f, cv] = x;
  const double total = obs.norm2[0] + obs.norm2[1] + obs.norm2[2];
  LambdaChoiceOptions opt;
  opt.max_condition = 1e9;
  opt.min_blend_weight = 0;
  const LambdaChoice ch = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), opt, &metrics);
  // Every candidate penalised, by brute force: the best of the classes and
  // the best of every basis.
  struct Best {
    double penalised = std::numeric_limits<double>::infinity(), score = 0, lambda = -1;
    int cls = -1;
  };
  Best of[2];
  for (size_t j = 0; j < members.size(); ++j)
    for (size_t l = 0; l < opt.grid.size(); ++l) {
      if (!std::isfinite(ch.score[j][l])) continue;
      const double factor = 1 + PriorSensitivity(classes[j], obs, opt.grid[l], metrics[j]);
      const double penalised = ch.score[j][l] * factor * factor;
      Best& b = of[j == 2 ? 1 : 0];
      if (penalised < b.penalised) b = {penalised, ch.score[j][l], opt.grid[l], static_cast<int>(j)};
    }
  ASSERT_TRUE(std::isfinite(of[0].penalised) && std::isfinite(of[1].penalised));
  const int won = of[1].penalised < of[0].penalised ? 1 : 0;
  ASSERT_EQ(ch.parts.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const Best& b = of[i == 0 ? won : 1 - won];
    SCOPED_TRACE(i);
    EXPECT_EQ(ch.parts[i].cls, b.cls);
    EXPECT_EQ(ch.parts[i].lambda, b.lambda);
    // Weights ∝ 1 / penalised score.
    EXPECT_NEAR(ch.parts[i].weight, (1 / b.penalised) / (1 / of[0].penalised + 1 / of[1].penalised), 1e-12);
    EXPECT_NEAR(ch.parts[i].held_out_error, std::sqrt(b.score / total), 1e-12);
    EXPECT_NEAR(ch.parts[i].sensitivity, PriorSensitivity(classes[b.cls], obs, b.lambda, metrics[b.cls]), 1e-12);
    // The predicted error is the held-out error weighed as the pick weighs it.
    EXPECT_NEAR(ch.parts[i].predicted_error, std::sqrt(b.penalised / total), 1e-12);
    EXPECT_GT(ch.parts[i].predicted_error, ch.parts[i].held_out_error);
  }
  EXPECT_EQ(ch.chosen_class, ch.parts[0].cls) << "the pick is the part of the larger weight";
  EXPECT_GE(ch.parts[0].weight, ch.parts[1].weight);
  EXPECT_NEAR(ch.predicted_error,
              ch.parts[0].weight * ch.parts[0].predicted_error + ch.parts[1].weight * ch.parts[1].predicted_error,
              1e-12);
  EXPECT_NEAR(ch.held_out_error,
              ch.parts[0].weight * ch.parts[0].held_out_error + ch.parts[1].weight * ch.parts[1].held_out_error, 1e-12);
  // Below the least weight, and without the blend, the pick alone.
  LambdaChoiceOptions high = opt, off = opt;
  high.min_blend_weight = ch.parts[1].weight + 1e-9;
  off.blend_every_basis = false;
  for (const LambdaChoiceOptions* o : {&high, &off}) {
    const LambdaChoice one = ChooseLambda(f, classes, &cv, obs, held, s.g.size(), *o, &metrics);
    ASSERT_EQ(one.parts.size(), 1u);
    EXPECT_EQ(one.parts[0].cls, ch.parts[0].cls);
    EXPECT_EQ(one.parts[0].lambda, ch.parts[0].lambda);
    EXPECT_EQ(one.parts[0].weight, 1);
    EXPECT_NEAR(one.predicted_error, ch.parts[0].predicted_error, 1e-12);
    EXPECT_NEAR(one.held_out_error, ch.parts[0].held_out_error, 1e-12);
  }
}

TEST(LambdaChoice, EveryBasisIsACandidateWhereTheRuleCanWeighIt) {
  const std::vector<std::vector<int>> classes = {{0, 2}, {1, 3}};
  const std::vector<int> all = {0, 1, 2, 3};
  LambdaChoiceOptions opt;
  for (const char* rule : {"cv", "gcv"}) {
    opt.rule = rule;
    EXPECT_EQ(CandidateMembers(classes, all, opt), (std::vector<std::vector<int>>{{0, 2}, {1, 3}, {0, 1, 2, 3}}));
  }
  // By in-sample residual every basis would always win; a fixed λ picks by residual too.
  for (const char* rule : {"residual", "fixed"}) {
    opt.rule = rule;
    EXPECT_EQ(CandidateMembers(classes, all, opt), classes) << rule;
  }
  opt.rule = "cv";
  opt.all_bases_candidate = false;
  EXPECT_EQ(CandidateMembers(classes, all, opt), classes);
}

// The noise a fit leaves, against a dense least-squares fit (QR) of the
// pixels: √(Σ_c RSS_c / Σ_c (n − p)) over the photo's RMS, and that is the
// added white noise's level.
TEST(FitResidualNoise, IsTheResidualOfTheLeastSquaresFitPerFreePixel) {
  const Scene s = MakeScene(4, 13);  // four random quadratics: full column rank
  const double sigma = 0.01;
  const Eigen::MatrixXd y = NoisyRender(s, Eigen::MatrixXd::Constant(4, 3, 0.25), sigma, 14);
  const auto f = FactorBasisImages(s.Y);
  const std::vector<ClassSpectrum> cls = FactorClasses(f, {{0, 1, 2, 3}});
  const Observation obs = MakeObservation(f, s.Y, y);
  const double n = static_cast<double>(s.g.size());
  double rss = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd A = s.Y[c].cast<double>();
    const Eigen::VectorXd x = A.colPivHouseholderQr().solve(y.col(c));
    rss += (A * x - y.col(c)).squaredNorm();
  }
  const double rms = std::sqrt(y.squaredNorm() / (3 * n));
  const double want = std::sqrt(rss / (3 * (n - 4))) / rms;
  const double got = FitResidualNoise(cls[0], obs, s.g.size(), {0, 1e-3, 1}, 1e300);
  EXPECT_NEAR(got, want, 1e-6 * want);
  // Held tridiagonal (no eigenvectors to project on), the same residual and
  // free pixels, at λ = 0 and at the least λ of a grid without it.
  const ClassSpectrum tri = FactorClasses(f, {{0, 1, 2, 3}}, SpectrumParts::kTridiagonal)[0];
  EXPECT_NEAR(FitResidualNoise(tri, obs, s.g.size(), {0, 1e-3, 1}, 1e300), want, 1e-6 * want);
  const double at_1e3 = FitResidualNoise(cls[0], obs, s.g.size(), {1e-3, 1}, 1e300);
  EXPECT_GT(std::abs(at_1e3 - got), 1e-5 * got) << "λ = 10⁻³ must read differently for the comparison to mean anything";
  EXPECT_NEAR(FitResidualNoise(tri, obs, s.g.size(), {1e-3, 1}, 1e300), at_1e3, 1e-9 * at_1e3);
  EXPECT_NEAR(got * rms, sigma, 0.1 * sigma);
  // The least λ within the bound: with a bound no λ meets, none.
  EXPECT_EQ(FitResidualNoise(cls[0], obs, s.g.size(), {0}, 1.0), -1);
  // The bound follows the lesser of the pixel noise and the fit's.
  LambdaChoiceOptions opt;
  opt.noise_bound.max_bound = 1e300;
  EXPECT_NEAR(BoundNoise(1.0, cls, obs, s.g.size(), opt), got, 1e-12);
  EXPECT_EQ(BoundNoise(1e-9, cls, obs, s.g.size(), opt), 1e-9);
  EXPECT_EQ(BoundNoise(kUnknownNoise, cls, obs, s.g.size(), opt), kUnknownNoise) << "unknown stays cautious";
  opt.max_condition = 1e6;
  EXPECT_EQ(BoundNoise(1.0, cls, obs, s.g.size(), opt), 1.0) << "a fixed bound does not follow the noise";
}

// Basis images with their own fine texture: a combination of them carries
// detail the photo's noise reading counts as noise; the fit of every basis
// holds the detail, and what it leaves reads the added noise alone.
TEST(FitPixelNoise, ReadsTheNoiseWhereTheFitHasTakenTheDetailAway) {
  Scene s = MakeScene(5, 21);
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> texture(0.7f, 1.3f);
  for (int c = 0; c < 3; ++c)
    for (Eigen::Index i = 0; i < s.Y[c].size(); ++i) s.Y[c].data()[i] *= texture(rng);
  const double sigma = 0.002;
  const Eigen::MatrixXd w = Eigen::MatrixXd::Constant(5, 3, 0.2);
  const Eigen::MatrixXd y = NoisyRender(s, w, sigma, 23);
  const double rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  const auto f = FactorBasisImages(s.Y);
  const std::vector<ClassSpectrum> classes = FactorClasses(f, {{0, 1}, {0, 1, 2, 3, 4}});
  const Observation obs = MakeObservation(f, s.Y, y);
  LambdaChoiceOptions opt;
  opt.noise_bound.max_bound = 1e300;
  const double photo = RelativePixelNoise(s.g, y);
  const double fit = FitPixelNoise(s.g, s.Y, y, classes, obs, opt);
  EXPECT_GT(photo, 10 * sigma / rms);
  EXPECT_NEAR(fit, sigma / rms, 0.15 * sigma / rms);  // ~1400 pixels: the median's spread
  // The least-regularised weights are the least-squares fit's here (λ = 0 is within the bound).
  const Eigen::MatrixXd least = LeastRegularisedWeights(classes[1], obs, {1, 0, 0.1}, 1e300);
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd A = s.Y[c].cast<double>();
    EXPECT_LT((least.col(c) - A.colPivHouseholderQr().solve(y.col(c))).norm(), 1e-6) << c;
  }
  EXPECT_EQ(LeastRegularisedWeights(classes[1], obs, {0}, 1.0).size(), 0) << "no λ within the bound";
  // The bound's pixel noise: the lesser reading, unless turned off or fixed.
  EXPECT_NEAR(BoundPixelNoise(photo, s.g, s.Y, y, classes, obs, opt), fit, 1e-15);
  EXPECT_EQ(BoundPixelNoise(kUnknownNoise, s.g, s.Y, y, classes, obs, opt), kUnknownNoise);
  EXPECT_EQ(BoundPixelNoise(0.0, s.g, s.Y, y, classes, obs, opt), 0.0);
  opt.noise_bound.read_fit_residual = false;
  EXPECT_EQ(BoundPixelNoise(photo, s.g, s.Y, y, classes, obs, opt), photo);
  opt.noise_bound.read_fit_residual = true;
  opt.max_condition = 1e6;
  EXPECT_EQ(BoundPixelNoise(photo, s.g, s.Y, y, classes, obs, opt), photo);
}

TEST(FitRecord, RoundTripsThroughJson) {
  FitRecord r;
  r.database = "MERL (NBRDF approximation)";
  r.database_kind = "nbrdf";
  r.grid = MerlGrid{90, 90, 180};
  r.probe = "p.exr";
  r.photo = "o.bsobs";
  r.lambda_rule = "cv";
  r.lambda = 0.03;
  r.predicted_relit_error = 0.041;
  r.held_out_error = 0.036;
  r.chosen_class = 1;
  r.relative_residual = 0.02;
  r.classes = {{3, 1.5, 20, "normal"}, {2, 0.5, 1e9, "qr"}, {0, std::numeric_limits<double>::infinity(), 0, ""}};
  r.lambda_grid = {0, 0.03};
  r.lambda_scores = {
      {2, 1}, {0.5, 0.25}, {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}};
  r.bases = {"a/R", "a/G", "a/B"};
  r.weights = Eigen::MatrixXd::Random(3, 3);
  r.seconds_factor = 0.2;
  r.seconds_solve = 0.003;
  r.lambda_beyond_condition_bound = true;
  r.prior_sensitivity = 0.125;
  r.relative_noise = 0.0025;
  r.condition_bound = 1.44e6;
  r.bound_noise = 0.0004;
  r.sensitivity_penalty = 1;
  r.penalty_gate = 1.5;
  r.min_wedge_share = 1.3e-5;
  r.mean_blend = 2.5e-4;
  r.parts = {{1, 0.03, 0.75, 0.041, std::nan(""), 0.037}, {2, 1e-4, 0.25, 0.05, std::nan(""), 0.033}};
  const FitRecord back = FitRecord::FromJson(nlohmann::json::parse(r.ToJson().dump()), "fit.json");
  EXPECT_EQ(back.ToJson(), r.ToJson());
  EXPECT_TRUE(back.lambda_beyond_condition_bound);
  EXPECT_EQ(back.prior_sensitivity, 0.125);
  EXPECT_EQ(back.relative_noise, 0.0025);
  EXPECT_EQ(back.condition_bound, 1.44e6);
  EXPECT_EQ(back.bound_noise, 0.0004);
  EXPECT_EQ(back.sensitivity_penalty, 1);
  EXPECT_EQ(back.penalty_gate, 1.5);
  EXPECT_EQ(back.min_wedge_share, 1.3e-5);
  EXPECT_EQ(back.mean_blend, 2.5e-4);
  // A fit made without the tables has no sensitivity: none is written, and a
  // file without one reads as not measured.
  nlohmann::json unmeasured = r.ToJson();
  unmeasured.erase("prior_sensitivity");
  EXPECT_EQ(FitRecord::FromJson(unmeasured, "fit.json").prior_sensitivity, -1);
  nlohmann::json unblended = r.ToJson(), overblended = r.ToJson();
  unblended.erase("class_mean_blend_after_check");
  EXPECT_EQ(FitRecord::FromJson(unblended, "fit.json").mean_blend, 0);
  overblended["class_mean_blend_after_check"] = 1.5;  // a blend is a convex combination
  EXPECT_THROW(FitRecord::FromJson(overblended, "fit.json"), Error);
  EXPECT_TRUE(back.weights == r.weights);
  EXPECT_TRUE(std::isinf(back.classes[2].residual));
  EXPECT_TRUE(std::isinf(back.lambda_scores[2][1]));
  ASSERT_EQ(back.parts.size(), 2u);
  EXPECT_EQ(back.parts[1].cls, 2);
  EXPECT_EQ(back.parts[1].lambda, 1e-4);
  EXPECT_EQ(back.parts[1].weight, 0.25);
  EXPECT_EQ(back.parts[1].predicted_error, 0.05);
  EXPECT_EQ(back.parts[1].held_out_error, 0.033);
  EXPECT_EQ(back.held_out_error, 0.036);
  nlohmann::json bad = r.ToJson();
  bad["chosen_class"] = 7;
  EXPECT_THROW(FitRecord::FromJson(bad, "fit.json"), Error);
  // A blend whose weights do not sum to 1, or that names no class of the fit.
  nlohmann::json heavy = r.ToJson(), stray = r.ToJson();
  heavy["blend"][1]["weight"] = 0.5;
  stray["blend"][1]["class"] = 3;
  EXPECT_THROW(FitRecord::FromJson(heavy, "fit.json"), Error);
  EXPECT_THROW(FitRecord::FromJson(stray, "fit.json"), Error);
}

}  // namespace brdfshot
