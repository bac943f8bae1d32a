#include "fit/transport.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {

std::string RenderQuality::Describe() const {
  return "theta=" + std::to_string(theta_samples) + ",phi=" + std::to_string(phi_samples) +
         ",probe=" + std::to_string(probe_width) + ",lights=" + std::to_string(max_lights) +
         ",level_step=" + std::to_string(level_step_deg) +
         ",brdf_supersample=" + std::to_string(brdf_supersample);
}

std::vector<DirectionalLight> ExtractLights(LatLongProbe* probe, int max_lights, double min_share) {
  std::vector<DirectionalLight> lights;
  if (max_lights <= 0) return lights;
  struct Texel {
    double power;
    int c, r;
  };
  std::vector<Texel> texels;
  double total = 0;
  for (int r = 0; r < probe->height(); ++r)
    for (int c = 0; c < probe->width(); ++c) {
      const cv::Vec3f v = probe->Texel(c, r);
      const double p = (v[0] + v[1] + v[2]) * probe->TexelSolidAngle(r);
      total += p;
      texels.push_back({p, c, r});
    }
  if (total <= 0) return lights;
  const size_t k = std::min<size_t>(max_lights, texels.size());
  std::partial_sort(texels.begin(), texels.begin() + k, texels.end(),
                    [](const Texel& a, const Texel& b) { return a.power > b.power; });
  cv::Mat rgb = probe->rgb().clone();
  for (size_t i = 0; i < k && texels[i].power >= min_share * total; ++i) {
    const Texel& t = texels[i];
    const double omega = probe->TexelSolidAngle(t.r);
    lights.push_back({probe->DirectionAt(t.c + 0.5, t.r + 0.5), probe->Texel(t.c, t.r) * omega});
    rgb.at<cv::Vec3f>(t.r, t.c) = cv::Vec3f(0, 0, 0);
  }
  *probe = LatLongProbe(rgb, probe->name());
  return lights;
}

TransportOperator TransportOperator::Build(const PixelGeometry& g, const LatLongProbe& probe_in,
                                           const MerlGrid& grid, const RenderQuality& q) {
  BRDFSHOT_CHECK(q.theta_samples > 0 && q.phi_samples > 0 && q.level_step_deg > 0 && q.brdf_supersample >= 0);
  BRDFSHOT_CHECK(g.normal.size() == g.size() && g.view.size() == g.size());
  TransportOperator t;
  t.grid_ = grid;
  t.quality_ = q;
  LatLongProbe probe =
      q.probe_width > 0 && q.probe_width < probe_in.width() ? probe_in.Resized(q.probe_width) : probe_in;
  t.lights_ = ExtractLights(&probe, q.max_lights, q.light_share);
  t.probe_ = std::make_shared<const PrefilteredProbe>(probe);

  for (int a = 0; a < q.theta_samples; ++a) {
    const double u = (a + 0.5) / q.theta_samples, th = u * u * kPi / 2;
    // The cell's exact solid angle (cos θ_lo − cos θ_hi) Δφ_h: the midpoint rule
    // would be 2× off in the first cell, where dω_h ∝ u³ du and chrome lives.
    const double u0 = double(a) / q.theta_samples, u1 = double(a + 1) / q.theta_samples;
    const double dwh = (std::cos(u0 * u0 * kPi / 2) - std::cos(u1 * u1 * kPi / 2)) * (2 * kPi / q.phi_samples);
    for (int b = 0; b < q.phi_samples; ++b) {
      const double ph = 2 * kPi * (b + 0.5) / q.phi_samples;
      t.samples_.push_back(
          {Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)), dwh, a, b});
    }
  }

  const double step = q.level_step_deg * kPi / 180;
  const int n_levels = static_cast<int>(std::ceil((kPi / 2) / step)) + 1;
  t.level_pixels_.resize(n_levels);
  t.normal_ = g.normal;
  t.view_ = g.view;
  for (size_t p = 0; p < g.size(); ++p) {
    const double c = Dot(g.normal[p], g.view[p]);
    if (c <= 0) continue;  // facing away: the pixel stays black
    const double x = std::acos(std::min(1.0, c)) / step;
    const int l0 = std::min(n_levels - 2, static_cast<int>(x));
    const float w1 = static_cast<float>(std::clamp(x - l0, 0.0, 1.0));
    t.level_pixels_[l0].push_back({static_cast<uint32_t>(p), 1 - w1});
    if (w1 > 0) t.level_pixels_[l0 + 1].push_back({static_cast<uint32_t>(p), w1});
  }
  return t;
}

template <typename RowFn>
std::array<MatrixXfR, 3> TransportOperator::ApplyImpl(Eigen::Index n, RowFn row) const {
  std::array<MatrixXfR, 3> Y;
  for (auto& y : Y) y.setZero(pixels(), n);
  const double step = quality_.level_step_deg * kPi / 180;
  const int nt = quality_.theta_samples, np = quality_.phi_samples;
  // Table reads per cell: ~1 per MERL θ_h bin the cell spans (2 changed no
  // error by more than 0.1 % in bench-basis), 2 across φ_h.
  const int su = quality_.brdf_supersample > 0 ? quality_.brdf_supersample
                                               : std::max(1, (grid_.n_th + nt - 1) / nt);
  const int sp = su > 1 ? 2 : 1;
#pragma omp parallel
  {
    RowFn row_local = row;  // per thread: the functor may keep scratch space
    std::vector<float> tmp(n);
    std::vector<int> active;
    std::vector<TablePoint> points;
    // Even levels, then odd ones: a pixel lives in two adjacent levels, so no
    // two threads ever add into the same row of Y at once.
    for (int parity = 0; parity < 2; ++parity) {
#pragma omp for schedule(dynamic, 1)
      for (int l = parity; l < levels(); l += 2) {
        const std::vector<LevelPixel>& px = level_pixels_[l];
        if (px.empty()) continue;
        const double tl = std::min(kPi / 2, l * step);
        const Vec3 wo_l(std::sin(tl), 0, std::cos(tl));
        // Samples that can reach above the horizon for some pixel of the level
        // (their exact θ_o is within a step): the rest would be all zeros.
        active.clear();
        for (int s = 0; s < static_cast<int>(samples_.size()); ++s) {
          const Vec3& h = samples_[s].h;
          const double cd = Dot(wo_l, h);
          if (cd <= 0 || 2 * cd * h.z - wo_l.z <= -2 * step) continue;
          active.push_back(s);
        }
        const Eigen::Index S = static_cast<Eigen::Index>(active.size());
        if (S == 0) continue;
        // M: the table averaged over each sample's cell, weighted by cosθ_i dω_i
        // (weights normalised, so a cell cut by the horizon stays bounded).
        MatrixXfR M(S, n);
        for (Eigen::Index k = 0; k < S; ++k) {
          const Sample& smp = samples_[active[k]];
          points.clear();
          double wsum = 0;
          for (int i = 0; i < su; ++i) {
            const double u = (smp.a + (i + 0.5) / su) / nt, th = u * u * kPi / 2;
            const double u0 = (smp.a + double(i) / su) / nt, u1 = (smp.a + double(i + 1) / su) / nt;
            const double dwh = std::cos(u0 * u0 * kPi / 2) - std::cos(u1 * u1 * kPi / 2);  // ∝ sub-cell dω_h
            for (int j = 0; j < sp; ++j) {
              const double ph = 2 * kPi * (smp.b + (j + 0.5) / sp) / np;
              const Vec3 h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
              const double cd = Dot(wo_l, h);
              if (cd <= 0) continue;
              const Vec3 wi = 2 * cd * h - wo_l;
              if (wi.z <= 0) continue;
              points.push_back({ToHalfDiff(wi, wo_l), wi.z * cd * dwh});
              wsum += points.back().weight;
            }
          }
          for (TablePoint& pt : points) pt.weight /= wsum;
          row_local(points, M.row(k).data());
        }
        // A: each pixel's lighting per sample, channel-major rows.
        const Eigen::Index P = static_cast<Eigen::Index>(px.size());
        MatrixXfR A = MatrixXfR::Zero(3 * P, S);
        for (Eigen::Index i = 0; i < P; ++i) {
          const size_t p = px[i].pixel;
          const Frame f = Frame::FromZX(normal_[p], view_[p]);
          const Vec3 wo = f.ToLocal(view_[p]);
          for (Eigen::Index k = 0; k < S; ++k) {
            const Sample& smp = samples_[active[k]];
            const double cd = Dot(wo, smp.h);
            if (cd <= 0) continue;
            const Vec3 wi = 2 * cd * smp.h - wo;
            if (wi.z <= 0) continue;
            const double domega = 4 * cd * smp.dwh;
            const cv::Vec3f L = probe_->Lookup(f.FromLocal(wi), domega);
            const double w = px[i].weight * wi.z * domega;
            for (int c = 0; c < 3; ++c) A(c * P + i, k) = static_cast<float>(w * L[c]);
          }
        }
        const MatrixXfR AM = A * M;
        for (Eigen::Index i = 0; i < P; ++i)
          for (int c = 0; c < 3; ++c) Y[c].row(px[i].pixel) += AM.row(c * P + i);
      }
    }
    // Suns: exact per pixel, the table read at the pixel's own (ω_i, ω_o).
    if (!lights_.empty()) {
#pragma omp for schedule(dynamic, 16)
      for (long p = 0; p < static_cast<long>(pixels()); ++p) {
        const Frame f = Frame::FromZX(normal_[p], view_[p]);
        const Vec3 wo = f.ToLocal(view_[p]);
        if (wo.z <= 0) continue;
        for (const DirectionalLight& l : lights_) {
          const Vec3 wi = f.ToLocal(l.direction);
          if (wi.z <= 0) continue;
          points.assign(1, TablePoint{ToHalfDiff(wi, wo), 1.0});
          row_local(points, tmp.data());
          for (int c = 0; c < 3; ++c) {
            const float w = static_cast<float>(wi.z * l.power[c]);
            float* y = Y[c].row(p).data();
            for (Eigen::Index j = 0; j < n; ++j) y[j] += w * tmp[j];
          }
        }
      }
    }
  }
  return Y;
}

std::array<MatrixXfR, 3> TransportOperator::Apply(const MatrixXfR& B) const {
  BRDFSHOT_CHECK(static_cast<size_t>(B.rows()) == grid_.size(), "basis matrix has " << B.rows()
                 << " rows, operator expects " << grid_.size());
  const Eigen::Index n = B.cols();
  struct Corner {
    size_t idx;
    double w;
  };
  return ApplyImpl(n, [&, corners = std::vector<Corner>()](const std::vector<TablePoint>& pts,
                                                          float* out) mutable {
    // Gather every point's trilinear corners, merge repeated entries, then read
    // each table row once.
    corners.clear();
    for (const TablePoint& pt : pts) {
      size_t idx[8];
      double w[8];
      const int k = grid_.TrilinearCorners(pt.hd, idx, w);
      for (int a = 0; a < k; ++a) corners.push_back({idx[a], w[a] * pt.weight});
    }
    std::sort(corners.begin(), corners.end(), [](const Corner& x, const Corner& y) { return x.idx < y.idx; });
    std::fill(out, out + n, 0.0f);
    for (size_t a = 0; a < corners.size();) {
      double w = 0;
      const size_t idx = corners[a].idx;
      for (; a < corners.size() && corners[a].idx == idx; ++a) w += corners[a].w;
      const float wf = static_cast<float>(w);
      const float* b = B.data() + idx * n;
      for (Eigen::Index j = 0; j < n; ++j) out[j] += wf * b[j];
    }
  });
}

Eigen::MatrixXd TransportOperator::Render(const MerlBrdf& brdf) const {
  BRDFSHOT_CHECK(brdf.grid() == grid_, "BRDF grid differs from the operator's grid");
  const auto Y = ApplyImpl(3, [&](const std::vector<TablePoint>& pts, float* out) {
    // Unmeasured entries read as 0, exactly as the basis matrix stores them, so
    // rendering a table and applying the operator to its columns agree.
    double acc[3] = {0, 0, 0};
    for (const TablePoint& pt : pts) {
      size_t idx[8];
      double w[8];
      const int k = grid_.TrilinearCorners(pt.hd, idx, w);
      for (int a = 0; a < k; ++a)
        for (int c = 0; c < 3; ++c) acc[c] += pt.weight * w[a] * std::max(0.0, brdf.Value(c, idx[a]));
    }
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(acc[c]);
  });
  Eigen::MatrixXd y(pixels(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = Y[c].col(c).cast<double>();
  return y;
}

}  // namespace brdfshot
