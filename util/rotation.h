// A rotation between two frames (camera → probe in this project), as a 3×3
// orthonormal matrix. Small value type, pbrt style.
#pragma once

#include <array>
#include <algorithm>
#include <cmath>
#include <string>

#include "util/vec3.h"

namespace brdfshot {

struct Rotation {
  std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

  Vec3 operator()(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  Rotation operator*(const Rotation& o) const {
    Rotation r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j] + m[i][2] * o.m[2][j];
    return r;
  }
  Rotation Inverse() const {
    Rotation r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[j][i];
    return r;
  }
  // Largest deviation of RᵀR from I: 0 for a rotation.
  double OrthonormalityError() const {
    double e = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double d = 0;
        for (int k = 0; k < 3; ++k) d += m[k][i] * m[k][j];
        e = std::max(e, std::abs(d - (i == j)));
      }
    return e;
  }
  // Angle of R (radians).
  double Angle() const {
    const double tr = m[0][0] + m[1][1] + m[2][2];
    return std::acos(std::clamp(0.5 * (tr - 1), -1.0, 1.0));
  }

  // R = R_y(yaw) R_x(pitch) R_z(roll), degrees: yaw turns about the probe's up
  // (+Y, positive from +Z towards +X), pitch about +X (from +Y towards +Z), roll
  // about +Z (from +X towards +Y) — roll first, yaw last.
  static Rotation FromYawPitchRoll(double yaw_deg, double pitch_deg, double roll_deg) {
    const double d = kPi / 180;
    const double cy = std::cos(yaw_deg * d), sy = std::sin(yaw_deg * d);
    const double cp = std::cos(pitch_deg * d), sp = std::sin(pitch_deg * d);
    const double cr = std::cos(roll_deg * d), sr = std::sin(roll_deg * d);
    Rotation Y, X, Z;
    Y.m = {{{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}}};
    X.m = {{{1, 0, 0}, {0, cp, -sp}, {0, sp, cp}}};
    Z.m = {{{cr, -sr, 0}, {sr, cr, 0}, {0, 0, 1}}};
    return Y * X * Z;
  }
  // The angles FromYawPitchRoll takes, degrees: pitch in [−90, 90], yaw and
  // roll in (−180, 180]. R's middle row is (cos p sin r, cos p cos r, −sin p)
  // and its last column (sin y cos p, −sin p, cos y cos p). At pitch ±90° only
  // yaw − roll (or yaw + roll) is defined: roll is then 0.
  std::array<double, 3> ToYawPitchRoll() const {
    const double d = 180 / kPi;
    // (+ 0.0 turns a −0 into 0, so that printed angles do not read "-0.00".)
    const double pitch = std::asin(std::clamp(-m[1][2], -1.0, 1.0)) + 0.0;
    if (std::abs(m[1][2]) > 1 - 1e-12) return {std::atan2(-m[2][0], m[0][0]) * d + 0.0, pitch * d, 0.0};
    return {std::atan2(m[0][2], m[2][2]) * d + 0.0, pitch * d, std::atan2(m[1][0], m[1][1]) * d + 0.0};
  }
};

}  // namespace brdfshot
