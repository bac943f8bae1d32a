// How much a fit depends on its prior rather than on its photo.
//
// The wedges' held-out error (lambda_choice.h) is measured under the photo's
// own lighting, so it cannot see how far the weights may swing along
// directions that lighting hardly excites — the directions another probe
// shows. Where the photo pins the weights, moving λ a decade either way
// barely moves the BRDF; where it does not, the prior decides and the BRDF
// follows λ. The prior sensitivity measures that: the relative change of the
// class's BRDF, in the cosine-weighted BRDF metric, when λ is divided and
// multiplied by ten. `brdfshot eval` reports how well it ranks the fits'
// actual relit error, with and without the wedge error (docs/benchmarks.md).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "fit/merl_grid.h"
#include "fit/solver.h"

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

// Σ over every `stride`-th bin of cos²-weight × b_J b_Jᵀ (CosineWeights of
// `grid`): the cosine-weighted BRDF Gram matrix of the bases `members`
// estimated from a sample of the tables (bins × bases), which `fit` holds —
// the full matrix over 1.5 M bins would cost seconds per photo.
Eigen::MatrixXd SampledCosineGram(const MatrixXfR& tables, const MerlGrid& grid, const std::vector<int>& members,
                                  int stride);

}  // namespace brdfshot
