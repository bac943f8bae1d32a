#include "normals/sphere_from_photo.h"

#include <gtest/gtest.h>

#include <cmath>

#include "normals/synthetic_sphere.h"
#include "util/check.h"

namespace brdfshot {
namespace {

TEST(RimOutsidePercent, ClosedFormsAtTheBorderAndTheCorner) {
  const cv::Size size(200, 100);
  EXPECT_EQ(RimOutsidePercent({100, 50, 30}, size), 0);
  EXPECT_NEAR(RimOutsidePercent({200, 50, 30}, size), 50, 1) << "centred on the right edge: half the rim";
  EXPECT_NEAR(RimOutsidePercent({0, 0, 30}, size), 75, 1) << "centred on a corner: three quarters";
  EXPECT_EQ(RimOutsidePercent({199.9, 50, 0.05}, size), 0) << "inside by a hair";
}

TEST(NormalMapOf, UnitNormalsFacingTheCameraInsideAndZeroOutside) {
  SphereView v;
  v.width = 64;
  v.height = 64;
  v.circle = {32, 32, 20};
  const cv::Mat map = NormalMapOf(v);
  ASSERT_EQ(map.size(), cv::Size(64, 64));
  EXPECT_EQ(map.at<cv::Vec3f>(0, 0), cv::Vec3f(0, 0, 0)) << "off the sphere";
  int inside = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const cv::Vec3f n = map.at<cv::Vec3f>(y, x);
      if (n == cv::Vec3f(0, 0, 0)) continue;
      ++inside;
      EXPECT_NEAR(cv::norm(n), 1.0, 1e-5);
      EXPECT_GE(n[2], 0.0f) << "the visible hemisphere faces the camera";
    }
  // About the disc's area (π r² = 1257 pixels).
  EXPECT_NEAR(inside, kPi * 20 * 20, 0.03 * kPi * 20 * 20);
  // Camera frame: x right, y up — the orthographic normal is ((x − cx)/r, −(y − cy)/r, ·).
  const cv::Vec3f right = map.at<cv::Vec3f>(32, 46), below = map.at<cv::Vec3f>(46, 32);
  EXPECT_NEAR(right[0], (46.5 - 32) / 20, 1e-4);
  EXPECT_NEAR(below[1], -(46.5 - 32) / 20, 1e-4);
}

TEST(ViewOfDetection, CarriesTheDetectedGeometry) {
  SphereDetection det;
  det.circle = {10.5, 20.25, 7};
  det.perspective = true;
  det.focal_px = 900;
  det.principal = {40, 30};
  const SphereView v = ViewOfDetection(det, cv::Size(80, 60));
  EXPECT_EQ(v.width, 80);
  EXPECT_EQ(v.height, 60);
  EXPECT_EQ(v.circle.cx, 10.5);
  EXPECT_EQ(v.circle.r, 7);
  EXPECT_TRUE(v.perspective);
  EXPECT_EQ(v.focal_px, 900);
  EXPECT_EQ(v.principal, cv::Point2d(40, 30));
}

}  // namespace
}  // namespace brdfshot

namespace brdfshot {

// A sphere whose rim crosses the left border is measured from its visible rim
// and flagged; one inside the frame is not; a photo without a sphere is an
// error naming the photo.
TEST(FindSphereInPhoto, MeasuresASphereCutByTheBorderAndSaysSo) {
  SyntheticSphereScene scene;
  scene.circle = {100, 240, 150};
  const SphereInPhoto cut = FindSphereInPhoto(RenderSyntheticSphere(scene), SphereDetectOptions{}, "cut.exr");
  EXPECT_NEAR(cut.view.circle.cx, 100, 1.0);
  EXPECT_NEAR(cut.view.circle.r, 150, 1.0);
  ASSERT_EQ(cut.warnings.size(), 1u);
  EXPECT_NE(cut.warnings[0].find("cut.exr: the sphere is cut by the image border"), std::string::npos)
      << cut.warnings[0];
  scene.circle = {320, 240, 150};
  EXPECT_TRUE(FindSphereInPhoto(RenderSyntheticSphere(scene), SphereDetectOptions{}, "whole.exr").warnings.empty());
  try {
    FindSphereInPhoto(cv::Mat(120, 160, CV_32FC3, cv::Scalar::all(0.5)), SphereDetectOptions{}, "grey.exr");
    ADD_FAILURE() << "a flat grey photo has no sphere";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("grey.exr: ", 0), 0u) << e.what();
  }
}

}  // namespace brdfshot
