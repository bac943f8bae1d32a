// The regularisation weight chosen per capture, from the capture's own pixels.
//
// No fixed λ is right: how much the class prior should count depends on the
// noise, on how well the database spans the material and on how much of the
// BRDF the lighting shows. The photo itself tells by spatially blocked
// cross-validation: the sphere's pixels are cut into K wedges around its centre
// (neighbouring pixels are correlated, so a held-out pixel must be far from the
// training ones); each wedge is predicted from a fit to the others, for every λ
// of a grid and every class, and the (class, λ) with the smallest held-out error
// wins. A wedge sees the light from other directions than the rest, which is
// the closest the photo comes to the question that matters: how the fit
// relights under lighting it has not seen.
//
// Every fold's normal equations are decomposed once per scene and class
// (CvSystem), so the whole search over classes and λ for one photo is a few
// hundred small matrix-vector products. The wedges' held-out error of the pick
// is also the fit's predicted error.
//
// Generalised cross-validation (one decomposition per class, all λ at once) is
// the alternative (`rule = "gcv"`): on noise-free leave-one-out over MERL it
// relights as well as the wedges, but it counts correlated pixels as
// independent, so on a real capture (JPEG noise, calibration errors) it asks for
// almost no regularisation and relights badly (docs/benchmarks.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "fit/photo_noise.h"
#include "fit/solver.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {

// The default number of wedges. Fewer, larger wedges hold out more of the
// sphere's lighting at once; three leave too little to fit a capture's
// felt or plastic from, twelve relight as six do at twice the
// factorisation, and five relight sets a, b and c at least as well as six
// for a sixth less (docs/benchmarks.md, "The number of wedges").
constexpr int kDefaultWedges = 5;

// Pixel → fold: K wedges of equal angle around the pixels' centroid, so each
// fold spans the sphere from its centre to its rim.
std::vector<int> WedgeFolds(const PixelGeometry& g, int folds);

// The pixels of each fold, in order.
std::vector<std::vector<int>> RowsByFold(const std::vector<int>& fold_of_pixel, int folds);

// Per fold, per channel: the Gram matrix of the held-out pixels' basis images.
std::vector<std::array<Eigen::MatrixXd, 3>> FoldGrams(const std::array<MatrixXfR, 3>& Y,
                                                      const std::vector<int>& fold_of_pixel, int folds);

// The whole photo's factor (no QR) from its folds' Gram matrices: every pixel
// lies in one fold, so their sum is YᵀY, with no second pass over the images.
std::array<ChannelFactor, 3> FactorOfFolds(const std::vector<std::array<Eigen::MatrixXd, 3>>& held_gram);

// Yᵀ y over each fold's rows among rows [begin, end) (end < 0: every row):
// z[k] sums fold k's rows, in double, each float row widened as it is read.
// The rows are read once, in order, each added to its own fold's sum: a
// wedge's rows lie scattered over the image, and reading them wedge by wedge
// runs well below the memory's speed. Within a fold the rows are added in
// ascending order, as ProjectRows over that fold's rows adds them.
std::vector<Eigen::VectorXd> ProjectRowsByFold(const MatrixXfR& Y, const Eigen::VectorXd& y,
                                               const std::vector<int>& fold_of_pixel, int folds,
                                               Eigen::Index begin = 0, Eigen::Index end = -1);

// The observation restricted to each fold's pixels (their sum is the whole
// observation: SumObservations).
std::vector<Observation> FoldObservations(const std::array<MatrixXfR, 3>& Y, const Eigen::MatrixXd& y,
                                          const std::vector<int>& fold_of_pixel, int folds);

// Σ of per-fold observations: the observation of all pixels, without
// projecting them again.
Observation SumObservations(const std::vector<Observation>& parts);

// Everything about the folds that does not depend on the photo.
// One class's training system in one fold, G_JJ − G_fold,JJ = Q T Qᵀ
// (Householder tridiagonalisation) per channel: each λ of the grid is then a
// tridiagonal solve and a product with Q. Eigenvectors, which cost three times
// as much to compute, are not needed. Q is formed (a matrix) or kept as its
// Householder reflectors (FoldQ).
struct FoldClassFactor {
  std::vector<int> members;
  std::array<Eigen::MatrixXd, 3> gram;        // G_JJ − G_fold,JJ
  std::array<Eigen::VectorXd, 3> gram_prior;  // gram μ' (ClassSpectrum::gram_prior)
  std::array<Eigen::MatrixXd, 3> Q;           // formed (FoldQ::kFormed), else empty
  // The reflectors (FoldQ::kReflectors), else empty.
  std::array<Eigen::Tridiagonalization<Eigen::MatrixXd>, 3> reflectors;
  std::array<Eigen::VectorXd, 3> diagonal, off_diagonal;  // of T
  // Q x and Qᵀ x for channel c, whichever way Q is held.
  Eigen::MatrixXd TimesQ(int c, const Eigen::MatrixXd& x) const;
  Eigen::VectorXd TimesQt(int c, const Eigen::VectorXd& x) const;

  // A class of every member of a larger one's but a few (a leave-one-out
  // evaluation's every-basis candidate: all bases but the left-out
  // material's): no factor of its own. Each λ is solved in `superset`'s
  // factor (Q formed) with the weights of `left_out` (positions in
  // superset->members) held at zero: the bordered system
  //   [A + λI  E] [d]   [b]
  //   [Eᵀ      0] [μ] = [0],
  // whose d is the solution of the smaller system (A_JJ + λI) d_J = b_J, at
  // a tridiagonal solve per left-out column and an r × r system per λ
  // instead of a tridiagonalisation of its own, each solve refined once.
  // Where a refined solve leaves more backward error than its own factor
  // would allow (BorderedFoldSolves) or meets a singular pivot, the class is
  // factored on the spot, so the scores are those of its own factor either
  // way. `gram` and the factors above stay empty;
  // `gram_prior` is its own.
  const FoldClassFactor* superset = nullptr;
  std::vector<int> left_out;
  bool bordered() const { return superset != nullptr; }
};

// How the folds' Q is held. Forming it costs as much again as the
// tridiagonalisation; a formed Q then makes each photo's λ grid one matrix
// product, the reflectors about twice that. A system that serves many photos
// (a scene's every target in an evaluation) forms it, and so does `fit`, whose
// λ choice is held to milliseconds after the factorisation; one that serves a
// single photo in an evaluation (leave-one-out, where every left-out material
// has its own classes) keeps the reflectors.
enum class FoldQ { kFormed, kReflectors };

struct CvSystem {
  std::vector<std::array<Eigen::MatrixXd, 3>> held_gram;                // [fold][channel], n × n
  std::vector<std::vector<FoldClassFactor>> train;                      // [fold][class]
  std::vector<std::vector<std::array<Eigen::MatrixXd, 3>>> held_class;  // [fold][class][channel]: G_fold,JJ
};
// `superset`, where given: per fold, a factor of many members with Q formed
// (the scene's every basis); a class of all its members but at most
// kMostLeftOut is held bordered on it (FoldClassFactor::superset). It must
// outlive the system.
CvSystem FactorFolds(const std::array<ChannelFactor, 3>& f, std::vector<std::array<Eigen::MatrixXd, 3>> held_gram,
                     const std::vector<std::vector<int>>& members, FoldQ q = FoldQ::kFormed,
                     const std::vector<FoldClassFactor>* superset = nullptr);

// A bordered class costs r + 1 tridiagonal solves and an r × r system per λ
// against a tridiagonalisation of its own (k³): it pays for a few left-out
// members of a large class, which is what a leave-one-out evaluation leaves
// out (one material's three channel-bases).
constexpr int kMostLeftOut = 8;
constexpr int kLeastBorderedMembers = 32;

// Per fold, the factor of every one of `n` bases with Q formed: the superset
// that FactorFolds holds each left-out material's every-basis class on.
std::vector<FoldClassFactor> FactorFoldsOfAll(const std::array<ChannelFactor, 3>& f,
                                              const std::vector<std::array<Eigen::MatrixXd, 3>>& held_gram);

struct LambdaChoiceOptions {
  std::string rule = "cv";  // cv | gcv | fixed (docs/method.md, "Choosing λ per capture")
  // Also offer every basis as one more candidate "class" (prior 1/n): the
  // criterion then decides whether the class restriction helps this photo
  // (rules cv and gcv; "residual" and "fixed" pick among the classes alone).
  bool all_bases_candidate = true;
  // Rule cv with the BRDF metrics given: each candidate's held-out error is
  // multiplied by (1 + a·s), s its prior sensitivity (fit_confidence.h) and
  // a this weight (0: no penalty). The wedges
  // share the photo's lighting, so a fit that swings along directions the
  // lighting hardly excites scores as well as one that does not; the
  // sensitivity sees how much of the BRDF the prior, not the photo, decides,
  // which is what another lighting shows (docs/method.md).
  double sensitivity_penalty = 1;
  // The penalty weighs only candidates the wedges do not find clearly worse
  // than their group's best by held-out error: by at most this many standard
  // errors of the per-wedge differences (paired: every wedge scores both
  // fits, and wedges differ far more from each other than two fits differ on
  // one). A rigid candidate (a small class) moves little with λ, so its
  // sensitivity is small whether or not it fits the photo; without the gate
  // its factor can outweigh a held-out error several times the best one's,
  // on every wedge. < 0: no gate.
  double penalty_gate = 1;
  // Each wedge's held-out error counted relative to its own signal
  // (WedgeWeights): the relit error is relative under every lighting, and a
  // wedge that holds a small bright source's highlight would otherwise decide
  // the choice alone — by how well the prior, not the photo, guesses a
  // highlight the other wedges never saw. false: each wedge's error as it is.
  bool relative_wedges = true;
  // A wedge darker than this share of the mean wedge's ‖y‖² is weighed as if
  // it held that share: a wedge in shadow (one light from the side) holds
  // little but noise, whose relative error says nothing of the fit. < 0:
  // ResolveConditionBound sets it to the photo's noise, ε² (0.1 for an
  // unknown noise).
  double min_wedge_share = -1;
  // Rule cv with the penalty and every basis a candidate: the fit blends the
  // best model class and every basis, each at its own best penalised λ,
  // weighted by the inverse of its penalised score (LambdaChoice::parts).
  // The wedges share the photo's lighting, so neither score ranks the class
  // prior against every basis reliably for another lighting; the relit error
  // is a norm, convex in the weights, so under any lighting the blend relights
  // no worse than its parts' weighted mean, and it keeps every bin that both
  // parts keep non-negative. false: the pick alone.
  bool blend_every_basis = true;
  // The blend's lesser part is left out below this weight (its penalised
  // score over three times the other's at 0.25): it would move the fit by less
  // than that fraction of the parts' difference, and it costs a second
  // constrained solve (docs/benchmarks.md).
  double min_blend_weight = 0.25;
  double fixed = 0.5;  // the weight for rule "fixed"
  std::vector<double> grid = {0, 1e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0};
  // Effective pixel count for GCV, as a fraction of the pixels (1: every pixel independent).
  double gcv_pixel_fraction = 1.0;
  // A λ is a candidate for a class only while the condition number of
  // G_JJ + λ_j I stays below a bound. Held-out pixels share the photo's
  // lighting, so they cannot see directions of w that this lighting hardly
  // excites; an unregularised fit may swing wildly along them and relight badly
  // under another probe. The bound keeps every direction's gain at most
  // 1/√bound of the best-seen one's. 0: the bound follows the photo's noise
  // (photo_noise.h, ResolveConditionBound); > 0: this bound for every photo.
  double max_condition = 0;
  NoiseBoundOptions noise_bound;
};

struct LambdaChoice {
  int chosen_class = -1;
  double lambda = 0;
  std::string rule;
  // score[j][i]: the criterion for class j at grid[i] (held-out squared error
  // summed over folds and RGB for cv; GCV's n·RSS/(n − dof)² for gcv); +inf
  // for an empty class.
  std::vector<std::vector<double>> score;
  std::vector<double> grid;
  // Relative held-out RMSE of the chosen (class, λ): √(error / Σ‖y‖²) over
  // the wedges when folds are given, each wedge's error weighed by
  // WedgeWeights (with relative wedges, the root of their mean relative
  // squared error), else GCV's estimate: the fit's error on pixels it was not
  // fitted to.
  double held_out_error = 0;
  // The pick's penalised error: the held-out error times (1 + a·s) where the
  // sensitivity penalty computed the pick's prior sensitivity s (rule cv),
  // else the held-out error. What a fit reports as its predicted relit error
  // is its FitConfidence (fit_confidence.h), which weighs the prior in the
  // images of other lighting rather than in the penalty's BRDF metric.
  double predicted_error = 0;
  // No λ of the grid kept any class within max_condition: the grid's largest
  // λ was taken instead of the criterion's pick.
  bool beyond_condition_bound = false;
  double condition_bound = 0;  // the bound the search ran under
  // sensitivity[j][l]: the prior sensitivity of class j at grid[l] where the
  // penalty needed it (NaN elsewhere); empty without the penalty.
  std::vector<std::vector<double>> sensitivity;
  double sensitivity_penalty = 0;  // the weight a of the penalty the pick was made with (0: none)
  double penalty_gate = -1;        // the penalty's gate z (LambdaChoiceOptions::penalty_gate); -1: none
  // The wedges' errors counted relative to their own signal, a wedge at least
  // this share of the mean wedge (LambdaChoiceOptions::relative_wedges); -1:
  // each wedge's error as it is, or no wedges.
  double min_wedge_share = -1;
  // The fit: Σ weight · (candidate `cls` solved at `lambda`), weights summing
  // to 1. One part, the pick, unless LambdaChoiceOptions::blend_every_basis
  // blends two; chosen_class and lambda are then the part of the larger
  // weight, and predicted_error and held_out_error are the parts' weighted
  // means (by Minkowski's inequality at least the blend's own held-out error).
  struct Part {
    int cls = -1;
    double lambda = 0;
    double weight = 1;
    double predicted_error = 0;  // the part's own, as LambdaChoice::predicted_error
    // Its prior sensitivity where the penalty computed it (NaN elsewhere).
    double sensitivity = std::numeric_limits<double>::quiet_NaN();
    double held_out_error = 0;  // the part's own, as LambdaChoice::held_out_error
  };
  std::vector<Part> parts;
};

// `opt` with max_condition set for a photo whose relative pixel noise is
// `relative_noise` (RelativePixelNoise) when it is 0 (follow the noise);
// unchanged when it is fixed.
LambdaChoiceOptions ResolveConditionBound(const LambdaChoiceOptions& opt, double relative_noise);

// An upper bound of the photo's noise from a fit: √(Σ_c RSS_c / Σ_c (n − dof_c))
// relative to the photo's RMS √(Σ_c ‖y_c‖² / 3n), for class `cls` at the least
// λ of `grid` that keeps it within `max_condition` (n = `pixels`). Pixel noise
// cannot exceed what a fit leaves, whatever the shading; −1 when no λ of the
// grid is within the bound or the photo is black.
double FitResidualNoise(const ClassSpectrum& cls, const Observation& obs, size_t pixels,
                        const std::vector<double>& grid, double max_condition);

// The weights (members × 3) of class `cls` at the least λ of `grid` that
// keeps it within `max_condition` (FitResidualNoise's fit); empty when none is
// or the class has no eigenvectors.
Eigen::MatrixXd LeastRegularisedWeights(const ClassSpectrum& cls, const Observation& obs,
                                        const std::vector<double>& grid, double max_condition);

// ResidualPixelNoise of the photo y (pixels × 3) after the largest candidate
// class's least-regularised fit within opt.noise_bound.max_bound, over the
// basis images Y (pixels × bases per channel) of geometry g; kUnknownNoise
// where there is no such fit.
double FitPixelNoise(const PixelGeometry& g, const std::array<MatrixXfR, 3>& Y, const Eigen::MatrixXd& y,
                     const std::vector<ClassSpectrum>& classes, const Observation& obs, const LambdaChoiceOptions& opt);

// The pixel noise the bound starts from: the photo's own reading
// `pixel_noise` (RelativePixelNoise), or the lesser of it and FitPixelNoise
// with opt.noise_bound.read_fit_residual. A fit of every basis takes a
// shading's detail away, which no basis image can follow in noise: on a
// render or a clean capture what it leaves reads far below the photo, on a
// noisy one about the same. Unchanged for an unknown or zero noise and when
// the bound is fixed (opt.max_condition > 0).
double BoundPixelNoise(double pixel_noise, const PixelGeometry& g, const std::array<MatrixXfR, 3>& Y,
                       const Eigen::MatrixXd& y, const std::vector<ClassSpectrum>& classes, const Observation& obs,
                       const LambdaChoiceOptions& opt);

// The noise the condition bound follows: the photo's pixel noise
// (RelativePixelNoise), or what the fit of the largest candidate class leaves
// where that is less. Immerkær's estimator reads a shading's own fine detail
// as noise (a glossy sphere reflects the probe's edges), which would hold a
// photo that the bases explain to far below it at the tightest bound. An
// unknown pixel noise (kUnknownNoise) stays unknown: the cautious bound.
double BoundNoise(double pixel_noise, const std::vector<ClassSpectrum>& classes, const Observation& obs, size_t pixels,
                  const LambdaChoiceOptions& opt);

// The least share of the mean wedge's ‖y‖² a wedge is weighed as holding,
// whatever the options say: a black wedge must not weigh without bound.
constexpr double kLeastWedgeShare = 1e-12;

// Each wedge's weight in the held-out score: with opt.relative_wedges, the
// mean wedge's ‖y‖² over the wedge's own (the latter at least
// opt.min_wedge_share of the former), so the score is the photo's ‖y‖² times
// the wedges' mean relative squared error; else 1 for each. `all` gives the
// photo's ‖y‖², `held` one Observation per wedge.
std::vector<double> WedgeWeights(const Observation& all, const std::vector<Observation>& held,
                                 const LambdaChoiceOptions& opt);

// Whether per-wedge differences `d` average at most z standard errors of
// their mean (the sample deviation over √K) above zero: a one-sided paired
// comparison of two fits on the same wedges. True for fewer than two.
bool WithinStandardErrors(const std::vector<double>& d, double z);

// ResolveConditionBound for a photo of pixel noise `pixel_noise`, the bound
// following BoundNoise over the candidate `classes`.
LambdaChoiceOptions ResolveConditionBound(const LambdaChoiceOptions& opt, double pixel_noise,
                                          const std::vector<ClassSpectrum>& classes, const Observation& obs,
                                          size_t pixels);

// Scores every class at every λ of the grid for `obs` and picks the best. With
// `cv` (and the observation's per-fold parts `held`) the predicted error is the
// held-out error of the pick, whichever rule picked. `pixels`: the observation's pixel count
// (gcv only). With rule "fixed" the class comes from the residual at opt.fixed.
// Grid values beyond opt.max_condition score +inf (it must be resolved: ≥ 1).
// The candidate member lists: the model's classes, then (when asked) every
// basis in `all` as one more.
std::vector<std::vector<int>> CandidateMembers(const std::vector<std::vector<int>>& classes,
                                               const std::vector<int>& all, const LambdaChoiceOptions& opt);

// `metrics`: per class, the BRDF metric over its members (PriorSensitivity's);
// with rule cv and opt.sensitivity_penalty they turn the penalty on. Only
// candidates whose held-out error alone beats the best penalised score so far
// need their sensitivity (the factor is at least 1), so few are computed.
// The blend (opt.blend_every_basis) takes the last candidate as every basis,
// where CandidateMembers puts it.
LambdaChoice ChooseLambda(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                          const CvSystem* cv, const Observation& obs, const std::vector<Observation>& held,
                          size_t pixels, const LambdaChoiceOptions& opt,
                          const std::vector<Eigen::MatrixXd>* metrics = nullptr);

}  // namespace brdfshot
