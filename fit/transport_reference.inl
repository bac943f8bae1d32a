// Template body of RenderReference (kept out of transport.h for readability).
#pragma once

#include <cmath>

namespace brdfshot {

template <typename BrdfFn>
Eigen::MatrixXd RenderReference(const PixelGeometry& g, const LatLongProbe& probe, BrdfFn brdf, int nt, int np) {
  // Suns are split off exactly as in TransportOperator (a dense grid converges on
  // them far too slowly); the remainder is integrated densely and unfiltered.
  LatLongProbe rest = probe;
  const RenderQuality q;
  const std::vector<DirectionalLight> lights = ExtractLights(&rest, q.max_lights, q.light_share, q.light_grid_width);
  const PrefilteredProbe lookup(rest);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(g.size(), 3);
#pragma omp parallel for schedule(dynamic, 4)
  for (long p = 0; p < static_cast<long>(g.size()); ++p) {
    const Frame f = Frame::FromZX(g.normal[p], g.view[p]);
    const Vec3 wo = f.ToLocal(g.view[p]);
    if (wo.z <= 0) continue;
    double acc[3] = {0, 0, 0};
    for (int a = 0; a < nt; ++a) {
      const double u = (a + 0.5) / nt, th = u * u * kPi / 2;
      // Exact cell solid angle (the midpoint rule is 2× off in the first cell).
      const double u0 = double(a) / nt, u1 = double(a + 1) / nt;
      const double dwh_t = (std::cos(u0 * u0 * kPi / 2) - std::cos(u1 * u1 * kPi / 2)) * (2 * kPi / np);
      for (int b = 0; b < np; ++b) {
        const double ph = 2 * kPi * (b + 0.5) / np;
        const Vec3 h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
        const double cd = Dot(wo, h);
        if (cd <= 0) continue;
        const Vec3 wi = Reflect(wo, h);
        if (wi.z <= 0) continue;
        const auto r = brdf(wi, wo);
        const cv::Vec3f L = lookup.LookupLevel(f.FromLocal(wi), 0);
        const double w = wi.z * 4 * cd * dwh_t;
        for (int c = 0; c < 3; ++c) acc[c] += w * r[c] * L[c];
      }
    }
    for (const DirectionalLight& l : lights) {
      const Vec3 wi = f.ToLocal(l.direction);
      if (wi.z <= 0) continue;
      const auto r = brdf(wi, wo);
      for (int c = 0; c < 3; ++c) acc[c] += wi.z * r[c] * l.power[c];
    }
    for (int c = 0; c < 3; ++c) out(p, c) = acc[c];
  }
  return out;
}

}  // namespace brdfshot
