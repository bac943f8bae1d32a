// The light-transport operator of one scene (paper eqs. 3–5).
//
// For fixed lighting and pixel geometry, rendering is linear in the BRDF table:
//   y_c(pixel) = Σ_bins T_c(pixel, bin) ρ(bin),
// so the images of all bases are Y_c = T_c B for the whole basis matrix at once.
//
// Quadrature (why it works for chrome and felt alike): per pixel we integrate
// over the half vector h in the local frame, with √θ_h on a midpoint grid —
// MERL's own non-linear θ_h spacing, dense where specular peaks live — and φ_h
// uniform. ω_i = reflect(ω_o, h), dω_i = 4 (ω_o·h) dω_h. The probe is looked up
// prefiltered over each sample's footprint dω_i, so a sample near the mirror
// direction sees a sharp probe and a grazing sample a blurred one: no aliasing
// with a few hundred samples. The table is read trilinearly, as MerlBrdf::Eval
// reads it (nearest-entry reads cost metals ~10 % against the converged
// reference: `brdfshot bench-basis`).
//
// Why T is applied in factored form, T = A S: in the frame (normal, plane of
// the view) ω_o = (sin θ_o, 0, cos θ_o) for every camera, so which table entries
// a half-vector sample reads depends on θ_o alone. Pixels are grouped into θ_o
// levels (one MERL θ_d bin apart, each pixel linear between its two); per
// level, S averages the table over each sample's cell (M = S B: samples ×
// bases, computed once per level) and A holds each pixel's lighting per sample
// (cos θ_i dω_i L, from its own exact frame and ω_o). Y for a level is then one
// dense product A M — cache-friendly, unlike a sparse T whose rows gather from
// a 1.7 GB table. Because M is per level, not per pixel, the table can be read
// at many points inside each sample's cell (a specular peak spans 2–3 MERL θ_h
// bins, narrower than a cell) while the probe is read once per cell, prefiltered
// over it: the BRDF gets its resolution, the lighting its own.
//
// A sun is the one thing a fixed grid cannot integrate: a texel holding a large
// share of the probe's power lands between samples. Such texels are taken out of
// the probe and added as directional lights, exact per pixel, before the smooth
// remainder goes through the quadrature.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/basis_tables.h"
#include "fit/merl_brdf.h"
#include "fit/nbrdf.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {

struct RenderQuality {
  // 32 × 48 is the cheapest setting with every class's worst basis image
  // within 1 % of the converged reference for a 256² sphere under the forest
  // and sunset probes at 512 × 256 (docs/benchmarks.md, `brdfshot bench-basis`); 30 along
  // √θ_h is markedly worse than 28 or 32 on both probes, so do not interpolate.
  // Smaller spheres and 1024-wide probes are at 1.2–1.8 % (a grazing-pixel
  // bias, not the sample count): `basis --error-target` measures a scene and
  // picks a finer setting where one helps (fit/quality_search.h).
  int theta_samples = 32;  // along √θ_h
  int phi_samples = 48;    // along φ_h, per ring: at least this, or 4·theta·√θ_h where that is more
  // 0: the probe as given. Resampling a 1024-wide probe to 512 saves ~6 % of
  // the time and costs the metals ~3 % of error against the probe the user has
  // (`basis --error-target`, forest); plain least squares, the most sensitive
  // to basis-image error, relit 0.080 instead of 0.093 in `eval`.
  int probe_width = 0;          // probe box-resampled to this width first (0 = as given)
  int max_lights = 64;          // texels split off as directional lights (0 = none)
  double light_share = 0.002;   // ...if each holds at least this share of the power
  int light_grid_width = 512;   // ...counted in blocks of a grid this wide (0: per texel)
  double level_step_deg = 1.0;  // θ_o spacing of the levels whose table reads are computed
  int level_substeps = 8;       // pixels snap to step/substeps, M linear in between
  int brdf_supersample = 0;     // table reads per sample cell along √θ_h (0: auto, ~1 per bin)
  std::string Describe() const;
};

// Suns split off a probe as directional lights; the probe keeps the remainder.
struct DirectionalLight {
  Vec3 direction;
  cv::Vec3f power;  // radiance × solid angle (W/m² per channel)
};
// Blocks of the probe on a `grid_width`-wide grid holding ≥ `min_share` of its
// power (at most `max_lights`, brightest first) become one light each at their
// power centroid; their texels are zeroed in the probe.
std::vector<DirectionalLight> ExtractLights(LatLongProbe* probe, int max_lights, double min_share, int grid_width = 0);

class TransportOperator {
 public:
  static TransportOperator Build(const PixelGeometry& geometry, const LatLongProbe& probe, const MerlGrid& grid,
                                 const RenderQuality& quality);

  size_t pixels() const { return normal_.size(); }
  const MerlGrid& grid() const { return grid_; }
  int levels() const { return n_levels_; }
  const std::vector<DirectionalLight>& lights() const { return lights_; }

  // Y_c = T_c B for c = R, G, B light channels: each pixels × B.cols().
  std::array<MatrixXfR, 3> Apply(const TablesRef& B) const;
  // Apply for each operator, reading the table once for all of them: its
  // averages over the half-vector cells (M, above) depend on neither the
  // lighting nor the pixels, only on the grid and the sampling, which the
  // operators must share (SharesTableReadsWith, checked). The result is
  // each operator's Apply(B), in order.
  static std::vector<std::array<MatrixXfR, 3>> ApplyToEach(const std::vector<const TransportOperator*>& ops,
                                                           const TablesRef& B);
  // ApplyToEach for several tables on the operators' grid (the database's, a
  // baseline's lobes, out-of-database targets) at once: each pixel's lighting
  // per sample (A, above) depends on neither table, so it is computed once for
  // all of them, and each table entry's trilinear weights once. Result
  // [operator][table]: that operator's Apply(table), the same to float rounding.
  static std::vector<std::vector<std::array<MatrixXfR, 3>>> ApplyAll(const std::vector<const TransportOperator*>& ops,
                                                                     const std::vector<TablesMap>& tables);
  // Same grid, half-vector cells and θ_o levels: what ApplyToEach needs.
  bool SharesTableReadsWith(const TransportOperator& other) const;
  // Image of one tabulated BRDF (channel c under light channel c): pixels × 3.
  Eigen::MatrixXd Render(const MerlBrdf& brdf) const;
  // Render of each BRDF (all on the operator's grid), in one pass: the
  // lighting per sample, most of a render's time, is looked up once for all.
  std::vector<Eigen::MatrixXd> RenderAll(const std::vector<const MerlBrdf*>& brdfs) const;

 private:
  struct Sample {
    Vec3 h;
    double dwh;
    int a, b;  // cell along √θ_h and φ_h
    int nphi;  // cells in this ring
  };
  struct TablePoint {
    HalfDiff hd;
    double weight;
  };
  // Y_c for BRDFs given by `row(points, out)`: writes the Σ widths column
  // values of Σ weight · ρ(hd) over the points, the columns of one result
  // after another. Result [operator][part]: part t holds widths[t] columns.
  // The operators of `ops` share their table reads.
  template <typename RowFn>
  static std::vector<std::vector<std::array<MatrixXfR, 3>>> ApplyImpl(
      const std::vector<const TransportOperator*>& ops, const std::vector<Eigen::Index>& widths, RowFn row);

  MerlGrid grid_;
  RenderQuality quality_;
  std::vector<Vec3> normal_, view_;
  int n_levels_ = 0;  // level l at θ_o = l · step, the last at or past 90°
  // Pixels of sub-level j, at θ_o = j · step / substeps (each pixel in one).
  std::vector<std::vector<uint32_t>> sublevel_pixels_;
  std::vector<Sample> samples_;
  std::vector<DirectionalLight> lights_;
  std::shared_ptr<const PrefilteredProbe> probe_;  // the probe without its suns
};

// Converged reference for tests and error reports: the same integral with a
// dense half-vector grid, the unfiltered probe (bilinear) and the BRDF given as
// a function of (ω_i, ω_o) in the local frame. Slow by design.
template <typename BrdfFn>
Eigen::MatrixXd RenderReference(const PixelGeometry& g, const LatLongProbe& probe, BrdfFn brdf, int theta_samples,
                                int phi_samples);

}  // namespace brdfshot

#include "fit/transport_reference.inl"
