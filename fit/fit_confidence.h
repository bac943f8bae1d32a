// How much a fit depends on its prior rather than on its photo.
//
// The wedges' held-out error (lambda_choice.h) is measured under the photo's
// own lighting, so it cannot see how far the weights may swing along
// directions that lighting hardly excites — the directions another probe
// shows. Where the photo pins the weights, moving λ a decade either way
// barely moves the BRDF; where it does not, the prior decides and the BRDF
// follows λ. The prior sensitivity measures that: the relative change of the
// class's BRDF when λ is divided and multiplied by ten, measured in the
// images that lighting the photo lacks shows: a sphere under suns
// (DirectionalImageGram). A BRDF metric (cosine-weighted bins) weighs every
// bin alike, the grazing ones most relit images never show included; the
// images weigh the bins as relighting does.
//
// The predicted relit error adds the two: what the wedges miss under the
// photo's own lighting and what the prior decides, which another lighting
// shows. A sum, not a product or a penalty factor, because the two are errors
// of the same images that add up in the worst case (the triangle inequality);
// `brdfshot eval` reports how well it ranks the fits' actual relit error;
// docs/benchmarks.md measures that and how far above the actual error the
// sum lies.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "fit/basis_tables.h"
#include "fit/lambda_choice.h"
#include "fit/merl_grid.h"
#include "fit/solver.h"
#include "util/vec3.h"

namespace brdfshot {

// √(d₋² + d₊²), d± = ‖w(λ±) − w(λ)‖_M / ‖w(λ)‖_M summed over RGB, where w(λ)
// is the class's unconstrained solve (SolveFromSpectrum, λ_j = λ‖y_c‖²/c_j),
// λ₋ = λ/10 and λ₊ = max(10 λ, 10⁻⁴) (λ = 0 is moved to the grid's scale).
// `metric`: the BRDF Gram matrix over the class's members (c_j × c_j, e.g.
// gram_cos(J, J) or SampledCosineGram). 0 for a BRDF of zero norm.
double PriorSensitivity(const ClassSpectrum& cls, const Observation& obs, double lambda,
                        const Eigen::MatrixXd& metric);

// Per class, the BRDF metric over its members: gram(J, J) of a metric over
// every basis (e.g. the database's gram_cos, or SampledCosineGram of all).
std::vector<Eigen::MatrixXd> ClassMetrics(const Eigen::MatrixXd& gram, const std::vector<std::vector<int>>& members);

// Σ over every `stride`-th bin of cos²-weight × b_J b_Jᵀ (MerlGrid::CosineWeightTable of
// `grid`): the cosine-weighted BRDF Gram matrix of the bases `members`
// estimated from a sample of the tables (bins × bases), which `fit` holds —
// the full matrix over 1.5 M bins would cost seconds per photo.
Eigen::MatrixXd SampledCosineGram(const TablesRef& tables, const MerlGrid& grid, const std::vector<int>& members,
                                  int stride);

// The confidence of a fit made by `choice`: per part, PriorSensitivity in
// `metric(cls)` (the image metric over class cls's members) at the part's λ
// and the predicted relit error held-out error + sensitivity; the fit's are
// the parts' means by weight. Each sensitivity is computed afresh: the
// parts' own (Part::sensitivity) are the penalty's, in its BRDF metric.
struct FitConfidence {
  double prior_sensitivity = -1;
  double predicted_relit_error = 0;
  std::vector<double> part_predicted_relit_error;  // parallel to choice.parts
};
FitConfidence ConfidenceOf(const LambdaChoice& choice, const std::vector<ClassSpectrum>& classes,
                           const Observation& obs, const std::function<Eigen::MatrixXd(int cls)>& metric);

// The suns of the confidence's image metric (unit vectors, world frame of
// DirectionalImageGram): elevations 30° and 60° at azimuths 0°, 60°, 120° and
// 180° from the view — front, side and back light, the kinds a captured probe
// with one bright source leaves least constrained. They are fixed, not the
// evaluation's scoring suns, so the confidence is not fitted to its score.
std::vector<Vec3> ConfidenceSuns();

// Σ over `suns` of ∫ r_J r_Jᵀ dA over an orthographic unit sphere seen from +z
// (y up), r_J the bases' radiance under a sun of unit irradiance: ρ_J(ω_i, ω_o)
// cos θ_i, ρ read trilinearly from `tables` (bins × bases on `grid`). The
// integral is a sum over a `sphere_pixels`² raster of the disk, each pixel
// weighing its area, so a finer raster converges to the same matrix. Double
// precision: thousands of rank-one terms accumulate into it.
Eigen::MatrixXd DirectionalImageGram(const TablesRef& tables, const MerlGrid& grid, const std::vector<Vec3>& suns,
                                     int sphere_pixels = 32);

}  // namespace brdfshot
