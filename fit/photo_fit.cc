#include "fit/photo_fit.h"

#include <cmath>

#include "fit/bin_constraints.h"
#include "fit/fit_confidence.h"
#include "fit/table_check.h"
#include "normals/observation.h"
#include "util/atomic_file.h"
#include "util/image_io.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

void CheckModelMatchesBases(const ClassModel& model, const std::string& model_source,
                            const std::vector<std::string>& names) {
  const std::vector<std::string>& bases = model.basis_names;
  if (bases.size() != names.size())
    throw FileError(model_source,
                    "has " + std::to_string(bases.size()) + " bases, the basis images " + std::to_string(names.size()));
  for (size_t i = 0; i < names.size(); ++i)
    if (bases[i] != names[i])
      throw FileError(model_source, "basis " + std::to_string(i) + " is '" + bases[i] + "', the basis images have '" +
                                        names[i] + "'");
}

std::string ConstraintName(WeightConstraint::Kind kind) {
  switch (kind) {
    case WeightConstraint::Kind::kWeights:
      return "non-negative weights";
    case WeightConstraint::Kind::kBins:
      return "non-negative bins";
    default:
      return "none";
  }
}

PhotoFit FitPhoto(const BasisImages& basis, const ClassModel& model, const Eigen::MatrixXd& y,
                  const PhotoFitOptions& opt, const BasisTables* tables, const std::vector<int>* folds_given) {
  BRDFSHOT_CHECK(static_cast<size_t>(y.rows()) == basis.geometry.size() && y.cols() == 3);
  BRDFSHOT_CHECK(model.label.size() == static_cast<size_t>(basis.Y[0].cols()));
  PhotoFit out;
  Stopwatch sw;
  // The folds serve the choice (rule cv) and the predicted error (every rule);
  // their Gram matrices add up to the whole photo's.
  const int folds = std::max(2, opt.folds);
  const std::vector<int> fold_of_pixel = folds_given ? *folds_given : WedgeFolds(basis.geometry, folds);
  BRDFSHOT_CHECK(fold_of_pixel.size() == basis.geometry.size());
  std::vector<std::array<Eigen::MatrixXd, 3>> fold_grams = FoldGrams(basis.Y, fold_of_pixel, folds);
  std::array<ChannelFactor, 3> f = FactorOfFolds(fold_grams);
  std::vector<std::vector<int>> model_members;
  for (int j = 0; j < model.classes(); ++j) model_members.push_back(model.Members(j));
  std::vector<int> every_basis(model.label.size());
  for (size_t i = 0; i < every_basis.size(); ++i) every_basis[i] = static_cast<int>(i);
  // The model's classes, then (by default) every basis as one more candidate.
  const std::vector<std::vector<int>> members = CandidateMembers(model_members, every_basis, opt.lambda);
  const std::vector<ClassSpectrum> classes = FactorClasses(f, members);
  // The BRDF metric (every constraint_stride-th bin of the tables) of the
  // prior sensitivity in the λ choice's penalty, and the confidence's image
  // metric, a sphere under suns (fit_confidence.h), the lighting a photo's
  // probe shows least. Both need the tables' grid (every basis file has one;
  // a table without its grid, as in unit tests of the solve, gets none).
  std::vector<Eigen::MatrixXd> metrics, sun_metrics;
  if (tables && basis.header.contains("grid") && basis.Grid().size() == static_cast<size_t>(tables->rows())) {
    metrics = ClassMetrics(SampledCosineGram(*tables, basis.Grid(), every_basis, std::max(1, opt.constraint_stride)),
                           members);
    sun_metrics = ClassMetrics(DirectionalImageGram(*tables, basis.Grid(), ConfidenceSuns()), members);
  }
  const CvSystem cv_system = FactorFolds(f, std::move(fold_grams), members);
  if (opt.constraint == WeightConstraint::Kind::kBins && !tables)
    throw Error("the non-negative-bin constraint needs the database's tables");
  out.seconds_factor = sw.Seconds();

  Stopwatch solve;
  const std::vector<Observation> held = FoldObservations(basis.Y, y, fold_of_pixel, folds);
  Observation obs = SumObservations(held);
  out.relative_noise = opt.relative_noise ? *opt.relative_noise : RelativePixelNoise(basis.geometry, y);
  out.bound_noise =
      BoundNoise(BoundPixelNoise(out.relative_noise, basis.geometry, basis.Y, y, classes, obs, opt.lambda), classes,
                 obs, basis.geometry.size(), opt.lambda);
  out.choice = ChooseLambda(f, classes, &cv_system, obs, held, basis.geometry.size(),
                            ResolveConditionBound(opt.lambda, out.bound_noise), metrics.empty() ? nullptr : &metrics);
  // Every class at the pick's λ, for fit.json's table; a part of the blend at its own.
  std::vector<double> lambda(classes.size(), out.choice.lambda);
  for (const LambdaChoice::Part& part : out.choice.parts) lambda[part.cls] = part.lambda;
  out.fit = SolveClasswise(f, classes, obs, lambda);
  // The chosen class by the rule, even where another class's data residual is lower.
  out.fit.chosen = out.choice.chosen_class;
  WeightConstraint constraint;
  constraint.kind = opt.constraint;
  bool needs_qr = false;
  for (const LambdaChoice::Part& part : out.choice.parts)
    needs_qr = needs_qr || out.fit.classes[part.cls].path != "normal";
  if (needs_qr && opt.constraint != WeightConstraint::Kind::kWeights) {
    // Too ill-conditioned for the normal equations (λ near 0): solve the parts
    // again through the QR of Y.
    AddQr(basis.Y, &f);
    obs = MakeObservation(f, basis.Y, y);
  }
  // Each part's class's sampled bins only: every candidate's together would
  // hold the sample twice over (every basis is a candidate too).
  std::vector<BinRows> bins(out.choice.parts.size());
  for (size_t i = 0; i < out.choice.parts.size(); ++i) {
    const LambdaChoice::Part& part = out.choice.parts[i];
    if (opt.constraint == WeightConstraint::Kind::kBins) {
      bins[i] = BinRows::EveryNth(*tables, classes[part.cls].members, std::max(1, opt.constraint_stride));
      constraint.bins = &bins[i];
    }
    if (opt.constraint != WeightConstraint::Kind::kNone || f[0].has_qr())
      out.fit.classes[part.cls] = SolveClass(f, classes[part.cls], obs, part.lambda, constraint);
  }
  out.seconds_solve = solve.Seconds();
  Stopwatch check;
  // The bins between the sampled ones: the whole table is checked, and any
  // that dip below zero join the constrained bins for another solve.
  if (opt.constraint == WeightConstraint::Kind::kBins) {
    TableCheckSource checks(*tables);  // a summary built for one part serves the next
    for (size_t i = 0; i < out.choice.parts.size(); ++i) {
      const LambdaChoice::Part& part = out.choice.parts[i];
      const TableKeep keep =
          KeepNonNegativeOnTable(f, classes[part.cls], obs, part.lambda, &checks, &bins[i], &out.fit.classes[part.cls]);
      out.negative_bins_added += keep.bins_added;
      out.mean_blend = std::max(out.mean_blend, keep.largest_mean_blend());
    }
  }
  out.seconds_table_check = check.Seconds();
  out.weights = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(every_basis.size()), 3);
  for (const LambdaChoice::Part& part : out.choice.parts)
    out.weights += part.weight * out.fit.classes[part.cls].weights;
  if (!sun_metrics.empty()) {
    out.confidence =
        ConfidenceOf(out.choice, classes, obs, [&](int cls) { return sun_metrics[static_cast<size_t>(cls)]; });
  } else {
    // Nothing to weigh the prior's moves with: the wedges' error alone.
    out.confidence.predicted_relit_error = out.choice.held_out_error;
    for (const LambdaChoice::Part& part : out.choice.parts)
      out.confidence.part_predicted_relit_error.push_back(part.held_out_error);
  }
  const Eigen::MatrixXd& w = out.weights;
  out.reconstruction.resize(y.rows(), 3);
  for (int c = 0; c < 3; ++c) out.reconstruction.col(c) = basis.Y[c].cast<double>() * w.col(c);
  out.relative_residual = std::sqrt((out.reconstruction - y).squaredNorm() / std::max(1e-300, y.squaredNorm()));
  if (basis.has_lobes()) {
    out.lobes = basis.Lobes("basis images");
    out.lambert_ggx = FitLambertGgx(out.lobes, MakeLobeSystem(basis.lobes, y));
  }
  return out;
}

FitRecord FitRecord::From(const PhotoFit& f, const BasisImages& basis, const std::string& photo) {
  FitRecord r;
  r.database = basis.header.value("database", "");
  r.database_kind = basis.header.value("database_kind", "");
  r.grid = basis.Grid();
  r.probe = basis.header.value("probe", "");
  r.photo = photo;
  r.lambda_rule = f.choice.rule;
  const std::string& path = f.fit.classes.at(f.fit.chosen).path;
  r.weights_constraint = path == "nonneg-weights" ? ConstraintName(WeightConstraint::Kind::kWeights)
                         : path == "nonneg-bins"  ? ConstraintName(WeightConstraint::Kind::kBins)
                                                  : ConstraintName(WeightConstraint::Kind::kNone);
  r.lambda = f.choice.lambda;
  r.lambda_beyond_condition_bound = f.choice.beyond_condition_bound;
  r.held_out_error = f.choice.held_out_error;
  r.prior_sensitivity = f.confidence.prior_sensitivity;
  r.predicted_relit_error = f.confidence.predicted_relit_error;
  r.relative_noise = f.relative_noise;
  r.bound_noise = f.bound_noise;
  r.condition_bound = f.choice.condition_bound;
  r.sensitivity_penalty = f.choice.sensitivity_penalty;
  r.penalty_gate = f.choice.penalty_gate;
  r.min_wedge_share = f.choice.min_wedge_share;
  r.chosen_class = f.fit.chosen;
  r.parts = f.choice.parts;
  BRDFSHOT_CHECK(f.confidence.part_predicted_relit_error.size() == r.parts.size(),
                 "the confidence and the choice differ in parts");
  for (size_t i = 0; i < r.parts.size(); ++i) r.parts[i].predicted_error = f.confidence.part_predicted_relit_error[i];
  r.relative_residual = f.relative_residual;
  for (const ClassSolution& s : f.fit.classes) r.classes.push_back({s.members, s.residual, s.condition[1], s.path});
  r.lambda_grid = f.choice.grid;
  r.lambda_scores = f.choice.score;
  r.bases = basis.BasisNames();
  r.weights = f.weights;
  r.seconds_factor = f.seconds_factor;
  r.seconds_solve = f.seconds_solve;
  r.seconds_table_check = f.seconds_table_check;
  r.negative_bins_added = f.negative_bins_added;
  r.mean_blend = f.mean_blend;
  r.lambert_ggx = f.lambert_ggx;
  r.lobes = f.lobes;
  return r;
}

namespace {
constexpr const char* kFitFormat = "brdfshot-fit-4";
// JSON has no infinity: an empty class's score is written as null.
nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
double FromFinite(const nlohmann::json& j) {
  return j.is_null() ? std::numeric_limits<double>::infinity() : j.get<double>();
}
}  // namespace

nlohmann::json FitRecord::ToJson() const {
  nlohmann::json j;
  j["format"] = kFitFormat;
  j["database"] = database;
  j["database_kind"] = database_kind;
  j["grid"] = {grid.n_th, grid.n_td, grid.n_pd};
  j["probe"] = probe;
  j["photo"] = photo;
  j["lambda"] = lambda;
  j["lambda_rule"] = lambda_rule;
  j["weights_constraint"] = weights_constraint;
  j["predicted_relit_error"] = predicted_relit_error;
  j["held_out_error"] = held_out_error;
  if (prior_sensitivity >= 0) j["prior_sensitivity"] = prior_sensitivity;
  j["chosen_class"] = chosen_class;
  j["blend"] = nlohmann::json::array();
  // A record made without its parts is the pick alone.
  const std::vector<LambdaChoice::Part> written =
      parts.empty() ? std::vector<LambdaChoice::Part>{{chosen_class, lambda, 1.0, predicted_relit_error, std::nan(""),
                                                       held_out_error}}
                    : parts;
  for (const LambdaChoice::Part& p : written)
    j["blend"].push_back({{"class", p.cls},
                          {"lambda", p.lambda},
                          {"weight", p.weight},
                          {"predicted_relit_error", p.predicted_error},
                          {"held_out_error", p.held_out_error}});
  j["relative_residual"] = relative_residual;
  j["classes"] = nlohmann::json::array();
  for (size_t k = 0; k < classes.size(); ++k)
    j["classes"].push_back({{"class", k},
                            {"members", classes[k].members},
                            {"residual", Finite(classes[k].residual)},
                            {"condition", Finite(classes[k].condition)},
                            {"path", classes[k].path}});
  nlohmann::json curve = nlohmann::json::array();
  for (const auto& row : lambda_scores) {
    nlohmann::json r = nlohmann::json::array();
    for (double v : row) r.push_back(Finite(v));
    curve.push_back(r);
  }
  j["lambda_choice"] = {
      {"rule", lambda_rule},
      {"grid", lambda_grid},
      {"score_per_class", curve},
      {"beyond_condition_bound", lambda_beyond_condition_bound},
      {"relative_pixel_noise", relative_noise},
      {"bound_noise", bound_noise},
      {"sensitivity_penalty", sensitivity_penalty},
      {"penalty_gate", penalty_gate},
      {"min_wedge_share", min_wedge_share},
      {"condition_bound", condition_bound},
      {"why", lambda_beyond_condition_bound
                  ? "no lambda of the grid kept any class within the condition bound: the grid's largest, the class "
                    "scoring best there"
              : lambda_rule == "cv" && sensitivity_penalty > 0
                  ? std::string("smallest held-out error over wedges of the sphere") +
                        (min_wedge_share >= 0 ? " (each relative to its own signal, at least min_wedge_share of "
                                                "the mean wedge's)"
                                              : "") +
                        " times (1 + sensitivity_penalty x the candidate's prior sensitivity)^2, any candidate "
                        "class, among the lambdas within the condition bound" +
                        (penalty_gate >= 0 ? std::string(" and not more than penalty_gate standard errors of the "
                                                         "per-wedge differences worse than their group's least "
                                                         "held-out error")
                                           : std::string())
              : lambda_rule == "cv"  ? "smallest held-out error over wedges of the sphere, any class, among the "
                                       "lambdas within the condition bound"
              : lambda_rule == "gcv" ? "smallest generalised cross-validation score, any class, among the lambdas "
                                       "within the condition bound"
              : lambda_rule == "residual"
                  ? "smallest in-sample residual, any class, among the lambdas within the condition bound: each "
                    "class at the least lambda the bound allows"
                  : "given by --lambda; class by residual"}};
  j["bases"] = bases;
  j["weights"] = nlohmann::json::array();
  for (Eigen::Index i = 0; i < weights.rows(); ++i)
    j["weights"].push_back({weights(i, 0), weights(i, 1), weights(i, 2)});
  j["negative_bins_constrained_after_check"] = negative_bins_added;
  j["class_mean_blend_after_check"] = mean_blend;
  j["seconds"] = {{"factor", seconds_factor}, {"solve", seconds_solve}, {"table_check", seconds_table_check}};
  if (lambert_ggx) j["lambert_ggx"] = lambert_ggx->ToJson(lobes);
  return j;
}

FitRecord FitRecord::FromJson(const nlohmann::json& j, const std::string& source) {
  try {
    if (j.at("format") != kFitFormat)
      throw FileError(source, "not a fit.json of this version (format " + j.at("format").dump() + "): fit again");
    FitRecord r;
    r.database = j.at("database");
    r.database_kind = j.at("database_kind");
    const auto& g = j.at("grid");
    r.grid = MerlGrid{g.at(0), g.at(1), g.at(2)};
    r.probe = j.at("probe");
    r.photo = j.at("photo");
    r.lambda = j.at("lambda");
    r.lambda_rule = j.at("lambda_rule");
    r.weights_constraint = j.at("weights_constraint");
    if (r.weights_constraint != ConstraintName(WeightConstraint::Kind::kNone) &&
        r.weights_constraint != ConstraintName(WeightConstraint::Kind::kWeights) &&
        r.weights_constraint != ConstraintName(WeightConstraint::Kind::kBins))
      throw FileError(source, "unknown weights_constraint \"" + r.weights_constraint + "\"");
    r.predicted_relit_error = j.at("predicted_relit_error");
    r.held_out_error = j.at("held_out_error");
    r.prior_sensitivity = j.value("prior_sensitivity", -1.0);  // absent: not measured
    r.chosen_class = j.at("chosen_class");
    r.relative_residual = j.at("relative_residual");
    for (const auto& c : j.at("classes"))
      r.classes.push_back({c.at("members").get<int>(), FromFinite(c.at("residual")), FromFinite(c.at("condition")),
                           c.at("path").get<std::string>()});
    r.lambda_grid = j.at("lambda_choice").at("grid").get<std::vector<double>>();
    r.lambda_beyond_condition_bound = j.at("lambda_choice").value("beyond_condition_bound", false);
    r.relative_noise = j.at("lambda_choice").value("relative_pixel_noise", -1.0);  // absent: not recorded
    r.bound_noise = j.at("lambda_choice").value("bound_noise", -1.0);
    r.condition_bound = j.at("lambda_choice").value("condition_bound", -1.0);
    r.sensitivity_penalty = j.at("lambda_choice").value("sensitivity_penalty", 0.0);
    r.penalty_gate = j.at("lambda_choice").value("penalty_gate", -1.0);
    r.min_wedge_share = j.at("lambda_choice").at("min_wedge_share");
    for (const auto& row : j.at("lambda_choice").at("score_per_class")) {
      std::vector<double> v;
      for (const auto& x : row) v.push_back(FromFinite(x));
      r.lambda_scores.push_back(v);
    }
    r.bases = j.at("bases").get<std::vector<std::string>>();
    const auto w = j.at("weights").get<std::vector<std::array<double, 3>>>();
    if (w.size() != r.bases.size()) throw FileError(source, "weights do not match the bases");
    if (r.chosen_class < 0 || static_cast<size_t>(r.chosen_class) >= r.classes.size())
      throw FileError(source, "chosen_class out of range");
    double weight_sum = 0;
    for (const auto& p : j.at("blend")) {
      r.parts.push_back({p.at("class").get<int>(), p.at("lambda").get<double>(), p.at("weight").get<double>(),
                         p.at("predicted_relit_error").get<double>(), std::nan(""),
                         p.at("held_out_error").get<double>()});
      if (r.parts.back().cls < 0 || static_cast<size_t>(r.parts.back().cls) >= r.classes.size())
        throw FileError(source, "a blend's class out of range");
      if (!(r.parts.back().weight >= 0)) throw FileError(source, "a blend's weight is negative");
      weight_sum += r.parts.back().weight;
    }
    if (r.parts.empty() || std::abs(weight_sum - 1) > 1e-9)
      throw FileError(source, "the blend's weights do not sum to 1");
    r.weights.resize(static_cast<Eigen::Index>(w.size()), 3);
    for (size_t i = 0; i < w.size(); ++i)
      for (int c = 0; c < 3; ++c) r.weights(static_cast<Eigen::Index>(i), c) = w[i][c];
    r.seconds_factor = j.at("seconds").at("factor");
    r.seconds_solve = j.at("seconds").at("solve");
    r.seconds_table_check = j.at("seconds").at("table_check");
    r.negative_bins_added = j.at("negative_bins_constrained_after_check");
    r.mean_blend = j.value("class_mean_blend_after_check", 0.0);  // absent: no blend
    if (!(r.mean_blend >= 0 && r.mean_blend <= 1))
      throw FileError(source, "class_mean_blend_after_check is not in [0, 1]");
    if (j.contains("lambert_ggx")) {
      r.lobes = LambertGgxLobes::FromJson(j.at("lambert_ggx").at("model"), source);
      r.lambert_ggx = LambertGgxFit::FromJson(j.at("lambert_ggx"), r.lobes, source);
    }
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("not a fit.json: ") + e.what());
  }
}

void FitRecord::Write(const std::string& path) const {
  const std::string text = ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& o) { o << text << "\n"; });
}

FitRecord FitRecord::Read(const std::string& path) { return FromJson(ReadJsonFile(path), path); }

Eigen::MatrixXd ReadFitPixels(const BasisImages& basis, const std::string& basis_path, const std::string& photo_path,
                              const std::string& obs_path) {
  Eigen::MatrixXd y(basis.geometry.size(), 3);
  if (!obs_path.empty()) {
    const Observations obs = Observations::Read(obs_path);
    if (obs.geometry.Hash() != basis.geometry.Hash())
      throw FileError(obs_path, "its pixels are not the ones " + basis_path +
                                    " was computed for: run 'brdfshot basis --obs " + obs_path + "'");
    return obs.rgb;
  }
  const cv::Mat photo = ReadHdrImage(photo_path);
  if (photo.cols != basis.geometry.width || photo.rows != basis.geometry.height)
    throw FileError(photo_path, "is " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows) +
                                    ", the basis images are for " + std::to_string(basis.geometry.width) + "x" +
                                    std::to_string(basis.geometry.height));
  for (size_t p = 0; p < basis.geometry.size(); ++p) {
    const cv::Vec3f v = photo.at<cv::Vec3f>(basis.geometry.y[p], basis.geometry.x[p]);
    for (int c = 0; c < 3; ++c) y(static_cast<Eigen::Index>(p), c) = v[c];
  }
  return y;
}

BasisDatabase DatabaseOfBases(const std::string& kind, const MerlGrid& grid, const std::vector<std::string>& bases,
                              DatabaseOptions opt) {
  opt.kind = kind;
  opt.grid = grid;
  opt.only = MaterialsOfBases(bases);
  opt.exclude.clear();
  opt.max_materials = 0;
  BasisDatabase base = LoadDatabase(opt);
  if (static_cast<size_t>(base.num_bases()) != bases.size())
    throw Error("the fit's " + std::to_string(bases.size()) + " bases are not in the database (" +
                std::to_string(base.num_bases()) + " found)");
  return base;
}

BasisDatabase DatabaseOfBases(const BasisImages& basis, DatabaseOptions opt) {
  const auto& g = basis.header.at("grid");
  return DatabaseOfBases(basis.header.value("database_kind", ""), MerlGrid{g.at(0), g.at(1), g.at(2)},
                         basis.BasisNames(), std::move(opt));
}

BasisDatabase DatabaseOfFit(const FitRecord& record, DatabaseOptions opt) {
  return DatabaseOfBases(record.database_kind, record.grid, record.bases, std::move(opt));
}

MerlBrdf BrdfOfFit(const FitRecord& record, const BasisDatabase& db, std::string* label, long* clamped) {
  if (label) *label = "fit over " + db.label;
  return CombineBases(db, record.weights, clamped);
}

MerlBrdf BrdfOfFit(const FitRecord& record, DatabaseOptions opt, std::string* label) {
  return BrdfOfFit(record, DatabaseOfFit(record, std::move(opt)), label);
}

MerlBrdf LambertGgxBrdf(const FitRecord& record) {
  BRDFSHOT_CHECK(record.lambert_ggx, "the fit record holds no Lambert + GGX fit");
  const LambertGgxFit& g = *record.lambert_ggx;
  // Only the chosen α's lobes: three columns instead of the whole grid's.
  LambertGgxLobes chosen;
  chosen.alphas = {g.alpha};
  BasisDatabase lobes;
  lobes.grid = record.grid;
  lobes.B = BasisTables(chosen.Tables(record.grid));
  const int r = g.alpha_index;
  return CombineBases(lobes, g.weights(std::vector<int>{0, 1 + 2 * r, 2 + 2 * r}, Eigen::all));
}

}  // namespace brdfshot
