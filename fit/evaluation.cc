#include "fit/evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "calib/sun_probe.h"
#include "fit/class_model.h"
#include "fit/fit_confidence.h"
#include "fit/lambda_choice.h"
#include "fit/ood_eval.h"
#include "fit/photo_noise.h"
#include "fit/table_check.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

namespace {
// RelativePixelNoise of every material's photo in `images` (pixels × 3M per
// channel; material m's channel c is column 3m + c).
std::vector<double> PhotoNoisePerMaterial(const PixelGeometry& g, const std::array<MatrixXfR, 3>& images) {
  const int M = static_cast<int>(images[0].cols() / 3);
  std::vector<double> noise(M);
#pragma omp parallel for schedule(static)
  for (int m = 0; m < M; ++m) noise[m] = RelativePixelNoise(g, MaterialImage(images, m));
  return noise;
}
}  // namespace

std::vector<LatLongProbe> DirectionalScoringProbes(int width) {
  struct Sun {
    const char* side;
    double azimuth_deg;  // from the view direction (+z) towards +x
  };
  const Sun suns[] = {{"front", 0}, {"side", 90}, {"back", 160}};
  // The sky's irradiance on an upward-facing patch (π L) is 3 % of the sun's.
  const float sky = static_cast<float>(0.03 / kPi);
  std::vector<LatLongProbe> out;
  for (const double elevation : {15.0, 45.0})
    for (const Sun& s : suns) {
      const double el = elevation * kPi / 180, az = s.azimuth_deg * kPi / 180;
      const Vec3 d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
      const LatLongProbe p = SunOverSkyProbe(d, cv::Vec3f(1, 1, 1), cv::Vec3f(sky, sky, sky), 2.0, width);
      out.emplace_back(p.rgb(), std::string("sun-") + s.side + "-" + std::to_string(static_cast<int>(elevation)));
    }
  return out;
}

namespace {
void GroupMaterials(const BasisDatabase& base, const BasisDatabase& targets, const LooInputs& in, const GmmOptions& gmm,
                    Evaluation* ev) {
  if (!targets.materials.empty()) {
    ev->group_kind = "family";
    for (size_t m = 0; m < targets.materials.size(); ++m) {
      const std::string fam = m < targets.families.size() ? targets.families[m] : "all";
      auto it = std::find(ev->groups.begin(), ev->groups.end(), fam);
      if (it == ev->groups.end()) ev->groups.push_back(fam), it = ev->groups.end() - 1;
      ev->group_of[targets.materials[m]] = static_cast<int>(it - ev->groups.begin());
    }
    return;
  }
  ev->group_kind = "class";
  const ClassModel full = BuildClassModel(in.class_gram.size() ? in.class_gram : in.gram, gmm);
  ev->class_sizes = ClassSizes(full);
  for (int k = 0; k < full.classes(); ++k) ev->groups.push_back("class " + std::to_string(k));
  for (int m = 0; m < base.num_materials(); ++m) {
    // The majority of the three channels' classes (the lowest on a three-way tie).
    std::map<int, int> votes;
    for (int c = 0; c < 3; ++c) votes[full.label[3 * m + c]]++;
    ev->group_of[base.materials[m]] =
        std::max_element(votes.begin(), votes.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
  }
}
}  // namespace

Evaluation RunEvaluation(const DatabaseOptions& db, const EvaluationOptions& opt) {
  if (opt.probes.size() < 2) throw Error("the evaluation needs at least two probes: one to fit, one to score under");
  Stopwatch total;
  Evaluation ev;
  const BasisDatabase base = LoadDatabase(db);
  ev.database_label = base.label;
  ev.grid = base.grid;
  ev.seconds_database = total.Seconds();

  Stopwatch sw;
  LooInputs in;
  in.materials = base.materials;
  {
    DatabaseOptions gopt = db;
    gopt.progress = false;
    DatabaseGrams grams = LoadDatabaseGrams(gopt);
    in.gram = std::move(grams.gram);
    in.gram_cos = std::move(grams.gram_cos);
  }
  in.sun_gram = DirectionalImageGram(base.B, base.grid, ConfidenceSuns());
  if (opt.class_features == "cos") {
    in.class_gram = in.gram_cos;
  } else if (opt.class_features == "log-cos") {
    const std::vector<float> cosw = base.grid.CosineWeightTable();
    in.class_gram = GramMatrix(base.B, &cosw, TableMapping::kLog);
  } else if (opt.class_features != "linear") {
    throw Error("unknown class features '" + opt.class_features + "' (" + ClassFeaturesHelp() + ")");
  }
  std::unique_ptr<TableCheck> table_check;  // reads base.B, which lives to the end of the run
  if (opt.loo.constraint == WeightConstraint::Kind::kBins) {
    in.constraint_sample = SampleBins(base.B, opt.constraint_stride);
    if (opt.check_whole_table) table_check = std::make_unique<TableCheck>(base.B), in.table_check = table_check.get();
  }
  if (opt.count_negative_bins) {
    in.bin_sample = SampleBins(base.B, 9 * opt.constraint_stride, opt.constraint_stride / 2);
    ev.lowest_basis_value = in.bin_sample.size() ? in.bin_sample.minCoeff() : 0.0f;
  }
  ev.seconds_grams = sw.Seconds();

  BasisDatabase targets;
  const bool ood = !opt.targets_kind.empty();
  if (ood) {
    DatabaseOptions topt = db;
    topt.kind = opt.targets_kind;
    if (!opt.targets_data.empty()) topt.data_root = opt.targets_data;
    topt.grid = base.grid;
    topt.only.clear(), topt.exclude.clear(), topt.max_materials = 0;
    targets = LoadDatabase(topt);
    ev.targets_label = targets.label;
  }
  ev.materials = ood ? targets.materials : base.materials;
  GroupMaterials(base, targets, in, opt.loo.gmm, &ev);

  const PixelGeometry geometry = OrthographicSphere(opt.sphere, opt.margin);
  ev.pixels = geometry.size();
  const std::vector<int> fold_of_pixel = WedgeFolds(geometry, opt.folds);
  const std::vector<int> one_fold(geometry.size(), 0);
  std::vector<LatLongProbe> scenes = opt.probes;
  const size_t fitted = scenes.size();
  if (opt.directional)
    for (LatLongProbe& p : DirectionalScoringProbes()) scenes.push_back(std::move(p));
  std::vector<TargetScene> target_scenes;
  Stopwatch bw;
  std::vector<TransportOperator> operators;
  for (const LatLongProbe& probe : scenes)
    operators.push_back(TransportOperator::Build(geometry, probe, base.grid, opt.quality));
  std::vector<const TransportOperator*> ops;
  for (const TransportOperator& t : operators) ops.push_back(&t);
  // Every scene and every table at once: the table reads are the same for
  // every scene, and each scene's lighting the same for every table.
  std::vector<std::array<MatrixXfR, 3>> Ys, Yts, lobes;
  {
    const MatrixXfR lobe_tables = opt.lambert_ggx ? in.lobes.Tables(base.grid) : MatrixXfR();
    std::vector<TablesMap> tables = {MapOf(base.B)};
    if (ood) tables.push_back(MapOf(targets.B));
    if (opt.lambert_ggx) tables.push_back(MapOf(lobe_tables));
    for (auto& parts : TransportOperator::ApplyAll(ops, tables)) {
      Ys.push_back(std::move(parts[0]));
      if (ood) Yts.push_back(std::move(parts[1]));
      if (opt.lambert_ggx) lobes.push_back(std::move(parts.back()));
    }
  }
  if (opt.progress)
    std::fprintf(stderr, "basis images: %zu scenes, %zu pixels x %d bases, %d theta_o levels, %.2f s\n", scenes.size(),
                 geometry.size(), base.num_bases(), operators.front().levels(), bw.Seconds());
  for (size_t i = 0; i < scenes.size(); ++i) {
    const bool scoring_only = i >= fitted;
    const std::array<MatrixXfR, 3>& Y = Ys[i];
    SceneFactors s;
    s.probe = scenes[i].name();
    s.scoring_only = scoring_only;
    s.pixels = geometry.size();
    s.f = FactorBasisImages(Y, !scoring_only);
    if (!scoring_only) s.fold_gram = FoldGrams(Y, fold_of_pixel, opt.folds);
    // Leave-one-out holds each material's every-basis candidate on the
    // scene's every basis: one factor per wedge for all materials.
    if (!scoring_only && !ood) s.fold_all = FactorFoldsOfAll(s.f, s.fold_gram);
    if (!scoring_only) s.photo_noise = PhotoNoisePerMaterial(geometry, ood ? Yts[i] : Y);
    if (ood) {
      target_scenes.push_back(scoring_only ? MakeTargetScene(s.f, Y, Yts[i], one_fold, 1)
                                           : MakeTargetScene(s.f, Y, Yts[i], fold_of_pixel, opt.folds));
      target_scenes.back().images = &Ys[i];
      target_scenes.back().target_images = &Yts[i];
    }
    if (opt.lambert_ggx) in.lobe_scenes.push_back(MakeLobeScene(ood ? Yts[i] : Y, lobes[i]));
    if (!ood) s.images = &Ys[i];
    (scoring_only ? ev.directional_probes : ev.probes).push_back(s.probe);
    in.scenes.push_back(std::move(s));
  }
  ev.seconds_basis = bw.Seconds();

  in.geometry = &geometry;
  LooOptions loo = opt.loo;
  loo.progress = opt.progress;
  Stopwatch fw;
  ev.shard_index = opt.loo.shard_index;
  ev.shard_count = opt.loo.shard_count;
  ev.result = ood ? RunOutOfDatabase(in, target_scenes, targets.materials, loo) : RunLeaveOneOut(in, loo);
  ev.seconds_fits = fw.Seconds();
  ev.seconds_total = total.Seconds();
  return ev;
}

}  // namespace brdfshot
