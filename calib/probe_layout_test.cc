#include "calib/probe_layout.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "util/data_paths.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

// A smooth probe with a known closed form per direction: the round trips are
// measured against it, not against our own resampling.
LatLongProbe SmoothProbe(int width) {
  LatLongProbe frame(cv::Mat(width / 2, width, CV_32FC3, cv::Scalar::all(0)));
  cv::Mat m(width / 2, width, CV_32FC3);
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) {
      const Vec3 d = frame.DirectionAt(c + 0.5, r + 0.5);
      m.at<cv::Vec3f>(r, c) = cv::Vec3f(1.5 + d.x, 1.5 + d.y, 1.5 + d.z * d.x);
    }
  return LatLongProbe(m);
}

double RelRmse(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = cv::Mat()) {
  double se = 0, ref = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      if (!mask.empty() && !mask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f d = a.at<cv::Vec3f>(y, x) - b.at<cv::Vec3f>(y, x), t = b.at<cv::Vec3f>(y, x);
      se += d.dot(d), ref += t.dot(t);
    }
  return std::sqrt(se / ref);
}

TEST(ProbeLayout, AngularMapRoundTripIsCloseOnASmoothProbe) {
  const LatLongProbe p = SmoothProbe(256);
  const LatLongProbe back = AngularMapToLatLong(LatLongToAngularMap(p, 512), 256);
  // The angular map's rim (+Z) squeezes a whole ring into one pixel circle:
  // compare away from it, i.e. directions within 150° of −Z.
  cv::Mat mask(128, 256, CV_8U);
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 256; ++c) mask.at<uint8_t>(r, c) = p.DirectionAt(c + 0.5, r + 0.5).z < std::cos(kPi / 6) ? 1 : 0;
  EXPECT_LT(RelRmse(back.rgb(), p.rgb(), mask), 2e-3);
}

TEST(ProbeLayout, MirrorBallRenderUnwrapsBackToTheProbe) {
  const LatLongProbe p = SmoothProbe(256);
  const cv::Mat ball = RenderMirrorBall(p, 400);
  const UnwrappedBall u = UnwrapMirrorBall(ball, 200, 200, 200, 256);
  const double e = RelRmse(u.probe.rgb(), p.rgb(), u.measured);
  double seen = 0;
  for (int r = 0; r < u.measured.rows; ++r)
    for (int c = 0; c < u.measured.cols; ++c) seen += u.measured.at<uint8_t>(r, c) ? u.probe.TexelSolidAngle(r) : 0;
  seen /= 4 * kPi;
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

TEST(ProbeLayout, RealProbeThroughAMirrorBall) {
  const std::string path = DataPath("envmaps/forest.exr");
  if (path.empty() || !std::filesystem::exists(path)) GTEST_SKIP() << "envmaps/forest.exr not found";
  const LatLongProbe p = LatLongProbe::Read(path).Resized(256);
  const UnwrappedBall u = UnwrapMirrorBall(RenderMirrorBall(p, 512), 256, 256, 256, 256);
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
