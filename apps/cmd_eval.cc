// brdfshot eval: every material of the database left out in turn (or another
// database's materials as targets), fitted under each probe by the default and
// its baselines, scored relit; CSV + markdown + plots (fit/evaluation.h).
#include <cstdio>
#include <sstream>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "fit/eval_report.h"
#include "fit/evaluation.h"
#include "fit/photo_fit.h"
#include "util/atomic_file.h"

namespace brdfshot {
namespace po = boost::program_options;

int EvalMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  EvaluationOptions eo;
  LooOptions& loo = eo.loo;
  std::string probes_arg, out = "eval_out", grid_arg;
  bool no_directional = false;
  std::string constraint = "bins";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("out,o", po::value(&out)->default_value(out), "output folder (CSV, markdown, plots)")
      ("probes", po::value(&probes_arg), "comma-separated probes (default: every <data>/envmaps/*.exr)")
      ("no-directional", po::bool_switch(&no_directional), "do not also score under small suns over a dim sky")
      ("sphere", po::value(&eo.sphere)->default_value(eo.sphere), "sphere diameter in pixels")
      ("margin", po::value(&eo.margin)->default_value(eo.margin), "drop pixels whose normal is further than this from the view (deg)")
      ("lambda", po::value(&loo.lambda)->default_value(loo.lambda), "regularisation weight of the fixed-λ methods ours and paper (paper: 0.5)")
      ("lambda-rule", po::value(&loo.choice.rule)->default_value(loo.choice.rule), "rule of the auto method: cv, gcv or fixed")
      ("constraint", po::value(&constraint)->default_value(constraint), "what the auto method keeps non-negative: bins, weights or none")
      ("folds", po::value(&eo.folds)->default_value(eo.folds), "wedges for the auto method's cross-validation")
      ("all-bases-candidate", po::bool_switch(&loo.choice.all_bases_candidate), "auto may also pick every basis as one class")
      ("max-condition", po::value(&loo.choice.max_condition)->default_value(loo.choice.max_condition), "auto: λ values beyond this condition number of G_JJ + λ_j I are not candidates")
      ("lambda-grid", po::value(&grid_arg), "comma-separated λ values the auto method chooses among (default: 0 … 10)")
      ("targets", po::value(&eo.targets_kind), "evaluate on another database's materials instead of leaving each out "
       "(e.g. standin: the analytic stand-ins, none of them in MERL), fitted with all of --db's bases")
      ("targets-data", po::value(&eo.targets_data), "data folder of --targets (default: --data)")
      ("classes", po::value(&loo.gmm.classes)->default_value(loo.gmm.classes), "Gaussians K")
      ("dims", po::value(&loo.gmm.dims)->default_value(loo.gmm.dims), "SVD coordinates N");
  // clang-format on
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("eval", "[options]", desc, argc, argv)) return 0;
  if (!grid_arg.empty()) loo.choice.grid = ParseLambdaGrid(grid_arg);
  loo.constraint = ParseConstraint(constraint);
  eo.directional = !no_directional;
  eo.quality = quality.q;
  eo.progress = true;
  for (const std::string& path : ResolveProbes(probes_arg, db.data)) eo.probes.push_back(LatLongProbe::Read(path));
  MakeOutputDir(out);

  const Evaluation ev = RunEvaluation(db.ToOptions(true), eo);
  std::ostringstream settings;
  settings << "database **" << ev.database_label << "** (" << ev.materials.size() << " materials, grid " << ev.grid.n_th
           << "x" << ev.grid.n_td << "x" << ev.grid.n_pd << "); sphere " << eo.sphere << " px (" << ev.pixels
           << " pixels, margin " << eo.margin << "°); quality " << eo.quality.Describe() << "; auto: λ by "
           << loo.choice.rule << " over " << eo.folds << " wedges, constraint: " << ConstraintName(loo.constraint)
           << "; ours and paper: λ = " << loo.lambda << "; N = " << loo.gmm.dims << ", K = " << loo.gmm.classes;
  const std::string report = EvaluationMarkdown(ev, settings.str(), loo.lambda);
  WriteEvaluationCsv(ev, out + "/eval.csv");
  WriteFileAtomic(out + "/eval.md", [&](std::ostream& o) { o << report; });
  const std::vector<std::string> plots = WriteEvaluationPlots(ev, out);
  std::printf("%s\nwrote %s/eval.csv, %s/eval.md, %s, %s\n", report.c_str(), out.c_str(), out.c_str(), plots[0].c_str(),
              plots[1].c_str());
  return 0;
}

}  // namespace brdfshot
