// Where exactly a sphere's rim crosses one radial intensity profile.
//
// The steepest point of a blurred step is the step only when both sides are
// flat. A shaded sphere is not flat at its rim: its radiance varies with the
// normal, whose component towards the camera grows like √depth inside the
// silhouette, so the inside rises like a + c √(s₀ − s). Blurred, that ramp
// drags the steepest point inwards by ~ slope · σ² / step (0.1–0.2 px for a
// matte ball at σ = 1–2 px, measured). So the rim is fitted as the model
//
//   p(s) = b₀ + b₁ (s − s₀) + a Φ((s₀ − s)/σ) + c R_σ(s₀ − s),
//
// R_σ the Gaussian-blurred √ ramp: linear in (b₀, b₁, a, c) for a given s₀ and
// σ (solved in closed form inside a 1-D search over s₀ — variable projection);
// σ, the optical blur, is shared by all rays of a photo.
//
// With `curved_interior` the model has a fifth term, e (s₀ − s) inside the
// rim only (blurred): the next order of the interior in depth. A sheen (felt,
// velvet: brightest at grazing) curves its interior over the few pixels next
// to the rim; fitted without it over the blur vote's wide window, that curve
// passes for extra blur (pink felt: σ 1.0 px voted for 0.875 px true, and its
// rim then 0.09 px inside). The blur vote uses it; the edge fit does not:
// over the edge fit's narrower window the extra unknown costs more in noise
// than it removes in bias (bench-detect 640 × 480: median centre error
// 0.031 → 0.12 px with it).
#pragma once

#include <vector>

namespace brdfshot {

class RimProfileModel {
 public:
  explicit RimProfileModel(double sigma, bool curved_interior = false);
  double sigma() const { return sigma_; }
  // Profile `p` sampled at radii r0 + i·step (i < n); search s₀ within ±1 px of
  // `guess`, fitting samples within ±`half_window` px (≤ 0: 4σ + 1). Returns s₀
  // and the residual sum of squares (NaN if the window leaves the profile).
  double Fit(const float* p, int n, double r0, double step, double guess, double* rss, double half_window = 0) const;

 private:
  double Ramp(double u) const;  // R_σ(u)
  // max(0, u) blurred by σ, given the blurred step Φ(u/σ)
  double InsideLine(double u, double step_u) const;
  double sigma_;
  bool curved_interior_;
  const std::vector<double>& ramp1_;  // R_1 on u ∈ [−8, 64), step 1/64 (shared table)
};

// The optical blur σ (0.5–4 px, to 1/8 px): the median over rays of the σ
// that fits each best, with the curved-interior model (see above).
double EstimateRimBlur(const std::vector<const float*>& profiles, int n, double r0, double step,
                       const std::vector<double>& guesses);

}  // namespace brdfshot
