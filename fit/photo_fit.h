// Fitting one photo: its pixels, the scene's basis images and the database's
// class model in, the weights and how they were chosen out — and the fit.json
// that records it (one writer, one reader).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "fit/basis_images.h"
#include "fit/database.h"
#include "fit/class_model.h"
#include "fit/fit_confidence.h"
#include "fit/lambda_choice.h"
#include "fit/lambert_ggx.h"
#include "fit/solver.h"

namespace brdfshot {

struct PhotoFitOptions {
  LambdaChoiceOptions lambda;  // rule "cv" by default; "fixed" with --lambda
  int folds = kDefaultWedges;  // wedges for cross-validation
  // What the chosen class's solve keeps non-negative; λ and the class are
  // chosen on the unconstrained solve. kBins constrains every
  // constraint_stride-th bin of the tables (a prime, so the sample does not
  // alias with the grid); the few bins between them that may still dip below
  // zero are clamped when the table is written (CombineBases).
  WeightConstraint::Kind constraint = WeightConstraint::Kind::kBins;
  int constraint_stride = 31;
  // The photo's relative pixel noise for the condition bound
  // (LambdaChoiceOptions::max_condition 0); none: RelativePixelNoise of its pixels.
  std::optional<double> relative_noise;
};

struct PhotoFit {
  ClasswiseFit fit;  // every class solved at its λ; fit.chosen is the pick
  LambdaChoice choice;
  // bases × 3: the fit, Σ over choice.parts of weight × that class's solve
  // (the pick's own weights where there is one part).
  Eigen::MatrixXd weights;
  Eigen::MatrixXd reconstruction;  // pixels × 3: Y w, the fit in the photo's own lighting
  double relative_residual = 0;    // ‖Y w − y‖ / ‖y‖
  double seconds_factor = 0;       // photo-independent: Gram matrices, class and fold spectra
  double seconds_solve = 0;        // the photo's projections, the λ search and the solve
  double seconds_table_check = 0;  // kBins: the whole table checked for bins below zero (and re-solves)
  int negative_bins_added = 0;     // kBins: bins off the sample found below zero and constrained too
  // kBins: the largest t, over the parts and channels, of the blend toward
  // the class's mean that lifts what those solves left below zero
  // (KeepNonNegativeOnTable); 0: none was needed.
  double mean_blend = 0;
  // How much the fit's BRDF moves when λ moves a decade either way, in the
  // images of a sphere under ConfidenceSuns, and the predicted relit error it
  // gives (fit/fit_confidence.h; the parts' weighted means for a blend);
  // prior sensitivity -1 when no tables (or none on the basis images' grid)
  // were given.
  FitConfidence confidence;
  double relative_noise = 0;  // the photo's pixel noise (kUnknownNoise: not measurable)
  // What the condition bound followed: the pixel noise, or what the largest
  // candidate's fit leaves where that reads less (BoundPixelNoise and
  // BoundNoise, lambda_choice.h).
  double bound_noise = 0;
  // The analytic baseline fitted to the same pixels, when the basis images
  // hold its lobes (fit/lambert_ggx.h).
  std::optional<LambertGgxFit> lambert_ggx;
  LambertGgxLobes lobes;
};

// Checks that `model` was built for `basis`'s bases (same names, same order);
// FileError naming `model_source` otherwise.
void CheckModelMatchesBases(const ClassModel& model, const std::string& model_source,
                            const std::vector<std::string>& basis_names);

// y: pixels × 3 in the order of basis.geometry. `tables`: the database's
// tables for the basis images' bases (bins × bases), needed by the kBins
// constraint only; Error when that constraint has none.
// `fold_of_pixel`: the cross-validation wedges of every pixel (default: the
// wedges of basis.geometry, one sphere; JointPhotos gives each photo its own).
PhotoFit FitPhoto(const BasisImages& basis, const ClassModel& model, const Eigen::MatrixXd& y,
                  const PhotoFitOptions& opt, const BasisTables* tables = nullptr,
                  const std::vector<int>* fold_of_pixel = nullptr);

// "none", "non-negative weights", "non-negative bins" (fit.json's weights_constraint).
std::string ConstraintName(WeightConstraint::Kind kind);

// fit.json: what `fit` wrote, what `render --weights` and `report` read.
struct FitRecord {
  std::string database, database_kind, probe, photo;
  MerlGrid grid;
  std::string lambda_rule;
  double lambda = 0;
  bool lambda_beyond_condition_bound = false;  // LambdaChoice::beyond_condition_bound
  std::string weights_constraint = "none";     // ConstraintName of the chosen class's solve
  double predicted_relit_error = 0;            // PhotoFit::confidence's (the held-out error without one)
  double held_out_error = 0;                   // LambdaChoice::held_out_error
  double prior_sensitivity = -1;               // PhotoFit::confidence's (-1: not measured)
  // The photo's relative pixel noise and the condition bound the λ search ran
  // under (lambda_choice.h, photo_noise.h); -1: not recorded.
  double relative_noise = -1, condition_bound = -1;
  double bound_noise = -1;         // PhotoFit::bound_noise; -1: not recorded
  double sensitivity_penalty = 0;  // LambdaChoice::sensitivity_penalty (0: the wedges' error alone)
  double penalty_gate = -1;        // LambdaChoice::penalty_gate (-1: none)
  double min_wedge_share = -1;     // LambdaChoice::min_wedge_share (-1: each wedge's error as it is)
  int chosen_class = -1;
  // The fit's parts (LambdaChoice::parts): class, λ, weight, predicted
  // (FitConfidence's) and held-out error; none is written as the pick alone (chosen_class at
  // lambda, weight 1).
  std::vector<LambdaChoice::Part> parts;
  double relative_residual = 0;
  struct ClassRow {
    int members = 0;
    double residual = 0, condition = 0;
    std::string path;
  };
  std::vector<ClassRow> classes;
  std::vector<double> lambda_grid;
  std::vector<std::vector<double>> lambda_scores;  // [class][grid]
  std::vector<std::string> bases;
  Eigen::MatrixXd weights;  // bases × 3
  double seconds_factor = 0, seconds_solve = 0, seconds_table_check = 0;
  int negative_bins_added = 0;
  double mean_blend = 0;
  std::optional<LambertGgxFit> lambert_ggx;  // as PhotoFit::lambert_ggx
  LambertGgxLobes lobes;

  static FitRecord From(const PhotoFit& f, const BasisImages& basis, const std::string& photo);
  nlohmann::json ToJson() const;
  static FitRecord FromJson(const nlohmann::json& j, const std::string& source);
  void Write(const std::string& path) const;  // atomic
  static FitRecord Read(const std::string& path);
};

// The photo's pixels in the order of `basis`'s geometry: from an observation
// file (remap's output, checked to be the basis images' pixels) or, with
// `obs_path` empty, a linear HDR image of the basis images' size. Errors name
// the file.
Eigen::MatrixXd ReadFitPixels(const BasisImages& basis, const std::string& basis_path, const std::string& photo_path,
                              const std::string& obs_path);

// The database a fit is made with: the named bases of database `kind` on
// `grid`, through `opt`'s data paths; Error if they are not all there.
BasisDatabase DatabaseOfBases(const std::string& kind, const MerlGrid& grid, const std::vector<std::string>& bases,
                              DatabaseOptions opt);
BasisDatabase DatabaseOfBases(const BasisImages& basis, DatabaseOptions opt);
BasisDatabase DatabaseOfFit(const FitRecord& record, DatabaseOptions opt);
// The fitted BRDF on the database's grid: Σ w_i b_i over the record's bases.
// `label` says what it is; `clamped` counts the bin-channels set to zero
// from below.
MerlBrdf BrdfOfFit(const FitRecord& record, const BasisDatabase& db, std::string* label = nullptr,
                   long* clamped = nullptr);
MerlBrdf BrdfOfFit(const FitRecord& record, DatabaseOptions opt, std::string* label = nullptr);
// The record's Lambert + GGX baseline on its grid (MERL layout, what `render`
// and other renderers read); the record must hold one.
MerlBrdf LambertGgxBrdf(const FitRecord& record);

}  // namespace brdfshot
