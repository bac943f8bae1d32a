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

#include "fit/solver.h"

namespace brdfshot {

// √(d₋² + d₊²), d± = ‖w(λ±) − w(λ)‖_M / ‖w(λ)‖_M summed over RGB, where w(λ)
// is the class's unconstrained solve (SolveFromSpectrum, λ_j = λ‖y_c‖²/c_j),
// λ₋ = λ/10 and λ₊ = max(10 λ, 10⁻⁴) (λ = 0 is moved to the grid's scale).
// `metric`: the database's BRDF Gram matrix (n × n, e.g. gram_cos), indexed by
// the class's members. 0 for a BRDF of zero norm.
double PriorSensitivity(const ClassSpectrum& cls, const Observation& obs, double lambda,
                        const Eigen::MatrixXd& metric);

}  // namespace brdfshot
