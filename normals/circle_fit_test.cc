#include "normals/circle_fit.h"

#include <gtest/gtest.h>

#include <random>

#include "util/check.h"

namespace brdfshot {
namespace {

TEST(CircleFit, RecoversACircleThroughAQuarterOfOutliers) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 0.05);
  const Circle truth{1234.5, 987.25, 321.75};
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < 400; ++i) {
    const double a = 2 * kPi * U(rng);
    const double r = i % 4 == 0 ? truth.r * (0.6 + 0.8 * U(rng)) : truth.r + N(rng);  // 25 % clutter
    pts.emplace_back(truth.cx + r * std::cos(a), truth.cy + r * std::sin(a));
  }
  FitQuality q;
  const Circle c = FitCircleRobust(pts, &q);
  EXPECT_NEAR(c.cx, truth.cx, 0.02);
  EXPECT_NEAR(c.cy, truth.cy, 0.02);
  EXPECT_NEAR(c.r, truth.r, 0.02);
  EXPECT_NEAR(q.rms_px, 0.05, 0.01);
  EXPECT_GE(q.inliers, 295);
  EXPECT_LE(q.inliers, 330);
}

TEST(CircleFit, CollinearOrTooFewPointsAreErrors) {
  std::vector<cv::Point2d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 2 * i + 1);
  EXPECT_THROW(FitCircleRobust(line), Error);
  EXPECT_THROW(FitCircleRobust({{0, 0}, {1, 0}, {0, 1}}), Error);
}

TEST(ConeFit, RecoversAPerspectiveSphereFromItsEllipticalRim) {
  const double f = 1500;
  const cv::Point2d pp(2000, 1500);
  const Vec3 centre(2.0, -1.2, -9.0);
  const Vec3 axis = Normalize(centre);
  const double alpha = std::asin(1 / Length(centre));
  // Rim rays: rotate the axis by α about directions perpendicular to it.
  const Frame fr = Frame::FromZ(axis);
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < 360; ++i) {
    const double phi = 2 * kPi * i / 360;
    const Vec3 d =
        fr.FromLocal(Vec3(std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), std::cos(alpha)));
    pts.emplace_back(pp.x + f * d.x / -d.z, pp.y - f * d.y / -d.z);
  }
  FitQuality q;
  const SphereCone cone = FitConeRobust(pts, f, pp, &q);
  EXPECT_LT(Length(Cross(cone.centre_dir, axis)) * f, 1e-6);  // sin of the angle: acos loses it
  EXPECT_NEAR(cone.half_angle, alpha, 1e-9);
  // The rim is not a circle: a circle fit to it leaves pixel-sized residuals.
  FitQuality cq;
  FitCircleRobust(pts, &cq);
  EXPECT_GT(cq.rms_px, 100 * q.rms_px + 1e-3);
  // Apparent circle of a centred sphere is f tan α about the principal point.
  const Circle c = ApparentCircle({Vec3(0, 0, -1), alpha}, f, pp);
  EXPECT_NEAR(c.cx, pp.x, 1e-9);
  EXPECT_NEAR(c.r, f * std::tan(alpha), 1e-9);
}

}  // namespace
}  // namespace brdfshot
