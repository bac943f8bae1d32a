#include "normals/sphere_geometry.h"

#include <gtest/gtest.h>

namespace brdfshot {

TEST(OrthographicSphere, NormalsAreUnitAndPixelCountMatchesTheDiscArea) {
  const int res = 200;
  const PixelGeometry g = OrthographicSphere(res, 90.0);
  // Disc of radius res/2 pixels: π r² pixel centres, ± the perimeter.
  EXPECT_NEAR(static_cast<double>(g.size()), kPi * 100 * 100, 2 * kPi * 100);
  for (size_t i = 0; i < g.size(); ++i) {
    EXPECT_NEAR(Length(g.normal[i]), 1, 1e-12);
    EXPECT_GT(g.normal[i].z, 0);
  }
}

TEST(OrthographicSphere, MarginDropsGrazingPixels) {
  const PixelGeometry g = OrthographicSphere(128, 60.0);
  for (size_t i = 0; i < g.size(); ++i) EXPECT_GE(g.normal[i].z, 0.5 - 1e-12);
  // Normal z ≥ cos 60° ⇔ radius ≤ sin 60°: area fraction sin²60° = 0.75 of the disc.
  EXPECT_NEAR(g.size() / (kPi * 64 * 64), 0.75, 0.03);
}

TEST(OrthographicSphere, CentrePixelFacesTheCameraAndTopPixelsFaceUp) {
  const PixelGeometry g = OrthographicSphere(101, 89.0);
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.x[i] == 50 && g.y[i] == 50) {
      EXPECT_NEAR(g.normal[i].z, 1, 1e-12);
    }
    if (g.y[i] < 20) {
      EXPECT_GT(g.normal[i].y, 0.5);  // row 0 is the top of the image
    }
  }
}

}  // namespace brdfshot
