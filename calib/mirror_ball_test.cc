#include "calib/mirror_ball.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "calib/test_probes.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

// Fraction of the sphere of directions the ball measured, by solid angle.
double MeasuredFraction(const UnwrappedBall& u) {
  double seen = 0;
  for (int r = 0; r < u.measured.rows; ++r)
    for (int c = 0; c < u.measured.cols; ++c) seen += u.measured.at<uint8_t>(r, c) ? u.probe.TexelSolidAngle(r) : 0;
  return seen / (4 * kPi);
}

// A ball 5 units off a 700 px pinhole, well off the optical axis: α ≈ 11°, the
// view direction turns by ~18° across the frame and by 2α across the ball.
BallCamera OffAxisPerspectiveBall() {
  const Vec3 centre(1.2, -0.6, -5);
  return BallCamera::Perspective(640, 480, 700, {320, 240}, Normalize(centre), std::asin(1 / Length(centre)));
}

TEST(MirrorBall, MirrorBallRenderUnwrapsBackToTheProbe) {
  const LatLongProbe p = SmoothProbe(256);
  const UnwrappedBall u =
      UnwrapMirrorBall(RenderMirrorBall(p, 400), BallCamera::Orthographic(400, 400, 200, 200, 200), 256);
  const double e = RelRmse(u.probe.rgb(), p.rgb(), u.measured), seen = MeasuredFraction(u);
  std::printf("mirror ball round trip: %.4f relative RMSE over the %.0f %% of directions the ball measured\n", e,
              100 * seen);
  EXPECT_LT(e, 5e-3);
  // Normals up to 70° reflect directions up to 140° from the camera: the
  // measured fraction of the sphere is (1 − cos 140°)/2.
  EXPECT_NEAR(seen, (1 - std::cos(140 * kPi / 180)) / 2, 0.01);
  // The filled part is finite and within the probe's range.
  double lo, hi;
  cv::minMaxLoc(u.probe.rgb().reshape(1), &lo, &hi);
  EXPECT_GT(lo, 0.0);
  EXPECT_LT(hi, 3.0);
}

// The two directions of the perspective model are computed by different
// algorithms (ray–sphere intersection; fixed-point iteration on the normal):
// each must undo the other.
TEST(MirrorBall, PerspectiveReflectingInvertsTrace) {
  const BallCamera cam = OffAxisPerspectiveBall();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  int tried = 0;
  double worst = 0;
  while (tried < 2000) {
    const double px = u(rng) * cam.width, py = u(rng) * cam.height;
    Vec3 n, v;
    if (!cam.Trace(px, py, &n, &v) || Dot(n, v) < std::cos(85 * kPi / 180)) continue;
    ++tried;
    cv::Point2d back;
    Vec3 n2, v2;
    ASSERT_TRUE(cam.Reflecting(Reflect(v, n), &back, &n2, &v2)) << px << "," << py;
    worst = std::max(worst, std::hypot(back.x - px, back.y - py));
  }
  std::printf(
      "perspective ball: reflect(trace(pixel)) lands %.2g px from the pixel at worst (2000 pixels, normals to 85 "
      "deg)\n",
      worst);
  EXPECT_LT(worst, 1e-6);
}

// A perspective ball unwraps back to the probe; unwrapping the same photo as
// if it were orthographic (the ball's apparent circle) is measurably wrong —
// the reason the perspective model exists.
TEST(MirrorBall, PerspectiveBallUnwrapsBackToTheProbe) {
  const LatLongProbe p = SmoothProbe(256);
  const BallCamera cam = OffAxisPerspectiveBall();
  const cv::Mat photo = RenderMirrorBall(p, cam);
  const UnwrappedBall u = UnwrapMirrorBall(photo, cam, 256);
  const double e = RelRmse(u.probe.rgb(), p.rgb(), u.measured);
  // The orthographic stand-in: the image of the cone's axis, radius f·tan α.
  const Vec3 a = cam.centre_dir;
  const BallCamera ortho = BallCamera::Orthographic(cam.width, cam.height, cam.principal.x + cam.focal_px * a.x / -a.z,
                                                    cam.principal.y - cam.focal_px * a.y / -a.z,
                                                    cam.focal_px * std::tan(cam.half_angle) / -a.z);
  const UnwrappedBall w = UnwrapMirrorBall(photo, ortho, 256);
  const double e_ortho = RelRmse(w.probe.rgb(), p.rgb(), w.measured);
  std::printf(
      "perspective ball (r ~ %.0f px) unwrapped: %.4f relative RMSE, as if orthographic: %.4f; measured %.0f %%\n",
      ortho.r, e, e_ortho, 100 * MeasuredFraction(u));
  EXPECT_LT(e, 5e-3);
  EXPECT_GT(e_ortho, 4 * e);
  // Less than the orthographic 88 %: towards the rim the view turns away
  // from the normal by up to α, so the 70° limit (in the ball's own frame)
  // is reached at a smaller angle from the ball's axis.
  EXPECT_GT(MeasuredFraction(u), 0.75);
  EXPECT_LT(MeasuredFraction(u), (1 - std::cos(140 * kPi / 180)) / 2);
}

TEST(MirrorBall, RealProbeThroughAMirrorBall) {
  const std::string path = DataPath("envmaps/forest.exr");
  if (path.empty() || !std::filesystem::exists(path)) GTEST_SKIP() << "envmaps/forest.exr not found";
  const LatLongProbe p = LatLongProbe::Read(path).Resized(256);
  const UnwrappedBall u =
      UnwrapMirrorBall(RenderMirrorBall(p, 512), BallCamera::Orthographic(512, 512, 256, 256, 256), 256);
  const double e = RelRmse(u.probe.rgb(), p.rgb(), u.measured);
  // Power (radiance × solid angle) over the measured directions: what diffuse
  // and glossy reflection see. The per-texel error is larger: near the ball's
  // rim one pixel spans many texels of a real probe's detail.
  double pw_truth = 0, pw_ball = 0;
  for (int r = 0; r < p.height(); ++r)
    for (int c = 0; c < p.width(); ++c)
      if (u.measured.at<uint8_t>(r, c)) {
        pw_truth += cv::sum(p.Texel(c, r))[0] * p.TexelSolidAngle(r);
        pw_ball += cv::sum(u.probe.Texel(c, r))[0] * p.TexelSolidAngle(r);
      }
  std::printf("forest through a 512 px mirror ball: %.3f relative RMSE per texel, power error %.4f\n", e,
              pw_ball / pw_truth - 1);
  EXPECT_LT(std::abs(pw_ball / pw_truth - 1), 0.02);
  EXPECT_LT(e, 0.5);
}

}  // namespace
}  // namespace brdfshot
