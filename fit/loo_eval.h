// Leave-one-out evaluation of the method against its baselines (docs/method.md,
// "How it is judged"). For every material m and every probe A: drop m's three channels
// from the bases and re-cluster without them, fit m's image under A, and score
//   relit  — relative RMSE of the reconstruction's image under every probe B ≠ A,
//   brdf   — cosine-weighted relative RMSE over the table's bins,
//   insample — relative residual under A itself.
// Methods: "auto" (the default fit: λ and class chosen per fit by wedge
// cross-validation, fit/lambda_choice.h, BRDF kept ≥ 0), "auto-signed" (the same
// λ and class, weights unconstrained), "ours" (corrected M-step, fixed λ),
// "paper" (M-step as printed), "lsq"
// (argmin ‖Yw − y‖² over all remaining bases), "oracle" (projection of the true
// BRDF onto the remaining bases in the cosine-weighted BRDF norm),
// "relit-oracle" (the remaining bases fitted to the true relit images under
// the scoring probes: the floor of the relit error).
//
// Every metric is a quadratic form in d = w − e_m, so with the Gram matrices of
// the basis images (per probe, per channel) and of the cosine-weighted table, a
// metric costs a 300 × 300 product — no image is re-rendered.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fit/class_model.h"
#include "fit/fit_confidence.h"
#include "fit/lambda_choice.h"
#include "fit/lambert_ggx.h"
#include "fit/solver.h"
#include "fit/table_check.h"
#include "util/stats.h"

namespace brdfshot {

struct SceneFactors {  // one probe's basis images, factored
  std::string probe;
  // A directional-light scene (a sun over a dim sky): it scores every fit
  // (LooRow::relit_directional) and is never fitted from; it needs no QR
  // and no folds.
  bool scoring_only = false;
  std::array<ChannelFactor, 3> f;                         // with the QR (least squares and the singular fallback)
  std::vector<std::array<Eigen::MatrixXd, 3>> fold_gram;  // per wedge of the sphere (FoldGrams), for "auto"
  // Per wedge, every basis's training system (FactorFoldsOfAll), which each
  // left-out material's every-basis candidate is solved on (FactorFolds'
  // superset); empty: every candidate factored on its own.
  std::vector<FoldClassFactor> fold_all;
  size_t pixels = 0;
  // RelativePixelNoise (photo_noise.h) of each scored material's photo under
  // this scene, for the condition bound of "auto"; empty: 0 (noise-free).
  std::vector<double> photo_noise;
  double PhotoNoise(int m) const { return photo_noise.empty() ? 0.0 : photo_noise[m]; }
  // The basis images themselves (pixels × n per channel), for the noise a
  // fit leaves (BoundPixelNoise); null: not read. They outlive the run.
  const std::array<MatrixXfR, 3>* images = nullptr;
};

// One scene's analytic lobe images (fit/lambert_ggx.h) against the images of
// the scored materials: all the Lambert + GGX baseline needs to fit a
// material under the scene and to score a fit there.
struct LobeScene {
  std::array<Eigen::MatrixXd, 3> gram;   // L_cᵀ L_c
  std::array<Eigen::MatrixXd, 3> cross;  // materials × lobes: row m is (material m's channel-c image)ᵀ L_c
  std::array<Eigen::VectorXd, 3> self;   // ‖material m's channel-c image‖²
  LobeSystem System(int m) const;
};
// `images`: pixels × 3M per channel, column 3m + c material m's channel c
// (the layout of the basis images); `L`: the lobe images of the same pixels.
LobeScene MakeLobeScene(const std::array<MatrixXfR, 3>& images, const std::array<MatrixXfR, 3>& L);

// What the class model of "ours" and "auto" is built on: the Gram matrix of
// the tables as they are ("linear", the paper's), cosine-weighted ("cos":
// ρ cos θ_i cos θ_o), or log-mapped after the cosine weight ("log-cos":
// log(1 + ρ cos θ_i cos θ_o)). "paper" always clusters the linear tables.
std::string ClassFeaturesHelp();

struct LooInputs {
  std::vector<std::string> materials;  // n/3 names
  Eigen::MatrixXd gram;                // BᵀB
  Eigen::MatrixXd class_gram;          // what "ours" and "auto" cluster (ClassFeatures); empty: gram
  Eigen::MatrixXd gram_cos;            // Bᵀ diag(cos²) B (BRDF metric)
  // The confidence's metric: DirectionalImageGram of the tables under
  // ConfidenceSuns (fit_confidence.h), as `fit` measures it. Empty: gram_cos.
  Eigen::MatrixXd sun_gram;
  std::vector<SceneFactors> scenes;    // one per probe
  // A sample of the database's bins (rows of its tables, SampleBins): every
  // fitted BRDF is evaluated there to count negative values. Empty: not counted.
  MatrixXfR bin_sample;
  // The bins the "auto" fit keeps non-negative under LooOptions::constraint
  // kBins (rows of the tables; disjoint from bin_sample, so the count
  // measures the bins between them).
  MatrixXfR constraint_sample;
  // The whole table, checked after the sampled constraint: bins below zero
  // join the constraint as in `fit` (fit/table_check.h). Null: the sample only.
  const TableCheck* table_check = nullptr;
  // The Lambert + GGX baseline: one LobeScene per scene (parallel to
  // `scenes`, over the scored materials); empty: not run.
  LambertGgxLobes lobes;
  std::vector<LobeScene> lobe_scenes;
  const PixelGeometry* geometry = nullptr;  // of the scenes' pixels, with their images; null: none
};

// Material m's photo (pixels × 3) from images laid out as the basis images
// are: pixels × 3M per channel, material m's channel c in column 3m + c.
Eigen::MatrixXd MaterialImage(const std::array<MatrixXfR, 3>& images, int m);

// Rows offset, offset + stride, … of the tables `B` (bins × bases).
MatrixXfR SampleBins(const TablesRef& B, int stride, int offset = 0);

// The share of (bin, channel) pairs where the BRDF of weights `w` (n × 3) is
// negative (kNegativeBinTolerance) over the sampled bins; -1 when `bins` is empty.
double NegativeBinShare(const MatrixXfR& bins, const Eigen::MatrixXd& w);
// The same for every fit whose weights are a block of three columns of W.
std::vector<double> NegativeBinShares(const MatrixXfR& bins, const Eigen::MatrixXd& W);

struct LooOptions {
  GmmOptions gmm;
  double lambda = 0.5;         // "ours": the corrected M-step at a fixed λ
  LambdaChoiceOptions choice;  // "auto": λ and class chosen per fit (the default of `fit`)
  // What "auto" keeps non-negative (kBins: LooInputs::constraint_sample);
  // "auto-signed" is the same choice unconstrained.
  WeightConstraint::Kind constraint = WeightConstraint::Kind::kBins;
  // Only the materials (or targets) m with m mod shard_count = shard_index:
  // one of shard_count independent jobs whose rows together are the full run's.
  int shard_index = 0, shard_count = 1;
  // Also fit every material (or target) from two photos at once (JointOfScenes; each
  // fitted scene with JointPartner's): "auto-joint" rows, probe "A+B", scored
  // under the probes neither photo was taken under, beside "auto-one" rows
  // (probe "A (A+B)", "B (A+B)"): each photo's own default fit scored there.
  bool joint = false;
  bool progress = false;
};

struct LooRow {
  std::string material, probe, method;
  int chosen_class = -1;  // -1 for baselines without classes
  double lambda = -1;     // the λ used (-1: none)
  double predicted = -1;  // the fit's own predicted error ("auto"; -1: none)
  double held_out = -1;   // the fit's own held-out error ("auto"; -1: none)
  double relit_mean = 0, relit_median = 0, brdf = 0, insample = 0;
  double relit_directional = -1;  // mean over the scoring-only scenes (-1: none)
  double negative_bins = -1;      // NegativeBinShare of the fitted BRDF (-1: not counted)
  double condition_bound = -1;    // "auto…": the bound its λ search ran under (-1: none)
  double prior_sensitivity = -1;  // "auto": its FitConfidence's, in the image metric (fit_confidence.h; -1: none)
};

// One method's fit of one photo, as the evaluations score it.
struct FittedMethod {
  const char* name;
  Eigen::MatrixXd w;  // n × 3
  int chosen_class;   // -1 for methods without classes
};

// The row of a fit, before scoring: which material, probe and method, and how
// λ was set ("auto…": the choice's λ and predicted error; "ours" and
// "paper": `fixed_lambda`). "auto" takes its prior sensitivity and predicted
// error from `confidence` where that measured one.
LooRow MethodRow(const FittedMethod& method, const std::string& material, const std::string& probe,
                 const LambdaChoice& choice, double fixed_lambda, const FitConfidence* confidence = nullptr);

// The "auto" fit of class `cls` at `lambda` under `kind` (its weights, n × 3,
// and for kNone and kBins the same solve unconstrained); for kBins, the
// class's constrained bins are kept per class index in `bins_of_class` (the
// sampled bins of in.constraint_sample at first, and every bin in.table_check
// adds), so the fits of one material under every probe share them.
ClassSolution SolveAuto(const LooInputs& in, WeightConstraint::Kind kind, const std::array<ChannelFactor, 3>& f,
                        const Observation& obs, const ClassSpectrum& cls, double lambda,
                        std::map<int, BinRows>* bins_of_class, int class_index);

// "auto-signed": `fit`'s unconstrained weights, solved again only where the
// constraint (w ≥ 0) has no unconstrained step.
Eigen::MatrixXd SignedWeights(const ClassSolution& fit, const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls,
                              const Observation& obs, double lambda);

// The default fit of one photo: every part of `choice` solved by SolveAuto
// and blended by its weight (LambdaChoice::parts). `weights` and
// `signed_weights` (each part's SignedWeights, blended alike) are n × 3;
// `confidence`, with `with_sensitivity`, is ConfidenceOf the choice in
// in.sun_gram (else in.gram_cos; fit_confidence.h), prior sensitivity -1 otherwise.
struct AutoFit {
  Eigen::MatrixXd weights, signed_weights;
  FitConfidence confidence;
};
AutoFit SolveChoice(const LooInputs& in, WeightConstraint::Kind kind, const std::array<ChannelFactor, 3>& f,
                    const Observation& obs, const std::vector<ClassSpectrum>& classes, const LambdaChoice& choice,
                    std::map<int, BinRows>* bins_of_class, bool with_sensitivity);

// Sets rows[i].negative_bins = NegativeBinShare(bins, methods[i].w) for every
// method, reading the bins once for all of them.
void SetNegativeBins(const MatrixXfR& bins, const std::vector<FittedMethod>& methods, LooRow* rows);

// The "lambert-ggx" row of scored material m fitted under scene a
// (in.lobe_scenes): relit and in-sample errors as for every method; no BRDF
// error (NaN: the analytic lobes have no Gram matrix with the database's
// tables); no negative bin (non-negative weights on non-negative lobes).
LooRow LambertGgxRow(const LooInputs& in, int a, int m, const std::string& material);

// Fills row's relit_mean / relit_median (over the fitted scenes not in
// `fitted_from`) and relit_directional (over the scoring-only scenes) from
// error(b), the fit's relit error under scene b.
template <typename ErrorUnder>
void ScoreRelitExcept(const std::vector<SceneFactors>& scenes, const std::vector<int>& fitted_from, ErrorUnder&& error,
                      LooRow* row) {
  std::vector<double> relit;
  double directional = 0;
  int directional_count = 0;
  for (int b = 0; b < static_cast<int>(scenes.size()); ++b) {
    if (scenes[b].scoring_only) {
      directional += error(b), ++directional_count;
    } else if (std::find(fitted_from.begin(), fitted_from.end(), b) == fitted_from.end()) {
      relit.push_back(error(b));
    }
  }
  if (relit.empty()) relit.push_back(error(fitted_from.at(0)));  // no other probe: in-sample
  double sum = 0;
  for (double e : relit) sum += e;
  row->relit_mean = sum / static_cast<double>(relit.size());
  row->relit_median = Median(relit);
  row->relit_directional = directional_count ? directional / directional_count : -1;
}

// The same for a fit from the photo under scene a alone.
template <typename ErrorUnder>
void ScoreRelit(const std::vector<SceneFactors>& scenes, int a, ErrorUnder&& error, LooRow* row) {
  ScoreRelitExcept(scenes, {a}, std::forward<ErrorUnder>(error), row);
}

// Two photos of material m, under fitted scenes a and b, as one: the Gram
// matrices of StackPhotos (fit/joint_photos.h) without the pixels. Each photo
// and its basis images are scaled by the inverse of the photo's RMS pixel
// value, so the stack's Gram matrices are s_a² G_a + s_b² G_b, and fold k holds
// both photos' wedge k. No QR: the solves take the eigen path.
struct JointScene {
  std::array<ChannelFactor, 3> f;
  std::vector<std::array<Eigen::MatrixXd, 3>> fold_gram;
  size_t pixels = 0;
  double photo_noise = 0;         // pooled over the photos' pixels as StackPhotos pools it
  std::array<double, 2> scale{};  // s_a², s_b²: what each photo's projections are multiplied by
};
// `photo_a`, `photo_b`: each photo's mean squared pixel value and relative
// pixel noise (RelativePixelNoise).
struct PhotoStats {
  double mean_square = 0, noise = 0;
};
JointScene JointOfScenes(const SceneFactors& a, const SceneFactors& b, PhotoStats photo_a, PhotoStats photo_b);
// The photos of database material m, which are its basis images.
JointScene JointOfScenes(const SceneFactors& a, const SceneFactors& b, int m);

// Per fold, the observation of material m's own columns (3m + c) — the photo
// of m is exactly its basis image, so its fold parts are columns of the fold Grams.
std::vector<Observation> HeldObservations(const std::vector<std::array<Eigen::MatrixXd, 3>>& fold_gram, int m);

// The fitted scene after a (cyclically) that a's photo is paired with for
// LooOptions::joint; -1 for a scoring-only scene, when there is no other
// fitted scene, or when the pair is a's partner's already (two fitted scenes
// make one pair, not two).
int JointPartner(const std::vector<SceneFactors>& scenes, int a);

struct LooResult {
  std::vector<LooRow> rows;
  double seconds_cluster = 0, seconds_solve = 0;  // summed over threads' wall time
};

LooResult RunLeaveOneOut(const LooInputs& in, const LooOptions& opt);

// Spearman's rank correlation of two equally long samples (ties get their mean
// rank); 0 when fewer than two values or a sample is constant.
double SpearmanCorrelation(const std::vector<double>& a, const std::vector<double>& b);

// Weighted error of weights `w` (n × 3) against material m under Gram matrices
// g[c]: sqrt(Σ_c d_cᵀ g_c d_c / Σ_c g_c(3m+c, 3m+c)).
double RelativeError(const std::array<const Eigen::MatrixXd*, 3>& g, const Eigen::MatrixXd& w, int m);
// RelativeError of each of several weight sets under the same g: one product
// of each g_c with all of them, which reads each g_c once instead of once per
// set (a scene's three Gram matrices are larger than the caches).
std::vector<double> RelativeErrors(const std::array<const Eigen::MatrixXd*, 3>& g,
                                   const std::vector<const Eigen::MatrixXd*>& w, int m);

}  // namespace brdfshot
