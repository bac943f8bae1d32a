// The evaluation sets run end to end (docs/benchmarks.md): the database's
// basis images under every probe and under directional light, the fits of
// every method, one row per material, probe and method. Leave-one-out over
// the database (set a) or, with `targets_kind`, another database's materials
// fitted with all of this one's bases (set b).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/database.h"
#include "fit/lambda_choice.h"
#include "fit/loo_eval.h"
#include "fit/transport.h"

namespace brdfshot {

struct EvaluationOptions {
  std::vector<LatLongProbe> probes;  // fitted from and scored under (each scored under the others)
  bool directional = true;           // also score under DirectionalScoringProbes()
  int sphere = 64;                   // diameter in pixels
  double margin = 80;                // pixels whose normal is further from the view are dropped (deg)
  int folds = kDefaultWedges;        // wedges for the auto method
  RenderQuality quality;
  std::string targets_kind, targets_data;  // set b: another database's materials (data root "" = the bases')
  LooOptions loo;
  // The auto fit keeps every constraint_stride-th bin of the tables
  // non-negative (as `fit` does); negative values are counted on the bins
  // ≡ constraint_stride / 2 modulo constraint_stride, every ninth of them —
  // bins the constraint never saw. A prime stride keeps both samples from
  // aliasing with the grid's dimensions.
  int constraint_stride = 31;
  // Then the whole table is checked and bins below zero join the constraint,
  // as `fit` does (fit/table_check.h). Off by default: over a whole set it
  // costs about twice the rest of the fits (docs/benchmarks.md).
  bool check_whole_table = false;
  bool count_negative_bins = true;
  std::string class_features = "linear";  // ClassFeaturesHelp()
  bool lambert_ggx = true;                // the analytic baseline (fit/lambert_ggx.h, default lobes)
  bool progress = false;
};

struct Evaluation {
  std::string database_label, targets_label;  // targets_label empty for leave-one-out
  MerlGrid grid;
  std::vector<std::string> materials;  // the scored materials
  std::vector<std::string> probes, directional_probes;
  size_t pixels = 0;
  // Groups for per-group tables: a target's family, or a database material's
  // class in the full-database model (majority of its channels).
  std::string group_kind;   // "family" or "class"
  std::string class_sizes;  // of the full-database model ("" for targets)
  std::vector<std::string> groups;
  std::map<std::string, int> group_of;  // material → index into groups
  double lowest_basis_value = 0;        // over the sampled bins: < 0 means the bases themselves go negative
  LooResult result;
  double seconds_database = 0, seconds_grams = 0, seconds_basis = 0, seconds_fits = 0, seconds_total = 0;
  int shard_index = 0, shard_count = 1;  // result holds this shard's rows (EvaluationOptions::loo)
};

// Small suns over a dim sky, at 15° and 45° above the horizon, from the
// camera's side (front), from 90° to the side and from 160° behind: the
// lighting that tests highlights and their falloff, which broad natural
// probes say least about.
std::vector<LatLongProbe> DirectionalScoringProbes(int width = 256);

// Error naming the problem for fewer than two probes, or an unknown targets kind.
Evaluation RunEvaluation(const DatabaseOptions& db, const EvaluationOptions& opt);

}  // namespace brdfshot
