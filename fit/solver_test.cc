#include "fit/solver.h"

#include "fit/bin_constraints.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <random>

namespace brdfshot {

namespace {
// Random positive "basis images" with columns of very different scale.
std::array<MatrixXfR, 3> Images(int pixels, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.1f, 1.0f);
  std::array<MatrixXfR, 3> Y;
  for (int c = 0; c < 3; ++c) {
    Y[c].resize(pixels, n);
    for (int i = 0; i < pixels; ++i)
      for (int j = 0; j < n; ++j) Y[c](i, j) = u(rng) * (j % 4 == 0 ? 100.0f : 1.0f);
  }
  return Y;
}
Eigen::MatrixXd Render(const std::array<MatrixXfR, 3>& Y, const Eigen::MatrixXd& w) {
  Eigen::MatrixXd y(Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = Y[c].cast<double>() * w.col(c);
  return y;
}
}  // namespace

// The projection against Eigen's own product in double, over all rows and
// over a row subset whose length is not a multiple of the sweep, and a sum a
// float accumulator could not hold: 2²⁴ + 1 exceeds float's 24-bit mantissa.
TEST(Solver, ProjectRowsIsTheDoubleProductOverTheRowsGiven) {
  const std::array<MatrixXfR, 3> Y = Images(203, 11, 9);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd y(203);
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = u(rng);
  const Eigen::VectorXd all = Y[0].cast<double>().transpose() * y;
  EXPECT_LT((ProjectRows(Y[0], y) - all).cwiseAbs().maxCoeff(), 1e-12 * all.cwiseAbs().maxCoeff());

  const std::vector<int> rows = {200, 3, 17, 17, 0, 99, 150, 151, 152, 5, 77, 202, 8};
  Eigen::VectorXd some = Eigen::VectorXd::Zero(11);
  for (int r : rows) some += y[r] * Y[0].row(r).transpose().cast<double>();
  EXPECT_LT((ProjectRows(Y[0], y, rows) - some).cwiseAbs().maxCoeff(), 1e-12 * some.cwiseAbs().maxCoeff());

  MatrixXfR ones = MatrixXfR::Ones(17, 2);
  ones(16, 1) = 0;
  Eigen::VectorXd big = Eigen::VectorXd::Constant(17, 1048576.0);  // 16 × 2²⁰ = 2²⁴
  big[16] = 1;
  const Eigen::VectorXd z = ProjectRows(ones, big);
  EXPECT_EQ(z[0], 16777217.0);
  EXPECT_EQ(z[1], 16777216.0);
}

// A class factored without eigenvectors solves a fixed λ by Cholesky where
// the system is well conditioned and by the QR route where not: the same
// weights, residual and condition as through the full spectrum.
TEST(Solver, AClassWithoutEigenvectorsSolvesAsTheFullSpectrumDoes) {
  auto Y = Images(300, 16, 7);
  for (auto& y : Y) y.col(15) = y.col(14);  // class 1 holds two equal bases: singular at λ = 0
  const auto f = FactorBasisImages(Y, true);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5, 6, 7}, {8, 9, 10, 11, 12, 13, 14, 15}};
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::MatrixXd w(16, 3);
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = u(rng);
  const Observation obs = MakeObservation(f, Y, Render(Y, w));
  const auto full = FactorClasses(f, members);
  const auto values = FactorClasses(f, members, SpectrumParts::kEigenvalues);
  ASSERT_FALSE(values[0].has_vectors());
  for (int c = 0; c < 3; ++c) EXPECT_LT((values[1].e[c] - full[1].e[c]).norm(), 1e-12 * full[1].e[c].norm());
  for (double lambda : {0.5, 1e-3, 0.0}) {
    for (int j = 0; j < 2; ++j) {
      const ClassSolution a = SolveClass(f, full[j], obs, lambda), b = SolveClass(f, values[j], obs, lambda);
      EXPECT_EQ(a.path, b.path) << "class " << j << ", λ " << lambda;
      EXPECT_LT((a.weights - b.weights).norm(), 1e-7 * a.weights.norm()) << "class " << j << ", λ " << lambda;
      EXPECT_NEAR(a.residual, b.residual, 1e-6 * a.residual + 1e-12) << "class " << j << ", λ " << lambda;
      for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(a.condition[c], b.condition[c]);
    }
  }
  EXPECT_EQ(SolveClass(f, values[1], obs, 0.0).path, "qr") << "the singular class at λ = 0 takes the QR route";
  // Without a QR there is nothing to fall back on: an internal error, not a wrong answer.
  const auto no_qr = FactorBasisImages(Y, false);
  const Observation obs_no_qr = MakeObservation(no_qr, Y, Render(Y, w));
  EXPECT_THROW(SolveClass(no_qr, FactorClasses(no_qr, members, SpectrumParts::kEigenvalues)[1], obs_no_qr, 0.0),
               std::logic_error);
  EXPECT_LT((SolveClass(no_qr, values[0], obs_no_qr, 0.5).weights - SolveClass(f, full[0], obs, 0.5).weights).norm(),
            1e-7 * w.norm());
}

// A class held tridiagonal solves as the same class held by its eigenvectors,
// and both as a dense Cholesky of G_JJ + λ_j I where that is positive
// definite: at shifts from well to badly conditioned, at λ = 0 on a singular
// class (two equal bases: the eigenvectors of T give the pseudo-inverse), and
// under the bin constraint, whose solves go through (G_JJ + λ_j I)⁺.
TEST(Solver, ATridiagonalClassSolvesAsItsEigenvectorsDo) {
  auto Y = Images(400, 40, 31);
  for (auto& y : Y) y.col(39) = y.col(38);
  const auto f = FactorBasisImages(Y, false);  // no QR: every λ goes through the factor
  std::vector<int> J(40);
  for (int j = 0; j < 40; ++j) J[j] = j;
  const ClassSpectrum full = FactorClasses(f, {J})[0];
  const ClassSpectrum tri = FactorClasses(f, {J}, SpectrumParts::kTridiagonal)[0];
  ASSERT_TRUE(tri.tridiagonal() && tri.solvable());
  ASSERT_FALSE(tri.has_vectors());
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::MatrixXd w(40, 3);
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = u(rng);
  const Observation obs = MakeObservation(f, Y, Render(Y, w));
  for (int c = 0; c < 3; ++c) {
    const double emax = full.e[c][39];
    EXPECT_LT((tri.e[c] - full.e[c]).cwiseAbs().maxCoeff(), 1e-12 * emax) << "channel " << c;
    ASSERT_LT(full.e[c][0], 1e-13 * emax) << "the twins must make the class singular for the test to mean anything";
    const Eigen::VectorXd r = obs.z[c](J) - full.gram_prior[c];
    const Eigen::VectorXd lj = (Eigen::VectorXd(4) << 1e-2, 1e-6, 1e-10, 0.0).finished() * emax;
    const Eigen::MatrixXd a = SolveClassSystem(full, c, r, lj), b = SolveClassSystem(tri, c, r, lj);
    for (Eigen::Index l = 0; l < lj.size(); ++l) {
      EXPECT_LT((a.col(l) - b.col(l)).norm(), 1e-6 * a.col(l).norm()) << "channel " << c << ", λ_j " << lj[l];
      if (lj[l] == 0) continue;
      Eigen::MatrixXd H = full.gram[c];
      H.diagonal().array() += lj[l];
      const Eigen::VectorXd x = H.llt().solve(r);
      EXPECT_LT((b.col(l) - x).norm(), 1e-6 * x.norm()) << "channel " << c << ", λ_j " << lj[l];
    }
    // λ = 0: the minimum-norm correction gives the twins equal shares.
    EXPECT_NEAR(b(38, 3), b(39, 3), 1e-6 * b.col(3).norm()) << "channel " << c;
  }
  for (double lambda : {0.5, 1e-3, 0.0}) {
    const ClassSolution a = SolveClass(f, full, obs, lambda), b = SolveClass(f, tri, obs, lambda);
    EXPECT_EQ(a.path, b.path) << "λ " << lambda;
    EXPECT_LT((a.weights - b.weights).norm(), 1e-6 * a.weights.norm()) << "λ " << lambda;
  }
  MatrixXfR tables(64, 40);
  std::uniform_real_distribution<float> uf(0.0f, 1.0f);
  for (Eigen::Index i = 0; i < tables.size(); ++i) tables.data()[i] = uf(rng);
  for (int i = 0; i < 8; ++i) {
    tables.row(i).setZero();  // bins that basis 4 (of the large scale) alone holds
    tables(i, 4) = 1;
  }
  Eigen::MatrixXd v = w;
  v.row(4).setConstant(-0.5);  // a difference of bases: the free fit goes negative at the bins basis 4 holds
  const Observation obs_v = MakeObservation(f, Y, Render(Y, v));
  const BinRows bins = BinRows::EveryNth(tables, J, 1);
  WeightConstraint constraint;
  constraint.kind = WeightConstraint::Kind::kBins;
  constraint.bins = &bins;
  for (double lambda : {1e-4, 1e-6}) {
    const ClassSolution a = SolveClass(f, full, obs_v, lambda, constraint);
    const ClassSolution b = SolveClass(f, tri, obs_v, lambda, constraint);
    EXPECT_LT((tables.cast<double>() * a.unconstrained_weights).minCoeff(), 0)
        << "the free fit must go negative for the test to mean anything";
    EXPECT_LT((a.weights - b.weights).norm(), 1e-6 * a.weights.norm()) << "λ " << lambda;
  }
}

TEST(Solver, ClassMeanIsRecoveredExactlyWithItsClass) {
  // The regulariser pulls towards μ' = 1/c_j, so a material equal to class 1's
  // mean is a fixed point for any λ: weights and class must come back exactly.
  const auto Y = Images(400, 24, 1);
  const auto f = FactorBasisImages(Y, true);
  const std::vector<std::vector<int>> members = {
      {0, 1, 2, 3, 4, 5, 6, 7}, {8, 9, 10, 11, 12, 13}, {14, 15, 16, 17, 18, 19, 20, 21, 22, 23}};
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(24, 3);
  for (int i : members[1]) w.row(i).setConstant(1.0 / 6);
  const ClasswiseFit fit = SolveClasswise(f, MakeObservation(f, Y, Render(Y, w)), members, SolveOptions{});
  EXPECT_EQ(fit.chosen, 1);
  EXPECT_LT((fit.weights() - w).norm(), 1e-9);
  EXPECT_LT(fit.classes[1].residual, 1e-18 * Render(Y, w).squaredNorm() + 1e-20);
}

TEST(Solver, ArbitraryCombinationRecoveredAsLambdaVanishes) {
  const auto Y = Images(300, 20, 2);
  const auto f = FactorBasisImages(Y, true);
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
                                                 {10, 11, 12, 13, 14, 15, 16, 17, 18, 19}};
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(20, 3);
  for (int i : members[0]) w.row(i) << 0.3 * (i % 3), 0.1 * i, 0.05;
  SolveOptions so;
  so.lambda = 1e-14;
  const ClasswiseFit fit = SolveClasswise(f, MakeObservation(f, Y, Render(Y, w)), members, so);
  EXPECT_EQ(fit.chosen, 0);
  EXPECT_LT((fit.weights() - w).norm(), 1e-6 * w.norm());
}

TEST(Solver, LambdaToZeroGivesTheLeastSquaresAnswer) {
  const auto Y = Images(200, 12, 3);
  const auto f = FactorBasisImages(Y, true);
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  Eigen::MatrixXd y(200, 3);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) = 5 + g(rng);  // not in the span
  const Observation obs = MakeObservation(f, Y, y);
  std::vector<int> all(12);
  for (int i = 0; i < 12; ++i) all[i] = i;
  SolveOptions so;
  so.lambda = 0;
  const ClasswiseFit fit = SolveClasswise(f, obs, {all}, so);
  // Independent least squares straight on Y (OpenCV-free, Eigen's SVD solve).
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd Yd = Y[c].cast<double>();
    const Eigen::VectorXd ls = Yd.bdcSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(y.col(c));
    EXPECT_LT((fit.weights().col(c) - ls).norm(), 1e-8 * ls.norm()) << "channel " << c;
  }
  EXPECT_LT((SolveLeastSquares(f, obs, all) - fit.weights()).norm(), 1e-8 * fit.weights().norm());
}

TEST(Solver, DuplicatedBasesGiveAFiniteAnswerAndReportTheConditioning) {
  auto Y = Images(150, 8, 4);
  for (int c = 0; c < 3; ++c) Y[c].col(5) = Y[c].col(2);  // exactly collinear
  const auto f = FactorBasisImages(Y, true);
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(8, 3);
  w.row(2).setConstant(1.0);
  const Observation obs = MakeObservation(f, Y, Render(Y, w));
  const std::vector<std::vector<int>> members = {{0, 1, 2, 3, 4, 5, 6, 7}};
  for (double lambda : {0.0, 0.5}) {
    SolveOptions so;
    so.lambda = lambda;
    const ClasswiseFit fit = SolveClasswise(f, obs, members, so);
    EXPECT_TRUE(fit.weights().allFinite()) << "lambda " << lambda;
    if (lambda == 0) {
      EXPECT_GT(fit.classes[0].condition[0], 1e12) << "singular system must be reported";
      // Minimum-norm correction splits the duplicate evenly around the prior.
      EXPECT_NEAR(fit.weights()(2, 0), fit.weights()(5, 0), 1e-6);
      // The residual comes from the Gram form wᵀGw − 2wᵀz + ‖y‖²: exact to ~ε‖y‖².
      EXPECT_LT(fit.classes[0].residual, 1e-13 * obs.norm2[0]);
    } else {
      EXPECT_LT(fit.classes[0].condition[0], 1e8);
    }
  }
}

TEST(Solver, FewerPixelsThanBasesStillSolves) {
  const auto Y = Images(10, 30, 6);
  const auto f = FactorBasisImages(Y, true);
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(30, 3);
  w.row(4).setConstant(0.5);
  std::vector<int> all(30);
  for (int i = 0; i < 30; ++i) all[i] = i;
  const ClasswiseFit fit = SolveClasswise(f, MakeObservation(f, Y, Render(Y, w)), {all}, SolveOptions{});
  EXPECT_TRUE(fit.weights().allFinite());
  EXPECT_LT(std::sqrt(fit.classes[0].residual), 0.5 * Render(Y, w).norm());
}

// The ridge solve against the closed form through an independent SVD of A,
// w = μ + V diag(σ / (σ² + λ)) Uᵀ (z − A μ), on a matrix whose singular values
// run from 1 to 1e-7 (normal equations would square that to 1e-14), for λ
// from well above the smallest σ² to far below it; and at λ = 0 on dependent
// columns, the minimum-norm correction.
TEST(Solver, SolveRidgeMatchesTheSvdClosedFormOnIllConditionedSystems) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  const int m = 40, k = 12;
  Eigen::MatrixXd X(m, k), Z(k, k);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = g(rng);
  for (Eigen::Index i = 0; i < Z.size(); ++i) Z.data()[i] = g(rng);
  const Eigen::MatrixXd U = Eigen::HouseholderQR<Eigen::MatrixXd>(X).householderQ() * Eigen::MatrixXd::Identity(m, k);
  const Eigen::MatrixXd V = Eigen::HouseholderQR<Eigen::MatrixXd>(Z).householderQ();
  Eigen::VectorXd sigma(k);
  for (int i = 0; i < k; ++i) sigma[i] = std::pow(10.0, -7.0 * i / (k - 1));
  const Eigen::MatrixXd A = U * sigma.asDiagonal() * V.transpose();
  Eigen::VectorXd z(m), prior(k);
  for (int i = 0; i < m; ++i) z[i] = g(rng);
  for (int i = 0; i < k; ++i) prior[i] = g(rng);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  for (const double lambda : {1e-2, 1e-8, 1e-12, 1e-16}) {
    const Eigen::VectorXd s = svd.singularValues();
    const Eigen::VectorXd gain = s.cwiseQuotient((s.array().square() + lambda).matrix());
    const Eigen::VectorXd want =
        prior + svd.matrixV() * gain.asDiagonal() * svd.matrixU().transpose() * (z - A * prior);
    const Eigen::VectorXd got = SolveRidge(A, z, lambda, prior);
    EXPECT_LT((got - want).norm(), 1e-8 * want.norm()) << "lambda " << lambda;
  }
  // λ = 0, the last column a copy of the first: the minimum-norm correction
  // splits the weight evenly between the two.
  Eigen::MatrixXd D = X.leftCols(4);
  D.col(3) = D.col(0);
  const Eigen::VectorXd target = D.leftCols(3) * Eigen::Vector3d(2, -1, 0.5);
  const Eigen::VectorXd w = SolveRidge(D, target, 0, Eigen::VectorXd::Zero(4));
  EXPECT_NEAR(w[0], 1.0, 1e-10);
  EXPECT_NEAR(w[3], 1.0, 1e-10);
  EXPECT_NEAR(w[1], -1.0, 1e-10);
  EXPECT_NEAR(w[2], 0.5, 1e-10);
}

TEST(Solver, NormalEquationsAndQrAgreeOnWellConditionedSystems) {
  const auto Y = Images(500, 30, 11);
  const auto f = FactorBasisImages(Y, true);
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  Eigen::MatrixXd y(500, 3);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) = 20 + g(rng);
  const Observation obs = MakeObservation(f, Y, y);
  const std::vector<int> J = {0, 2, 3, 5, 8, 9, 12, 17, 21, 22, 29};
  const ClassSpectrum cls = FactorClasses(f, {J})[0];
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(J.size(), 1.0 / J.size());
  for (double lambda : {1e-3, 0.05, 0.5, 5.0}) {
    const ClassSolution s = SolveClass(f, cls, obs, lambda);
    EXPECT_EQ(s.path, "normal") << "lambda " << lambda;
    for (int c = 0; c < 3; ++c) {
      // The QR route on the augmented system, never squared.
      const Eigen::VectorXd qr = SolveRidge(f[c].R(Eigen::all, J), obs.z_qr[c], s.lambda_j[c], prior);
      const Eigen::VectorXd ne = s.weights.col(c)(J);
      EXPECT_LT((ne - qr).norm(), 1e-6 * qr.norm()) << "lambda " << lambda << " channel " << c;
    }
  }
}

// A solve under the bin constraint carries the unconstrained solve beside
// it, bit for bit what SolveClass gives without the constraint, while its own
// weights are moved to keep every bin ≥ 0.
TEST(Solver, AConstrainedSolveCarriesTheUnconstrainedOne) {
  const auto Y = Images(300, 12, 21);
  const auto f = FactorBasisImages(Y, true);
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  Eigen::MatrixXd w = Eigen::MatrixXd::Constant(12, 3, 0.1);
  w.row(3).setConstant(-0.4);  // a difference of bases, as a material outside the database is
  Eigen::MatrixXd y = Render(Y, w);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += 0.01 * g(rng);
  const Observation obs = MakeObservation(f, Y, y);
  std::vector<int> J(12);
  for (int j = 0; j < 12; ++j) J[j] = j;
  const ClassSpectrum cls = FactorClasses(f, {J})[0];
  // "Tables": positive bins and one column that dominates a few of them.
  MatrixXfR tables(64, 12);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (Eigen::Index i = 0; i < tables.size(); ++i) tables.data()[i] = u(rng);
  for (int i = 0; i < 8; ++i) tables(i, 3) = 20;
  const BinRows bins = BinRows::EveryNth(tables, J, 1);
  WeightConstraint constraint;
  constraint.kind = WeightConstraint::Kind::kBins;
  constraint.bins = &bins;
  for (const double lambda : {1e-4, 1e-2}) {
    const ClassSolution free = SolveClass(f, cls, obs, lambda);
    const ClassSolution held = SolveClass(f, cls, obs, lambda, constraint);
    ASSERT_EQ(held.unconstrained_weights.rows(), 12);
    EXPECT_TRUE(held.unconstrained_weights == free.weights) << "lambda " << lambda;
    EXPECT_TRUE(free.unconstrained_weights == free.weights) << "lambda " << lambda;
    const Eigen::MatrixXd dense = tables.cast<double>();
    EXPECT_LT((dense * free.weights).minCoeff(), 0) << "the free fit must go negative for the test to mean anything";
    EXPECT_GE((dense * held.weights).minCoeff(), -1e-6 * (dense * free.weights).cwiseAbs().maxCoeff());
    // Non-negative weights have no unconstrained step to carry.
    WeightConstraint weights;
    weights.kind = WeightConstraint::Kind::kWeights;
    EXPECT_EQ(SolveClass(f, cls, obs, lambda, weights).unconstrained_weights.size(), 0) << "lambda " << lambda;
  }
}

TEST(Solver, SingularSystemTakesTheQrPathAndWithoutItTheTruncatedOne) {
  auto Y = Images(200, 10, 12);
  for (int c = 0; c < 3; ++c) Y[c].col(7) = Y[c].col(1);  // exactly collinear: G is singular
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(10, 3);
  w.row(1).setConstant(0.8);
  w.row(4).setConstant(0.3);
  const std::vector<int> all = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const auto with_qr = FactorBasisImages(Y, true), without = FactorBasisImages(Y, false);
  const ClassSolution a =
      SolveClass(with_qr, FactorClasses(with_qr, {all})[0], MakeObservation(with_qr, Y, Render(Y, w)), 0.0);
  const ClassSolution b =
      SolveClass(without, FactorClasses(without, {all})[0], MakeObservation(without, Y, Render(Y, w)), 0.0);
  EXPECT_EQ(a.path, "qr");
  EXPECT_EQ(b.path, "normal-truncated");
  for (const ClassSolution* s : {&a, &b}) {
    ASSERT_TRUE(s->weights.allFinite()) << s->path;
    // Minimum-norm correction: the twins share the weight equally about the prior.
    EXPECT_NEAR(s->weights(1, 0), s->weights(7, 0), 1e-6) << s->path;
    EXPECT_LT((Render(Y, s->weights) - Render(Y, w)).norm(), 1e-6 * Render(Y, w).norm()) << s->path;
  }
  // A well-conditioned λ keeps the normal equations.
  EXPECT_EQ(SolveClass(with_qr, FactorClasses(with_qr, {all})[0], MakeObservation(with_qr, Y, Render(Y, w)), 0.5).path,
            "normal");
}

}  // namespace brdfshot
