// The whole-table check of a fitted BRDF (fit/table_check.h) against the
// plain pass over every bin (NegativeBins), on the database `fit` uses (MERL,
// or its neural fits; skipped where neither is found). The weights are a
// class's mean, 1/k on each of its members, perturbed by Gaussian noise of
// `spread`/k: spread 0.5 is a well-regularised fit, 8 one near least squares
// whose weights cancel. Numbers in docs/benchmarks.md; run:
// build/fit/fit_table_check_benchmark.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "fit/bin_constraints.h"
#include "fit/class_model.h"
#include "fit/database.h"
#include "fit/table_check.h"

namespace brdfshot {
namespace {

struct Setup {
  BasisDatabase db;
  std::vector<std::vector<int>> classes;  // the full database's, largest first
  std::string error;
};

const Setup& TheSetup() {
  static const Setup s = [] {
    Setup s;
    try {
      s.db = LoadDatabase(DatabaseOptions{});
      const ClassModel model = BuildClassModel(LoadDatabaseGrams(DatabaseOptions{}).gram, GmmOptions{});
      for (int j = 0; j < model.classes(); ++j) s.classes.push_back(model.Members(j));
      std::sort(s.classes.begin(), s.classes.end(), [](auto& a, auto& b) { return a.size() > b.size(); });
    } catch (const std::exception& e) {
      s.error = e.what();
    }
    return s;
  }();
  return s;
}

Eigen::MatrixXd Weights(const std::vector<int>& members, double spread) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  const double k = static_cast<double>(members.size());
  Eigen::MatrixXd w(static_cast<Eigen::Index>(members.size()), 3);
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = (1 + spread * g(rng)) / k;
  return w;
}

// Args: the class (0: largest), the spread ×10.
void BM_NegativeBinsEveryBin(benchmark::State& state) {
  const Setup& s = TheSetup();
  if (!s.error.empty()) return state.SkipWithError(s.error.c_str());
  const std::vector<int>& J = s.classes.at(static_cast<size_t>(state.range(0)));
  const Eigen::MatrixXd w = Weights(J, 0.1 * static_cast<double>(state.range(1)));
  size_t found = 0;
  for (auto _ : state) found = NegativeBins(s.db.B, J, w).size();
  state.counters["members"] = static_cast<double>(J.size());
  state.counters["negative_bins"] = static_cast<double>(found);
}

void BM_TableCheckBuild(benchmark::State& state) {  // once per fit (or per evaluation); Args: block and sub-block rows
  const Setup& s = TheSetup();
  if (!s.error.empty()) return state.SkipWithError(s.error.c_str());
  for (auto _ : state) {
    const TableCheck check(s.db.B, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    benchmark::DoNotOptimize(check.blocks());
  }
}

// Args as BM_NegativeBinsEveryBin, then the block's and the sub-block's rows.
void BM_TableCheckNegativeBins(benchmark::State& state) {
  const Setup& s = TheSetup();
  if (!s.error.empty()) return state.SkipWithError(s.error.c_str());
  const std::vector<int>& J = s.classes.at(static_cast<size_t>(state.range(0)));
  const Eigen::MatrixXd w = Weights(J, 0.1 * static_cast<double>(state.range(1)));
  const TableCheck check(s.db.B, static_cast<int>(state.range(2)), static_cast<int>(state.range(3)));
  size_t found = 0;
  double cleared = 0;
  for (auto _ : state) found = check.NegativeBins(J, w, &cleared).size();
  state.counters["members"] = static_cast<double>(J.size());
  state.counters["negative_bins"] = static_cast<double>(found);
  state.counters["bins_cleared"] = cleared;
}

// A fit solved again: the weights of BM_TableCheckNegativeBins checked, then
// moved by Gaussian noise of `nudge`/1000 of their spread (the third Arg),
// checked again by the sequence (timed) and by a fresh check (not timed).
void BM_TableCheckSequenceNudge(benchmark::State& state) {
  const Setup& s = TheSetup();
  if (!s.error.empty()) return state.SkipWithError(s.error.c_str());
  const std::vector<int>& J = s.classes.at(static_cast<size_t>(state.range(0)));
  const double spread = 0.1 * static_cast<double>(state.range(1)), nudge = 1e-3 * static_cast<double>(state.range(2));
  const Eigen::MatrixXd w = Weights(J, spread);
  std::mt19937 rng(12);
  std::normal_distribution<double> g(0, 1);
  Eigen::MatrixXd moved = w;
  for (Eigen::Index i = 0; i < moved.size(); ++i) moved(i) += nudge * spread * g(rng) / static_cast<double>(J.size());
  const TableCheck check(s.db.B);
  double read = 0;
  size_t found = 0;
  for (auto _ : state) {
    state.PauseTiming();
    TableCheckSequence sequence(check, J);
    sequence.NegativeBins(w);
    state.ResumeTiming();
    found = sequence.NegativeBins(moved, &read).size();
  }
  state.counters["bins_read"] = read;
  state.counters["negative_bins"] = static_cast<double>(found);
  state.counters["same_as_fresh"] = check.NegativeBins(J, moved).size() == found;
}

}  // namespace

BENCHMARK(BM_NegativeBinsEveryBin)->Args({0, 5})->Args({0, 20})->Args({0, 80})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TableCheckBuild)->Args({128, 0})->Args({128, 16})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TableCheckNegativeBins)
    ->ArgsProduct({{0}, {5, 20, 80}, {32, 128, 256}, {0}})
    ->ArgsProduct({{0}, {5, 20, 80}, {128}, {8, 16, 32}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_TableCheckSequenceNudge)->ArgsProduct({{0}, {20, 80}, {10, 50}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace brdfshot

BENCHMARK_MAIN();
