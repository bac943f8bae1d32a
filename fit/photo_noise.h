// How noisy a photo is, read off its own pixels, and how far the fit may
// trust it.
//
// The wedges (lambda_choice.h) are blind to what the photo's lighting does not
// excite, so the λ search is held inside a condition bound: no direction of
// the weights may gain more than 1/√bound of the best-seen one's. How far
// that may go depends on the photo. A clean photo (16-bit, low ISO, a render)
// pins directions the lighting excites only weakly; a noisy one does not, and
// a fit that follows its noise there relights badly under another probe. A
// direction with eigenvalue e_i of the normal equations shows in the photo
// with a per-pixel amplitude √(e_i/e_max) of the strongest one's; it is
// trusted while that stays above the pixel noise ε (relative to the photo's
// RMS) divided by a margin m, i.e. e_max/e_i ≤ (m/ε)². The projection on a
// direction averages the noise over many pixels, so directions somewhat below
// the noise are still measured (m > 1); but the errors of a real capture
// (JPEG blocks, the response curve, the normals) are neither white nor
// independent, and the margin does not grow with the pixel count.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>

#include "normals/sphere_geometry.h"

namespace brdfshot {

// The photo's pixel noise relative to its RMS level, ε = σ/s. σ is the
// standard deviation of white noise that would explain the pixels' response to
// the 3 × 3 kernel [1 −2 1] ⊗ [1 −2 1] (Immerkær's noise estimator, with the
// median absolute response for robustness to highlights and edges: for
// Gaussian noise the response is N(0, 36σ²)), pooled over RGB; the kernel
// vanishes on shading that is linear or quadratic along either axis, so a
// smooth photo reads near zero. Only pixels whose eight neighbours are in
// `g` count. y: pixels × 3 in g's order. kUnknownNoise where it cannot be
// measured: a black photo, or one without a full 3 × 3 neighbourhood.
constexpr double kUnknownNoise = -1;
double RelativePixelNoise(const PixelGeometry& g, const Eigen::MatrixXd& y);

// The same estimator read on what a fit leaves, y − fitted, relative to the
// photo's RMS. The kernel reads a shading's own fine detail as noise (a
// glossy sphere reflects the probe's edges); a fit that explains the shading
// takes that detail away and leaves the noise, which no smooth combination of
// basis images can follow.
double ResidualPixelNoise(const PixelGeometry& g, const Eigen::MatrixXd& y, const Eigen::MatrixXd& fitted);

struct NoiseBoundOptions {
  // m: how far below the pixel noise a direction's amplitude may be and
  // still be trusted; measured (docs/benchmarks.md, "The condition bound").
  double margin = 6;
  // The bound's range. Below: on JPEG captures the bound 1e6 relights better
  // than looser ones (their errors are not white, and the wedges cannot see
  // them); no photo gets a tighter one. Above: beyond 1e10 float basis images
  // (24-bit mantissa, summed in double) carry too little to separate
  // directions.
  double min_bound = 1e6, max_bound = 1e12;
  // Also read the noise on what the largest candidate class's fit leaves
  // (ResidualPixelNoise, lambda_choice.h's BoundPixelNoise) and follow the
  // lesser: the photo's own reading counts a glossy shading's fine detail as
  // noise.
  bool read_fit_residual = true;
};

// clamp((m/ε)², min_bound, max_bound); max_bound for ε = 0 (noise-free);
// min_bound, the cautious end, for an unknown noise (ε < 0).
double ConditionBoundForNoise(double relative_noise, const NoiseBoundOptions& opt = {});

}  // namespace brdfshot
