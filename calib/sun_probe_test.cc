#include "calib/sun_probe.h"

#include <gtest/gtest.h>

#include "util/check.h"

namespace brdfshot {
namespace {

// Power and centroid computed from the texels, independently of how the disc
// was drawn: Σ L dω must equal the irradiance, the power-weighted mean
// direction must be the light's.
void PowerAndCentroid(const LatLongProbe& p, cv::Vec3d* power, Vec3* centroid) {
  *power = {0, 0, 0};
  Vec3 c(0, 0, 0);
  for (int row = 0; row < p.height(); ++row)
    for (int col = 0; col < p.width(); ++col) {
      const cv::Vec3f L = p.Texel(col, row);
      const double w = p.TexelSolidAngle(row);
      for (int k = 0; k < 3; ++k) (*power)[k] += L[k] * w;
      c = c + p.DirectionAt(col + 0.5, row + 0.5) * (w * (L[0] + L[1] + L[2]));
    }
  *centroid = Normalize(c);
}

TEST(SunProbe, DeliversTheIrradianceFromTheGivenDirection) {
  // DiLiGenT's first light (camera frame: x right, y up, z towards the camera).
  const Vec3 dir(-0.0635, -0.4317, 0.8998);
  const cv::Vec3f e(1.2909f, 1.5776f, 2.1336f);
  for (const double radius : {0.05, 1.0, 3.0}) {
    const LatLongProbe p = SunProbe(dir, e, radius, 512);
    cv::Vec3d power;
    Vec3 centroid;
    PowerAndCentroid(p, &power, &centroid);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(power[k], e[k], 1e-5 * e[k]) << radius;
    // Within half a texel (0.35°) of the light: a disc of texel centres is not
    // exactly round.
    EXPECT_LT(std::acos(std::min(1.0, Dot(centroid, Normalize(dir)))) * 180 / kPi, 0.36) << radius;
  }
}

TEST(SunProbe, RefusesZeroDirectionAndNegativeIntensity) {
  EXPECT_THROW(SunProbe(Vec3(0, 0, 0), cv::Vec3f(1, 1, 1)), Error);
  EXPECT_THROW(SunProbe(Vec3(0, 0, 1), cv::Vec3f(1, -1, 1)), Error);
  EXPECT_THROW(SunProbe(Vec3(0, 0, 1), cv::Vec3f(1, NAN, 1)), Error);
}

TEST(SunOverSkyProbe, AddsTheSkysPowerOverTheUpperHemisphereOnly) {
  // A uniform sky of radiance L over the upper hemisphere delivers 2πL of
  // power (Σ L dω); below the horizon only the sun may be lit.
  const Vec3 dir(0.3, 0.5, 0.8);
  const cv::Vec3f e(1.0f, 2.0f, 3.0f), sky(0.01f, 0.02f, 0.04f);
  const LatLongProbe p = SunOverSkyProbe(dir, e, sky, 2.0, 256);
  cv::Vec3d power;
  Vec3 centroid;
  PowerAndCentroid(p, &power, &centroid);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(power[k], e[k] + 2 * kPi * sky[k], 1e-4 * power[k]) << k;
  for (int row = p.height() / 2; row < p.height(); ++row)
    for (int col = 0; col < p.width(); col += 7) EXPECT_EQ(p.Texel(col, row), cv::Vec3f(0, 0, 0)) << row;
  EXPECT_THROW(SunOverSkyProbe(dir, e, cv::Vec3f(0, -1, 0)), Error);
}

}  // namespace
}  // namespace brdfshot
