#include "apps/common_options.h"

#include <cmath>

#include <filesystem>
#include <sstream>

#include "calib/calibrate.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

void DatabaseArgs::Add(po::options_description& d) {
  // clang-format off
  d.add_options()
      ("db", po::value(&kind)->default_value(kind), "database: auto | merl | nbrdf | standin "
       "(auto: real MERL files if present, else the neural fits, else the stand-in)")
      ("data", po::value(&data), "data folder (default: $BRDFSHOT_DATA, then ../shared)")
      ("merl-dir", po::value(&merl_dir), "folder of MERL .binary files (default: <data>/merl)")
      ("grid", po::value(&grid)->default_value(grid), "table grid n_th x n_td x n_pd for nbrdf/standin")
      ("materials", po::value(&materials), "comma-separated material names (default: all)")
      ("exclude", po::value(&exclude), "comma-separated material names to leave out (leave-one-out on a known material)")
      ("max-materials", po::value(&max_materials)->default_value(0), "keep N materials spread over the list (0: all)");
  // clang-format on
}

DatabaseOptions DatabaseArgs::ToOptions(bool progress) const {
  DatabaseOptions o;
  o.kind = kind;
  o.data_root = data;
  o.merl_dir = merl_dir;
  o.grid = ParseGrid(grid);
  o.only = SplitList(materials);
  o.exclude = SplitList(exclude);
  o.max_materials = max_materials;
  o.progress = progress;
  return o;
}

MerlGrid ParseGrid(const std::string& text) {
  MerlGrid g;
  char x1 = 0, x2 = 0;
  std::istringstream s(text);
  if (!(s >> g.n_th >> x1 >> g.n_td >> x2 >> g.n_pd) || x1 != 'x' || x2 != 'x' || g.n_th <= 0 || g.n_td <= 0 ||
      g.n_pd <= 0 || g.n_th > 1000 || g.n_td > 1000 || g.n_pd > 2000)
    throw Error("bad --grid '" + text + "': expected e.g. 90x90x180");
  return g;
}

cv::Size ParseImageSize(const std::string& text, const std::string& option, int min_side) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream s(text);
  if (!(s >> width >> x >> height) || x != 'x' || width < min_side || height < min_side)
    throw Error("bad " + option + " '" + text + "': expected WIDTHxHEIGHT, each ≥ " + std::to_string(min_side));
  return {width, height};
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::vector<double> ParseNumberList(const std::string& text, size_t count, const std::string& option,
                                    const std::string& names) {
  const std::vector<std::string> parts = SplitList(text);
  if (parts.size() != count) throw Error("bad " + option + " '" + text + "': expected " + names);
  std::vector<double> v;
  for (const std::string& p : parts) {
    try {
      v.push_back(std::stod(p));
    } catch (const std::exception&) {
      throw Error("bad " + option + " '" + text + "': expected " + std::to_string(count) + " numbers " + names);
    }
  }
  return v;
}

std::vector<double> ParseLambdaGrid(const std::string& text) {
  const std::vector<std::string> parts = SplitList(text);
  std::vector<double> grid = ParseNumberList(text, parts.size(), "--lambda-grid", "comma-separated numbers ≥ 0");
  if (grid.empty()) throw Error("bad --lambda-grid '" + text + "': give at least one value");
  for (double v : grid)
    if (!(v >= 0 && std::isfinite(v)))
      throw Error("bad --lambda-grid '" + text + "': every value must be finite and ≥ 0");
  return grid;
}

void AddConditionBoundOptions(po::options_description& d, LambdaChoiceOptions* choice) {
  // clang-format off
  d.add_options()
      ("max-condition", po::value(&choice->max_condition)->default_value(choice->max_condition),
       "a λ is a candidate only while the condition number of G_JJ + λ_j I stays below this; 0: from the photo's "
       "pixel noise (docs/method.md)")
      ("noise-margin", po::value(&choice->noise_bound.margin)->default_value(choice->noise_bound.margin),
       "with --max-condition 0: the bound is (m/ε)², ε the photo's pixel noise relative to its RMS: a direction of "
       "the weights is trusted down to an amplitude of ε/m")
      ("min-condition", po::value(&choice->noise_bound.min_bound)->default_value(choice->noise_bound.min_bound),
       "with --max-condition 0: the bound is never below this")
      ("max-noise-bound", po::value(&choice->noise_bound.max_bound)->default_value(choice->noise_bound.max_bound),
       "with --max-condition 0: the bound is never above this (a noise-free photo gets it)")
      ("residual-noise", po::value(&choice->noise_bound.read_fit_residual)->default_value(choice->noise_bound.read_fit_residual),
       "with --max-condition 0: 1: the pixel noise is also read on what the fit of every basis leaves, and the bound "
       "follows the lesser (a glossy shading's fine detail is not noise); 0: the photo's own reading")
      ("every-basis-candidate", po::value(&choice->all_bases_candidate)->default_value(choice->all_bases_candidate),
       "1: besides the model's classes, every basis is one more candidate class of the λ choice; 0: the classes only")
      ("sensitivity-penalty", po::value(&choice->sensitivity_penalty)->default_value(choice->sensitivity_penalty),
       "a: the wedges' error of each candidate is multiplied by (1 + a × its prior sensitivity) (docs/method.md); 0: not")
      ("penalty-gate", po::value(&choice->penalty_gate)->default_value(choice->penalty_gate),
       "z: with the penalty, a candidate competes only while its wedges' error exceeds its group's least by at most z "
       "standard errors of the per-wedge differences (docs/method.md); < 0: every candidate")
      ("relative-wedges", po::value(&choice->relative_wedges)->default_value(choice->relative_wedges),
       "1: each wedge's held-out error counts relative to the wedge's own signal (docs/method.md); 0: as it is")
      ("blend", po::value(&choice->blend_every_basis)->default_value(choice->blend_every_basis),
       "1: with the penalty and the every-basis candidate, the fit blends the best class and every basis, each at its "
       "own λ, weighted by 1 / penalised score (docs/method.md); 0: the pick alone")
      ("min-blend-weight", po::value(&choice->min_blend_weight)->default_value(choice->min_blend_weight),
       "with --blend 1: the lesser part is left out below this weight (0: always blended)");
  // clang-format on
}

void CheckConditionBound(const LambdaChoiceOptions& choice) {
  if (!(choice.max_condition >= 1 || choice.max_condition == 0))
    throw Error("--max-condition must be 0 (from the photo's noise) or at least 1");
  if (!(choice.noise_bound.margin > 0 && std::isfinite(choice.noise_bound.margin)))
    throw Error("--noise-margin must be positive");
  if (!(choice.min_blend_weight >= 0 && choice.min_blend_weight <= 0.5))
    throw Error("--min-blend-weight must lie in [0, 0.5]");
  if (std::isnan(choice.penalty_gate)) throw Error("--penalty-gate must be a number");
  if (!(choice.sensitivity_penalty >= 0 && std::isfinite(choice.sensitivity_penalty)))
    throw Error("--sensitivity-penalty must be finite and ≥ 0");
  if (!(choice.noise_bound.max_bound >= 1 && std::isfinite(choice.noise_bound.max_bound)))
    throw Error("--max-noise-bound must be finite and at least 1");
  if (!(choice.noise_bound.min_bound >= 1 && choice.noise_bound.min_bound <= choice.noise_bound.max_bound)) {
    std::ostringstream m;
    m << "--min-condition must lie in [1, " << choice.noise_bound.max_bound << "]";
    throw Error(m.str());
  }
}

void QualityArgs::Add(po::options_description& d) {
  // clang-format off
  d.add_options()
      ("theta-samples", po::value(&q.theta_samples)->default_value(q.theta_samples), "half-vector samples along sqrt(theta_h)")
      ("phi-samples", po::value(&q.phi_samples)->default_value(q.phi_samples), "half-vector samples along phi_h")
      ("probe-width", po::value(&q.probe_width)->default_value(q.probe_width), "resample the probe to this width first (0: as given)")
      ("level-step", po::value(&q.level_step_deg)->default_value(q.level_step_deg), "theta_o spacing (deg) of the pixel levels sharing table reads")
      ("level-substeps", po::value(&q.level_substeps)->default_value(q.level_substeps), "pixels snap to level-step/level-substeps in theta_o")
      ("brdf-supersample", po::value(&q.brdf_supersample)->default_value(q.brdf_supersample), "table reads per sample cell along sqrt(theta_h) (0: auto)");
  // clang-format on
}

double FocalLengthPx(double focal_px, double focal_35mm, cv::Size photo, const std::string& prefix) {
  if (!(focal_px >= 0 && std::isfinite(focal_px)))
    throw Error("--" + prefix + "focal-px must be a focal length in pixels, or 0 for orthographic");
  if (!(focal_35mm >= 0 && std::isfinite(focal_35mm)))
    throw Error("--" + prefix + "focal-35mm must be a focal length in mm, or 0");
  return focal_35mm > 0 ? FocalPxFrom35mm(focal_35mm, photo) : focal_px;
}

void MakeOutputDir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir, ec)) throw FileError(dir, "cannot create output folder");
}

WeightConstraint::Kind ParseConstraint(const std::string& text) {
  if (text == "none") return WeightConstraint::Kind::kNone;
  if (text == "weights") return WeightConstraint::Kind::kWeights;
  if (text == "bins") return WeightConstraint::Kind::kBins;
  throw Error("unknown --constraint '" + text + "': bins, weights or none");
}

}  // namespace brdfshot
