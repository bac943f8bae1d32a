// brdfshot eval: every material of the database left out in turn (or another
// database's materials as targets), fitted under each probe by the default and
// its baselines, scored relit; CSV + markdown + plots (fit/evaluation.h). In
// independent jobs: `--shard i/n` runs every n-th material and writes a shard,
// `--merge` makes the tables of all n (fit/evaluation_shard.h).
#include <cstdio>
#include <sstream>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "fit/eval_report.h"
#include "fit/evaluation.h"
#include "fit/evaluation_shard.h"
#include "fit/photo_fit.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

// The command line as typed; ToOptions checks it and fills the evaluation's options.
struct EvalArgs {
  DatabaseArgs db;
  QualityArgs quality;
  EvaluationOptions eo;
  std::string probes, out = "eval_out", grid, constraint = "bins", shard, merge;
  bool no_directional = false, check_whole_table = false;

  void Add(po::options_description& desc) {
    LooOptions& loo = eo.loo;
    // clang-format off
    desc.add_options()
        ("out,o", po::value(&out)->default_value(out), "output folder (CSV, markdown, plots; or the shard)")
        ("probes", po::value(&probes), "comma-separated probes (default: every <data>/envmaps/*.exr)")
        ("no-directional", po::bool_switch(&no_directional), "do not also score under small suns over a dim sky")
        ("sphere", po::value(&eo.sphere)->default_value(eo.sphere), "sphere diameter in pixels")
        ("margin", po::value(&eo.margin)->default_value(eo.margin), "drop pixels whose normal is further than this from the view (deg)")
        ("lambda", po::value(&loo.lambda)->default_value(loo.lambda), "regularisation weight of the fixed-λ methods ours and paper (paper: 0.5)")
        ("lambda-rule", po::value(&loo.choice.rule)->default_value(loo.choice.rule), "rule of the auto method: cv, residual, gcv or fixed")
        ("constraint", po::value(&constraint)->default_value(constraint), "what the auto method keeps non-negative: bins, weights or none")
        ("check-whole-table", po::bool_switch(&check_whole_table), "with --constraint bins: after every 31st bin, check the whole "
         "table and constrain the bins below zero, as fit does (several times the run's time: docs/benchmarks.md)")
        ("folds", po::value(&eo.folds)->default_value(eo.folds), "wedges for the auto method's cross-validation")
        ("joint", po::bool_switch(&loo.joint), "also fit every material from two photos at once (each probe's with the next "
         "probe's) and score it against each photo alone, under the probes neither was taken under")
        ("lambda-grid", po::value(&grid), "comma-separated λ values the auto method chooses among (default: 0 … 10)")
        ("targets", po::value(&eo.targets_kind), "evaluate on another database's materials instead of leaving each out "
         "(e.g. standin: the analytic stand-ins, none of them in MERL), fitted with all of --db's bases")
        ("targets-data", po::value(&eo.targets_data), "data folder of --targets (default: --data)")
        ("classes", po::value(&loo.gmm.classes)->default_value(loo.gmm.classes), "Gaussians K")
        ("dims", po::value(&loo.gmm.dims)->default_value(loo.gmm.dims), "SVD coordinates N")
        ("class-features", po::value(&eo.class_features)->default_value(eo.class_features), "what the classes of ours and auto are built on: linear, cos or log-cos tables")
        ("shard", po::value(&shard), "i/n: run only every n-th material, from the i-th (0-based), and write <out>/eval_shard_i_of_n.json")
        ("merge", po::value(&merge), "comma-separated shard files of one run: write the tables of all of them");
    // clang-format on
    AddConditionBoundOptions(desc, &loo.choice);
    db.Add(desc);
    quality.Add(desc);
  }

  EvaluationOptions ToOptions() {
    if (!grid.empty()) eo.loo.choice.grid = ParseLambdaGrid(grid);
    CheckConditionBound(eo.loo.choice);
    eo.loo.constraint = ParseConstraint(constraint);
    eo.directional = !no_directional;
    eo.check_whole_table = check_whole_table;
    eo.quality = quality.q;
    eo.progress = true;
    if (!shard.empty()) {
      const size_t slash = shard.find('/');
      const std::vector<double> v =
          ParseNumberList(slash == std::string::npos ? shard : shard.substr(0, slash) + "," + shard.substr(slash + 1),
                          2, "--shard", "i/n");
      if (!(v[1] >= 1 && v[0] >= 0 && v[0] < v[1] && v[0] == int(v[0]) && v[1] == int(v[1])))
        throw Error("--shard " + shard + ": expected i/n with 0 ≤ i < n, e.g. 0/8");
      eo.loo.shard_index = static_cast<int>(v[0]), eo.loo.shard_count = static_cast<int>(v[1]);
    }
    for (const std::string& path : ResolveProbes(probes, db.data)) eo.probes.push_back(LatLongProbe::Read(path));
    return eo;
  }

  // How the auto method bounds and weighs its candidates; part of the settings, so that
  // shards of runs that choose differently are never merged.
  static std::string ChoiceSettings(const LambdaChoiceOptions& c) {
    std::ostringstream s;
    s << (c.all_bases_candidate ? " (the classes and every basis" : " (the classes");
    if (c.sensitivity_penalty > 0) {
      s << "; sensitivity penalty " << c.sensitivity_penalty;
      if (c.penalty_gate >= 0) s << " within " << c.penalty_gate << " standard errors";
      if (c.blend_every_basis && c.all_bases_candidate) s << "; blend down to weight " << c.min_blend_weight;
    }
    s << (c.relative_wedges ? "; wedges relative" : "; wedges as they are");
    if (c.max_condition > 0)
      s << "; condition bound " << c.max_condition;
    else
      s << "; condition bound from the " << (c.noise_bound.read_fit_residual ? "lesser noise reading" : "photo's noise")
        << ", margin " << c.noise_bound.margin << ", within [" << c.noise_bound.min_bound << ", "
        << c.noise_bound.max_bound << "]";
    s << ")";
    return s.str();
  }

  // What the markdown states about the run.
  std::string Settings(const Evaluation& ev) const {
    std::ostringstream s;
    s << "database **" << ev.database_label << "** (" << ev.materials.size() << " materials, grid " << ev.grid.n_th
      << "x" << ev.grid.n_td << "x" << ev.grid.n_pd << "); sphere " << eo.sphere << " px (" << ev.pixels
      << " pixels, margin " << eo.margin << "°); quality " << eo.quality.Describe() << "; auto: λ by "
      << eo.loo.choice.rule << " over " << eo.folds << " wedges" << ChoiceSettings(eo.loo.choice)
      << ", constraint: " << ConstraintName(eo.loo.constraint)
      << (eo.loo.constraint != WeightConstraint::Kind::kBins ? ""
          : eo.check_whole_table                             ? " (the whole table checked)"
                                                             : " (every 31st bin only)")
      << "; ours and paper: λ = " << eo.loo.lambda << "; N = " << eo.loo.gmm.dims << ", K = " << eo.loo.gmm.classes
      << " on the " << eo.class_features << " tables";
    return s.str();
  }
};

}  // namespace

int EvalMain(int argc, char** argv) {
  EvalArgs args;
  po::options_description desc("options");
  args.Add(desc);
  if (!ParseOptions("eval", "[options]", desc, argc, argv)) return 0;
  MakeOutputDir(args.out);
  EvaluationShard run;
  if (!args.merge.empty()) {
    std::vector<EvaluationShard> shards;
    const std::vector<std::string> files = SplitList(args.merge);
    for (const std::string& f : files) shards.push_back(ReadEvaluationShard(f));
    run = MergeEvaluationShards(shards, files);
  } else {
    const EvaluationOptions eo = args.ToOptions();
    run.evaluation = RunEvaluation(args.db.ToOptions(true), eo);
    run.settings = args.Settings(run.evaluation), run.fixed_lambda = eo.loo.lambda;
  }
  const Evaluation& ev = run.evaluation;
  if (ev.shard_count > 1) {
    const std::string path =
        args.out + "/eval_shard_" + std::to_string(ev.shard_index) + "_of_" + std::to_string(ev.shard_count) + ".json";
    WriteEvaluationShard(run, path);
    std::printf("shard %d of %d: %zu rows in %.1f s\nwrote %s\n", ev.shard_index, ev.shard_count, ev.result.rows.size(),
                ev.seconds_total, path.c_str());
    return 0;
  }
  std::vector<std::string> written;
  const std::string report = WriteEvaluationReport(ev, run.settings, run.fixed_lambda, args.out, &written);
  std::printf("%s\nwrote", report.c_str());
  for (const std::string& w : written) std::printf(" %s", w.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace brdfshot
