// The light-transport operator of one scene (paper eqs. 3–5).
//
// For fixed lighting and pixel geometry, rendering is linear in the BRDF table:
//   y_c(pixel) = Σ_bins T_c(pixel, bin) ρ(bin),
// so the images of all bases are one sparse–dense product Y_c = T_c B.
//
// Quadrature (why it works for chrome and felt alike): per pixel we integrate
// over the half vector h in the local frame, with √θ_h on a midpoint grid —
// MERL's own non-linear θ_h spacing, dense where specular peaks live — and φ_h
// uniform. ω_i = reflect(ω_o, h), dω_i = 4 (ω_o·h) dω_h. The probe is looked up
// prefiltered over each sample's footprint dω_i, so a sample near the mirror
// direction sees a sharp probe and a grazing sample a blurred one: no aliasing
// with a few hundred samples. The BRDF is read at the nearest MERL entry
// (duplicates merged per pixel), which keeps T as sparse as the samples.
//
// A sun is the one thing a fixed grid cannot integrate: a texel holding a large
// share of the probe's power lands between samples. Such texels are taken out of
// the probe and added as directional lights, exact per pixel, before the smooth
// remainder goes through the quadrature.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/merl_brdf.h"
#include "fit/nbrdf.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {

struct RenderQuality {
  int theta_samples = 24;  // along √θ_h
  int phi_samples = 48;    // along φ_h
  int probe_width = 512;   // probe box-resampled to this width first (0 = as given)
  int max_lights = 64;     // texels split off as directional lights (0 = none)
  double light_share = 0.002;  // ...if each holds at least this share of the power
  std::string Describe() const;
};

// Texels split off a probe as directional lights; the probe keeps the remainder.
struct DirectionalLight {
  Vec3 direction;
  cv::Vec3f power;  // radiance × solid angle (W/m² per channel)
};
std::vector<DirectionalLight> ExtractLights(LatLongProbe* probe, int max_lights, double min_share);

class TransportOperator {
 public:
  static TransportOperator Build(const PixelGeometry& geometry, const LatLongProbe& probe,
                                 const MerlGrid& grid, const RenderQuality& quality);

  size_t pixels() const { return offset_.size() - 1; }
  size_t nonzeros() const { return bin_.size(); }
  const MerlGrid& grid() const { return grid_; }

  // Y_c = T_c B for c = R, G, B light channels: each pixels × B.cols().
  std::array<MatrixXfR, 3> Apply(const MatrixXfR& B) const;
  // Image of one tabulated BRDF (channel c under light channel c): pixels × 3.
  Eigen::MatrixXd Render(const MerlBrdf& brdf) const;

 private:
  MerlGrid grid_;
  std::vector<uint64_t> offset_;  // pixels + 1
  std::vector<uint32_t> bin_;     // MERL entry per nonzero
  std::vector<float> weight_;     // 3 per nonzero: L_c cosθ_i dω_i
};

// Converged reference for tests and error reports: the same integral with a
// dense half-vector grid, the unfiltered probe (bilinear) and the BRDF given as
// a function of (ω_i, ω_o) in the local frame. Slow by design.
template <typename BrdfFn>
Eigen::MatrixXd RenderReference(const PixelGeometry& g, const LatLongProbe& probe, BrdfFn brdf,
                                int theta_samples, int phi_samples);

}  // namespace brdfshot

#include "fit/transport_reference.inl"
