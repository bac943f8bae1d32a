// The fit's solve and its photo-independent factorisation at the size of a
// 128-pixel sphere (12.9 k pixels × 300 bases × 3 channels, classes of
// 141 / 29 / 127 / 3 as the NBRDF database's), side by side with the
// Householder-QR route the normal equations replace. Numbers in
// docs/benchmarks.md; run: build/fit/fit_solver_benchmark.
#include <benchmark/benchmark.h>

#include <random>

#include "fit/bin_constraints.h"
#include "fit/fit_confidence.h"
#include "fit/lambda_choice.h"
#include "fit/solver.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {
namespace {

struct Problem {
  PixelGeometry g;
  std::array<MatrixXfR, 3> Y;
  Eigen::MatrixXd y;
  std::vector<std::vector<int>> members;
};

// Smooth random basis images (each a random quadratic in the normal, scales
// spread over three decades as metals' and fabrics' are) and an observation
// that is a noisy combination of them.
const Problem& TheProblem() {
  static const Problem p = [] {
    Problem p;
    p.g = OrthographicSphere(128, 80);
    const int n = 300;
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    for (int c = 0; c < 3; ++c) {
      p.Y[c].resize(static_cast<Eigen::Index>(p.g.size()), n);
      for (int j = 0; j < n; ++j) {
        const double scale = std::pow(10.0, 3 * u(rng)), a = u(rng), bx = u(rng) - .5, by = u(rng) - .5, q = u(rng);
        for (size_t i = 0; i < p.g.size(); ++i) {
          const Vec3& m = p.g.normal[i];
          p.Y[c](static_cast<Eigen::Index>(i), j) =
              static_cast<float>(scale * (a + bx * m.x + by * m.y + q * m.z * m.z));
        }
      }
    }
    Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
    for (int j = 0; j < n; j += 7) w[j] = 1.0 / 43;
    p.y.resize(static_cast<Eigen::Index>(p.g.size()), 3);
    std::normal_distribution<double> noise(0, 0.01);
    for (int c = 0; c < 3; ++c) {
      p.y.col(c) = p.Y[c].cast<double>() * w;
      for (Eigen::Index i = 0; i < p.y.rows(); ++i) p.y(i, c) *= 1 + noise(rng);
    }
    const int sizes[4] = {141, 29, 127, 3};
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    for (int k = 0, at = 0; k < 4; at += sizes[k++])
      p.members.emplace_back(order.begin() + at, order.begin() + at + sizes[k]);
    return p;
  }();
  return p;
}

// The photo-independent part of the default fit: the default wedges, the Gram
// factorisation, the class spectra and the wedges' systems.
// The candidates are the four classes and every basis, as `fit`'s default;
// the BRDF metric of the sensitivity penalty is a stand-in of the same size
// (the basis images' Gram matrix: the penalty's cost does not depend on its values).
struct ChoiceFactors {
  std::vector<int> fold;
  std::array<ChannelFactor, 3> f;
  std::vector<ClassSpectrum> classes;
  CvSystem cv;
  std::vector<Eigen::MatrixXd> metrics;
};
ChoiceFactors FactorForChoice(const Problem& p) {
  ChoiceFactors x;
  x.fold = WedgeFolds(p.g, kDefaultWedges);
  x.f = FactorBasisImages(p.Y, false);
  std::vector<int> all(p.Y[0].cols());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const std::vector<std::vector<int>> candidates = CandidateMembers(p.members, all, LambdaChoiceOptions{});
  x.classes = FactorClasses(x.f, candidates);
  x.cv = FactorFolds(x.f, FoldGrams(p.Y, x.fold, kDefaultWedges), candidates);
  x.metrics = ClassMetrics(x.f[0].gram, candidates);
  return x;
}
// The default's bound, read as `fit` reads it: the photo's pixel noise, or
// what the largest candidate's least-regularised fit leaves where that is
// less, read on the pixels and through the fit's residual.
double BoundNoiseOfPhoto(const Problem& p, const ChoiceFactors& x, const Observation& obs) {
  const LambdaChoiceOptions opt;
  return BoundNoise(BoundPixelNoise(RelativePixelNoise(p.g, p.y), p.g, p.Y, p.y, x.classes, obs, opt), x.classes, obs,
                    p.g.size(), opt);
}
LambdaChoiceOptions DefaultBound(const Problem& p, const ChoiceFactors& x, const Observation& obs) {
  return ResolveConditionBound(LambdaChoiceOptions{}, BoundNoiseOfPhoto(p, x, obs));
}

void BM_FactorGram(benchmark::State& state) {
  const Problem& p = TheProblem();
  for (auto _ : state) benchmark::DoNotOptimize(FactorBasisImages(p.Y, false));
}
BENCHMARK(BM_FactorGram)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FactorGramAndClasses(benchmark::State& state) {
  const Problem& p = TheProblem();
  for (auto _ : state) {
    const auto f = FactorBasisImages(p.Y, false);
    benchmark::DoNotOptimize(FactorClasses(f, p.members));
  }
}
BENCHMARK(BM_FactorGramAndClasses)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FactorWithFolds(benchmark::State& state) {  // everything `fit` factors by default
  const Problem& p = TheProblem();
  for (auto _ : state) benchmark::DoNotOptimize(FactorForChoice(p));
}
BENCHMARK(BM_FactorWithFolds)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FactorQr(benchmark::State& state) {  // the route for ill-conditioned systems
  const Problem& p = TheProblem();
  for (auto _ : state) benchmark::DoNotOptimize(FactorBasisImages(p.Y, true));
}
BENCHMARK(BM_FactorQr)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SolveFixedLambda(benchmark::State& state) {
  const Problem& p = TheProblem();
  const auto f = FactorBasisImages(p.Y, false);
  const auto classes = FactorClasses(f, p.members);
  for (auto _ : state)
    benchmark::DoNotOptimize(SolveClasswise(f, classes, MakeObservation(f, p.Y, p.y), SolveOptions{0.5}));
}
BENCHMARK(BM_SolveFixedLambda)->Unit(benchmark::kMillisecond)->UseRealTime();

// `fit`'s default: noise, bound, wedge pick; the argument is
// LambdaChoiceOptions::relative_wedges (1: the default).
void BM_SolveWithLambdaChoice(benchmark::State& state) {
  const Problem& p = TheProblem();
  const ChoiceFactors x = FactorForChoice(p);
  const auto& [fold, f, classes, cv, metrics] = x;
  for (auto _ : state) {
    const std::vector<Observation> held = FoldObservations(p.Y, p.y, fold, kDefaultWedges);
    const Observation obs = SumObservations(held);
    LambdaChoiceOptions opt = DefaultBound(p, x, obs);
    opt.relative_wedges = state.range(0) != 0;
    const LambdaChoice ch = ChooseLambda(f, classes, &cv, obs, held, p.g.size(), opt, &metrics);
    for (const LambdaChoice::Part& part : ch.parts)  // every part of a blend
      benchmark::DoNotOptimize(SolveClass(f, classes[part.cls], obs, part.lambda));
    state.counters["parts"] = static_cast<double>(ch.parts.size());
    state.counters["class"] = ch.chosen_class;
    state.counters["lambda"] = ch.lambda;
  }
}
BENCHMARK(BM_SolveWithLambdaChoice)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// The choice's three parts, each alone: projecting the photo by wedge (one
// pass over the basis images), the noise the bound follows (the photo's own
// and what the largest candidate's fit leaves: one more pass), and scoring
// the classes and λ within the bound then solving the pick.
void BM_ChoicePartProjectByWedge(benchmark::State& state) {
  const Problem& p = TheProblem();
  const std::vector<int> fold = WedgeFolds(p.g, kDefaultWedges);
  for (auto _ : state) {
    const std::vector<Observation> held = FoldObservations(p.Y, p.y, fold, kDefaultWedges);
    benchmark::DoNotOptimize(SumObservations(held));
  }
}
BENCHMARK(BM_ChoicePartProjectByWedge)->Unit(benchmark::kMillisecond)->UseRealTime();

// What reading the basis images alone costs (the projection's floor): the
// same bytes summed in float, rows split over the threads.
void BM_ReadBasisImagesOnly(benchmark::State& state) {
  const Problem& p = TheProblem();
  for (auto _ : state) {
    double total = 0;
    for (const MatrixXfR& Y : p.Y) {
#pragma omp parallel for schedule(static) reduction(+ : total)
      for (Eigen::Index r = 0; r < Y.rows(); ++r) total += Y.row(r).sum();
    }
    benchmark::DoNotOptimize(total);
  }
}
BENCHMARK(BM_ReadBasisImagesOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ChoicePartPhotoNoise(benchmark::State& state) {
  const Problem& p = TheProblem();
  const ChoiceFactors x = FactorForChoice(p);
  const Observation obs = SumObservations(FoldObservations(p.Y, p.y, x.fold, kDefaultWedges));
  for (auto _ : state) benchmark::DoNotOptimize(BoundNoiseOfPhoto(p, x, obs));
}
BENCHMARK(BM_ChoicePartPhotoNoise)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ChoicePartScoreAndSolve(benchmark::State& state) {
  const Problem& p = TheProblem();
  const ChoiceFactors x = FactorForChoice(p);
  const auto& [fold, f, classes, cv, metrics] = x;
  const std::vector<Observation> held = FoldObservations(p.Y, p.y, fold, kDefaultWedges);
  const Observation obs = SumObservations(held);
  const LambdaChoiceOptions opt = DefaultBound(p, x, obs);
  LambdaChoice ch;
  for (auto _ : state) {
    ch = ChooseLambda(f, classes, &cv, obs, held, p.g.size(), opt, &metrics);
    for (const LambdaChoice::Part& part : ch.parts)
      benchmark::DoNotOptimize(SolveClass(f, classes[part.cls], obs, part.lambda));
  }
  state.counters["condition_bound"] = opt.max_condition;
  state.counters["lambda"] = ch.lambda;
}
BENCHMARK(BM_ChoicePartScoreAndSolve)->Unit(benchmark::kMillisecond)->UseRealTime();

// The default's non-negative constraint: 47 k sampled bins of a table (every
// 31st of the 1.46 M), non-negative and heavy-tailed as BRDFs are; the bins
// restricted to each class are photo-independent and built outside the loop.
void BM_SolveWithLambdaChoiceAndBinConstraint(benchmark::State& state) {
  const Problem& p = TheProblem();
  const ChoiceFactors x = FactorForChoice(p);
  const auto& [fold, f, classes, cv, metrics] = x;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0, 1);
  const MatrixXfR tables = MatrixXfR::NullaryExpr(47000, 300, [&]() {
    const float v = u(rng);
    return v * v * v * v;
  });
  std::vector<BinRows> class_bins;
  for (const ClassSpectrum& c : classes) class_bins.push_back(BinRows::EveryNth(tables, c.members, 1));
  int negative_before = 0;
  for (auto _ : state) {
    const std::vector<Observation> held = FoldObservations(p.Y, p.y, fold, kDefaultWedges);
    const Observation obs = SumObservations(held);
    const LambdaChoice ch = ChooseLambda(f, classes, &cv, obs, held, p.g.size(), DefaultBound(p, x, obs), &metrics);
    WeightConstraint constraint;
    constraint.kind = WeightConstraint::Kind::kBins;
    for (const LambdaChoice::Part& part : ch.parts) {
      constraint.bins = &class_bins[part.cls];
      benchmark::DoNotOptimize(SolveClass(f, classes[part.cls], obs, part.lambda, constraint));
    }
    if (negative_before == 0) {
      const ClassSolution free = SolveClass(f, classes[ch.chosen_class], obs, ch.lambda);
      const Eigen::MatrixXd wJ = free.weights(classes[ch.chosen_class].members, Eigen::all);
      for (int c = 0; c < 3; ++c)
        negative_before += static_cast<int>((class_bins[ch.chosen_class].Times(wJ.col(c)).array() < 0).count());
    }
  }
  state.counters["bin_channels_below_zero_unconstrained"] = negative_before;
}
BENCHMARK(BM_SolveWithLambdaChoiceAndBinConstraint)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SolveQrRoute(benchmark::State& state) {  // COD of [R_J; √λ_j I] per class and channel
  const Problem& p = TheProblem();
  const auto f = FactorBasisImages(p.Y, true);
  for (auto _ : state) {
    const Observation obs = MakeObservation(f, p.Y, p.y);
    for (const auto& J : p.members)
      for (int c = 0; c < 3; ++c) {
        const Eigen::VectorXd prior = Eigen::VectorXd::Constant(J.size(), 1.0 / J.size());
        benchmark::DoNotOptimize(SolveRidge(f[c].R(Eigen::all, J), obs.z_qr[c], 0.5 * obs.norm2[c] / J.size(), prior));
      }
  }
}
BENCHMARK(BM_SolveQrRoute)->Unit(benchmark::kMillisecond)->UseRealTime();

// One channel's spectrum of the every-basis candidate (297 of the 300 bases,
// as the leave-one-out evaluation factors it for every material and scene),
// by the decompositions Eigen offers: its eigenvectors by QR iteration (what
// FactorClasses computes), its eigenvalues alone, the right singular vectors
// of the Gram matrix by divide and conquer (equal to the eigenvectors for a
// positive semi-definite matrix), and the tridiagonal form with Q formed (what
// the wedge systems use).
enum class Spectrum { kEigenvectors, kEigenvalues, kSingularVectors, kTridiagonalWithQ };
void BM_EveryBasisSpectrum(benchmark::State& state, Spectrum kind) {
  const Problem& p = TheProblem();
  static const Eigen::MatrixXd gram = [&] {
    const Eigen::MatrixXd g = FactorBasisImages(p.Y, false)[0].gram;
    return Eigen::MatrixXd(g.topLeftCorner(297, 297));
  }();
  for (auto _ : state) {
    switch (kind) {
      case Spectrum::kEigenvectors:
        benchmark::DoNotOptimize(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram).eigenvectors().data());
        break;
      case Spectrum::kEigenvalues:
        benchmark::DoNotOptimize(
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(gram, Eigen::EigenvaluesOnly).eigenvalues().data());
        break;
      case Spectrum::kSingularVectors:
        benchmark::DoNotOptimize(Eigen::BDCSVD<Eigen::MatrixXd>(gram, Eigen::ComputeThinV).matrixV().data());
        break;
      case Spectrum::kTridiagonalWithQ: {
        const Eigen::Tridiagonalization<Eigen::MatrixXd> tri(gram);
        const Eigen::MatrixXd q = tri.matrixQ();
        benchmark::DoNotOptimize(q.data());
      }
    }
  }
}
BENCHMARK_CAPTURE(BM_EveryBasisSpectrum, eigenvectors, Spectrum::kEigenvectors)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_EveryBasisSpectrum, eigenvalues, Spectrum::kEigenvalues)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_EveryBasisSpectrum, bdcsvd_v, Spectrum::kSingularVectors)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_EveryBasisSpectrum, tridiagonal_q, Spectrum::kTridiagonalWithQ)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The every-basis candidate's factor over R, G, B as the leave-one-out
// evaluation takes it (FactorClasses, 297 bases), held by its eigenvectors or
// in tridiagonal form, and then the solves one fit asks of it per channel:
// the noise reading's and the pick's at one λ each and the sensitivity's
// three λ.
void BM_EveryBasisFactorAndSolves(benchmark::State& state, SpectrumParts parts) {
  const Problem& p = TheProblem();
  static const std::array<ChannelFactor, 3> f = FactorBasisImages(p.Y, false);
  std::vector<int> J(297);
  for (int i = 0; i < 297; ++i) J[static_cast<size_t>(i)] = i;
  const Eigen::VectorXd lj = Eigen::Vector3d(1e-6, 1e-7, 1e-5) * f[0].gram.diagonal().mean();
  for (auto _ : state) {
    const ClassSpectrum cls = FactorClasses(f, {J}, parts)[0];
    for (int c = 0; c < 3; ++c) {
      const Eigen::VectorXd r = Eigen::VectorXd::Ones(297) - cls.gram_prior[c];
      benchmark::DoNotOptimize(SolveClassSystem(cls, c, r, lj.head(1)).data());
      benchmark::DoNotOptimize(SolveClassSystem(cls, c, r, lj.head(1)).data());
      benchmark::DoNotOptimize(SolveClassSystem(cls, c, r, lj).data());
    }
  }
}
BENCHMARK_CAPTURE(BM_EveryBasisFactorAndSolves, eigenvectors, SpectrumParts::kValuesAndVectors)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_EveryBasisFactorAndSolves, tridiagonal, SpectrumParts::kTridiagonal)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace brdfshot

BENCHMARK_MAIN();
