#include "fit/transport.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {

std::string RenderQuality::Describe() const {
  return "theta=" + std::to_string(theta_samples) + ",phi=" + std::to_string(phi_samples) +
         ",probe=" + std::to_string(probe_width) + ",lights=" + std::to_string(max_lights);
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

namespace {
struct HalfSample {
  Vec3 h;
  double theta_h, cos_ph, sin_ph, cos_th, sin_th, dwh;
};

std::vector<HalfSample> HalfVectorGrid(int nt, int np) {
  std::vector<HalfSample> s;
  for (int a = 0; a < nt; ++a) {
    const double u = (a + 0.5) / nt, th = u * u * kPi / 2;
    // dω_h = sinθ_h dθ_h dφ_h with dθ_h = π u du.
    const double dwh = std::sin(th) * kPi * u / nt * (2 * kPi / np);
    for (int b = 0; b < np; ++b) {
      const double ph = 2 * kPi * (b + 0.5) / np;
      HalfSample x;
      x.theta_h = th;
      x.cos_th = std::cos(th);
      x.sin_th = std::sin(th);
      x.cos_ph = std::cos(ph);
      x.sin_ph = std::sin(ph);
      x.h = Vec3(x.sin_th * x.cos_ph, x.sin_th * x.sin_ph, x.cos_th);
      x.dwh = dwh;
      s.push_back(x);
    }
  }
  return s;
}

struct Entry {
  uint32_t bin;
  float w[3];
};
}  // namespace

TransportOperator TransportOperator::Build(const PixelGeometry& g, const LatLongProbe& probe_in,
                                           const MerlGrid& grid, const RenderQuality& q) {
  BRDFSHOT_CHECK(q.theta_samples > 0 && q.phi_samples > 0);
  BRDFSHOT_CHECK(grid.size() < (1ull << 32));
  LatLongProbe probe =
      q.probe_width > 0 && q.probe_width < probe_in.width() ? probe_in.Resized(q.probe_width) : probe_in;
  const std::vector<DirectionalLight> lights = ExtractLights(&probe, q.max_lights, q.light_share);
  const PrefilteredProbe lookup(probe);
  const std::vector<HalfSample> samples = HalfVectorGrid(q.theta_samples, q.phi_samples);

  std::vector<std::vector<Entry>> per_pixel(g.size());
#pragma omp parallel
  {
    std::vector<Entry> buf;
#pragma omp for schedule(dynamic, 16)
    for (long p = 0; p < static_cast<long>(g.size()); ++p) {
      buf.clear();
      const Frame f = Frame::FromZX(g.normal[p], g.view[p]);
      const Vec3 wo = f.ToLocal(g.view[p]);
      if (wo.z > 0) {
        for (const HalfSample& s : samples) {
          const double cd = Dot(wo, s.h);
          if (cd <= 0) continue;
          const Vec3 wi = 2 * cd * s.h - wo;
          if (wi.z <= 0) continue;
          // Difference vector: ω_i rotated by −φ_h about z, then −θ_h about y.
          const double x1 = s.cos_ph * wi.x + s.sin_ph * wi.y;
          const double y1 = -s.sin_ph * wi.x + s.cos_ph * wi.y;
          const double dx = s.cos_th * x1 - s.sin_th * wi.z;
          HalfDiff hd;
          hd.theta_h = s.theta_h;
          hd.theta_d = std::acos(std::min(1.0, cd));
          hd.phi_d = std::atan2(y1, dx);
          const double domega = 4 * cd * s.dwh;
          const cv::Vec3f L = lookup.Lookup(f.FromLocal(wi), domega);
          const double w = wi.z * domega;
          buf.push_back({static_cast<uint32_t>(grid.NearestIndex(hd)),
                         {static_cast<float>(w * L[0]), static_cast<float>(w * L[1]),
                          static_cast<float>(w * L[2])}});
        }
        for (const DirectionalLight& l : lights) {
          const Vec3 wi = f.ToLocal(l.direction);
          if (wi.z <= 0) continue;
          buf.push_back({static_cast<uint32_t>(grid.NearestIndex(ToHalfDiff(wi, wo))),
                         {static_cast<float>(wi.z * l.power[0]), static_cast<float>(wi.z * l.power[1]),
                          static_cast<float>(wi.z * l.power[2])}});
        }
        // Merge samples that land in the same entry: fewer nonzeros, same sum.
        std::sort(buf.begin(), buf.end(), [](const Entry& a, const Entry& b) { return a.bin < b.bin; });
        size_t out = 0;
        for (size_t i = 0; i < buf.size(); ++i) {
          if (out > 0 && buf[out - 1].bin == buf[i].bin) {
            for (int c = 0; c < 3; ++c) buf[out - 1].w[c] += buf[i].w[c];
          } else {
            buf[out++] = buf[i];
          }
        }
        buf.resize(out);
      }
      per_pixel[p] = buf;
    }
  }
  TransportOperator t;
  t.grid_ = grid;
  t.offset_.assign(g.size() + 1, 0);
  for (size_t p = 0; p < g.size(); ++p) t.offset_[p + 1] = t.offset_[p] + per_pixel[p].size();
  t.bin_.resize(t.offset_.back());
  t.weight_.resize(3 * t.offset_.back());
  for (size_t p = 0; p < g.size(); ++p) {
    size_t o = t.offset_[p];
    for (const Entry& e : per_pixel[p]) {
      t.bin_[o] = e.bin;
      for (int c = 0; c < 3; ++c) t.weight_[3 * o + c] = e.w[c];
      ++o;
    }
  }
  return t;
}

std::array<MatrixXfR, 3> TransportOperator::Apply(const MatrixXfR& B) const {
  BRDFSHOT_CHECK(static_cast<size_t>(B.rows()) == grid_.size(), "basis matrix has " << B.rows()
                 << " rows, operator expects " << grid_.size());
  const Eigen::Index n = B.cols();
  std::array<MatrixXfR, 3> Y;
  for (auto& y : Y) y.setZero(pixels(), n);
#pragma omp parallel
  {
    std::vector<float> acc(3 * n);
#pragma omp for schedule(dynamic, 8)
    for (long p = 0; p < static_cast<long>(pixels()); ++p) {
      std::fill(acc.begin(), acc.end(), 0.0f);
      float* a0 = acc.data();
      float* a1 = a0 + n;
      float* a2 = a1 + n;
      for (uint64_t e = offset_[p]; e < offset_[p + 1]; ++e) {
        const float* row = B.data() + static_cast<size_t>(bin_[e]) * n;
        const float w0 = weight_[3 * e], w1 = weight_[3 * e + 1], w2 = weight_[3 * e + 2];
#pragma omp simd
        for (Eigen::Index j = 0; j < n; ++j) {
          a0[j] += w0 * row[j];
          a1[j] += w1 * row[j];
          a2[j] += w2 * row[j];
        }
      }
      for (int c = 0; c < 3; ++c)
        std::copy(acc.begin() + c * n, acc.begin() + (c + 1) * n, Y[c].row(p).data());
    }
  }
  return Y;
}

Eigen::MatrixXd TransportOperator::Render(const MerlBrdf& brdf) const {
  BRDFSHOT_CHECK(brdf.grid() == grid_, "BRDF grid differs from the operator's grid");
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(pixels(), 3);
  for (size_t p = 0; p < pixels(); ++p)
    for (uint64_t e = offset_[p]; e < offset_[p + 1]; ++e)
      for (int c = 0; c < 3; ++c) {
        const double v = brdf.Value(c, bin_[e]);
        if (v > 0) y(p, c) += weight_[3 * e + c] * v;
      }
  return y;
}

}  // namespace brdfshot
