// Small geometric value types (after pbrt-v4): a 3-vector and an orthonormal frame.
// Double precision: directions feed trigonometry near the poles and the
// specular peak, where float loses the MERL θ_h resolution (≈0.01° in bin 1).
#pragma once

#include <cmath>

namespace brdfshot {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double Dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double Length(const Vec3& v) { return std::sqrt(Dot(v, v)); }
inline Vec3 Normalize(const Vec3& v) { return v * (1.0 / Length(v)); }

// Mirror `v` about unit `n`: 2(v·n)n − v.
constexpr Vec3 Reflect(const Vec3& v, const Vec3& n) { return 2.0 * Dot(v, n) * n - v; }

// Orthonormal frame with z along a given unit vector. FromZ uses the branchless
// construction of Duff et al. 2017, continuous everywhere except z = −1 exactly.
struct Frame {
  Vec3 x, y, z;
  static Frame FromZ(const Vec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    return {Vec3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3(b, sign + n.y * n.y * a, -n.y), n};
  }
  // Frame with z = n and x in the plane of n and `towards` (e.g. the view vector),
  // so a local direction's azimuth is measured from that plane.
  static Frame FromZX(const Vec3& n, const Vec3& towards) {
    Vec3 t = towards - Dot(towards, n) * n;
    const double len = Length(t);
    if (len < 1e-12) return FromZ(n);
    t = t * (1.0 / len);
    return {t, Cross(n, t), n};
  }
  Vec3 ToLocal(const Vec3& v) const { return {Dot(v, x), Dot(v, y), Dot(v, z)}; }
  Vec3 FromLocal(const Vec3& v) const { return x * v.x + y * v.y + z * v.z; }
};

constexpr double kPi = 3.14159265358979323846;

}  // namespace brdfshot
