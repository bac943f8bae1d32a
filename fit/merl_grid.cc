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

}  // namespace brdfshot
