// Leave-one-out evaluation of the method against its baselines (DESIGN.md "How
// we judge it"). For every material m and every probe A: drop m's three channels
// from the bases and re-cluster without them, fit m's image under A, and score
//   relit  — relative RMSE of the reconstruction's image under every probe B ≠ A,
//   brdf   — cosine-weighted relative RMSE over the table's bins,
//   insample — relative residual under A itself.
// Methods: "auto" (the default fit: λ and class chosen per fit by wedge
// cross-validation, fit/lambda_choice.h), "ours" (corrected M-step, fixed λ),
// "paper" (M-step as printed), "lsq"
// (argmin ‖Yw − y‖² over all remaining bases), "oracle" (projection of the true
// BRDF onto the remaining bases in the cosine-weighted BRDF norm).
//
// Every metric is a quadratic form in d = w − e_m, so with the Gram matrices of
// the basis images (per probe, per channel) and of the cosine-weighted table, a
// metric costs a 300 × 300 product — no image is re-rendered.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "fit/class_model.h"
#include "fit/lambda_choice.h"
#include "fit/solver.h"

namespace brdfshot {

struct SceneFactors {            // one probe's basis images, factored
  std::string probe;
  std::array<ChannelFactor, 3> f;        // with the QR (least squares and the singular fallback)
  std::vector<std::array<Eigen::MatrixXd, 3>> fold_gram;  // per wedge of the sphere (FoldGrams), for "auto"
  size_t pixels = 0;
};

struct LooInputs {
  std::vector<std::string> materials;     // n/3 names
  Eigen::MatrixXd gram;                   // BᵀB (clustering)
  Eigen::MatrixXd gram_cos;               // Bᵀ diag(cos²) B (BRDF metric)
  std::vector<SceneFactors> scenes;       // one per probe
};

struct LooOptions {
  GmmOptions gmm;
  double lambda = 0.5;             // "ours": the corrected M-step at a fixed λ
  LambdaChoiceOptions choice;      // "auto": λ and class chosen per fit (the default of `fit`)
  bool progress = false;
};

struct LooRow {
  std::string material, probe, method;
  int chosen_class = -1;                  // -1 for baselines without classes
  double lambda = -1;                     // the λ used (-1: none)
  double predicted = -1;                  // the fit's own predicted error ("auto"; -1: none)
  double relit_mean = 0, relit_median = 0, brdf = 0, insample = 0;
};

struct LooResult {
  std::vector<LooRow> rows;
  double seconds_cluster = 0, seconds_solve = 0;  // summed over threads' wall time
};

LooResult RunLeaveOneOut(const LooInputs& in, const LooOptions& opt);

// Median (mean of the two middle values for an even count; 0 when empty).
double Median(std::vector<double> v);

// Spearman's rank correlation of two equally long samples (ties get their mean
// rank); 0 when fewer than two values or a sample is constant.
double SpearmanCorrelation(const std::vector<double>& a, const std::vector<double>& b);

// Weighted error of weights `w` (n × 3) against material m under Gram matrices
// g[c]: sqrt(Σ_c d_cᵀ g_c d_c / Σ_c g_c(3m+c, 3m+c)).
double RelativeError(const std::array<const Eigen::MatrixXd*, 3>& g, const Eigen::MatrixXd& w, int m);

}  // namespace brdfshot
