#include "fit/merl_grid.h"

#include <algorithm>
#include <cmath>

namespace brdfshot {

namespace {
// Rotations about z and y by angle a (right-handed).
Vec3 RotZ(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}
Vec3 RotY(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}
}  // namespace

HalfDiff ToHalfDiff(const Vec3& wi, const Vec3& wo) {
  const Vec3 h = Normalize(wi + wo);
  HalfDiff hd;
  hd.theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
  const double phi_h = std::atan2(h.y, h.x);
  const Vec3 d = RotY(RotZ(wi, -phi_h), -hd.theta_h);
  hd.theta_d = std::acos(std::clamp(d.z, -1.0, 1.0));
  hd.phi_d = std::atan2(d.y, d.x);
  if (hd.phi_d < 0) hd.phi_d += 2 * kPi;
  return hd;
}

void FromHalfDiff(const HalfDiff& hd, Vec3* wi, Vec3* wo) {
  const double st = std::sin(hd.theta_d);
  const Vec3 d(st * std::cos(hd.phi_d), st * std::sin(hd.phi_d), std::cos(hd.theta_d));
  const Vec3 h(std::sin(hd.theta_h), 0, std::cos(hd.theta_h));
  *wi = RotY(d, hd.theta_h);
  *wo = Reflect(*wi, h);
}

HalfDiff MerlGrid::LatticePoint(int i, int j, int k) const {
  const double u = static_cast<double>(i) / n_th;
  return {u * u * kPi / 2, j * (kPi / 2) / n_td, k * kPi / n_pd};
}

void MerlGrid::Continuous(const HalfDiff& hd, double* u_h, double* u_d, double* u_p) const {
  *u_h = std::sqrt(std::max(0.0, hd.theta_h) / (kPi / 2)) * n_th;
  *u_d = hd.theta_d / (kPi / 2) * n_td;
  double p = std::fmod(hd.phi_d, kPi);
  if (p < 0) p += kPi;
  *u_p = p / kPi * n_pd;
}

size_t MerlGrid::NearestIndex(const HalfDiff& hd) const {
  double uh, ud, up;
  Continuous(hd, &uh, &ud, &up);
  const int i = std::clamp(static_cast<int>(std::lround(uh)), 0, n_th - 1);
  const int j = std::clamp(static_cast<int>(std::lround(ud)), 0, n_td - 1);
  const int k = static_cast<int>(std::lround(up)) % n_pd;
  return Index(i, j, k);
}

int MerlGrid::TrilinearCorners(const HalfDiff& hd, size_t idx[8], double w[8]) const {
  double uh, ud, up;
  Continuous(hd, &uh, &ud, &up);
  const int i0 = std::clamp(static_cast<int>(std::floor(uh)), 0, n_th - 1);
  const int j0 = std::clamp(static_cast<int>(std::floor(ud)), 0, n_td - 1);
  const int k0 = static_cast<int>(std::floor(up)) % n_pd;
  const double fh = std::clamp(uh - i0, 0.0, 1.0), fd = std::clamp(ud - j0, 0.0, 1.0), fp = up - std::floor(up);
  const int i1 = std::min(i0 + 1, n_th - 1), j1 = std::min(j0 + 1, n_td - 1);
  const int k1 = (k0 + 1) % n_pd;
  int n = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int e = 0; e < 2; ++e) {
        const double x = (a ? fh : 1 - fh) * (b ? fd : 1 - fd) * (e ? fp : 1 - fp);
        if (x == 0) continue;
        idx[n] = Index(a ? i1 : i0, b ? j1 : j0, e ? k1 : k0);
        w[n++] = x;
      }
  return n;
}

bool MerlGrid::Measurable(size_t idx) const { return CosineWeight(idx) > 0; }

double MerlGrid::CosineWeight(size_t idx) const {
  int i, j, k;
  Unindex(idx, &i, &j, &k);
  Vec3 wi, wo;
  FromHalfDiff(LatticePoint(i, j, k), &wi, &wo);
  // A small tolerance: lattice points exactly on the horizon count as unmeasured.
  if (wi.z <= 1e-9 || wo.z <= 1e-9) return 0;
  return wi.z * wo.z;
}

std::vector<float> MerlGrid::CosineWeightTable() const {
  std::vector<double> cos_h(n_th), sin_h(n_th), cos_d(n_td), sin_d(n_td), cos_p(n_pd), sin_p(n_pd);
  for (int i = 0; i < n_th; ++i) {
    const double t = LatticePoint(i, 0, 0).theta_h;
    cos_h[i] = std::cos(t), sin_h[i] = std::sin(t);
  }
  for (int j = 0; j < n_td; ++j) {
    const double t = LatticePoint(0, j, 0).theta_d;
    cos_d[j] = std::cos(t), sin_d[j] = std::sin(t);
  }
  for (int k = 0; k < n_pd; ++k) {
    const double t = LatticePoint(0, 0, k).phi_d;
    cos_p[k] = std::cos(t), sin_p[k] = std::sin(t);
  }
  std::vector<float> w(size());
  // The arithmetic of FromHalfDiff and CosineWeight on the same sines.
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n_th; ++i)
    for (int j = 0; j < n_td; ++j)
      for (int k = 0; k < n_pd; ++k) {
        const Vec3 d(sin_d[j] * cos_p[k], sin_d[j] * sin_p[k], cos_d[j]);
        const Vec3 h(sin_h[i], 0, cos_h[i]);
        const Vec3 wi(cos_h[i] * d.x + sin_h[i] * d.z, d.y, -sin_h[i] * d.x + cos_h[i] * d.z);
        const Vec3 wo = Reflect(wi, h);
        w[Index(i, j, k)] = wi.z <= 1e-9 || wo.z <= 1e-9 ? 0.0f : static_cast<float>(wi.z * wo.z);
      }
  return w;
}

}  // namespace brdfshot
