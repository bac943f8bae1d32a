#include "calib/probe_alignment.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "calib/mirror_ball.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

// The lighting as the camera sees it: L_cam(d) = scale · L_probe(R d).
LatLongProbe InCameraFrame(const LatLongProbe& probe, const Rotation& R, float scale) {
  return LatLongProbe(probe.Rotated(R).rgb() * scale);
}

double DegreesBetween(const Rotation& a, const Rotation& b) { return (a * b.Inverse()).Angle() * 180 / kPi; }

}  // namespace

// Round trip: the committed studio probe, turned by a known rotation, seen in
// a rendered mirror ball (400 px, at a different exposure), unwrapped; the
// estimate must recover the rotation. Tolerance 0.5°: one texel of the 256-wide
// probe is 1.4°.
TEST(ProbeAlignment, RecoversAKnownRotationThroughAMirrorBall) {
  const std::string exr = AssetPath("envmaps/studio_256.exr");
  if (exr.empty()) GTEST_SKIP() << "samples/assets not found";
  const LatLongProbe probe = LatLongProbe::Read(exr);
  for (const auto& ypr : {std::array<double, 3>{37, 0, 0}, {-120, 12, -5}, {75, -20, 8}}) {
    const Rotation truth = Rotation::FromYawPitchRoll(ypr[0], ypr[1], ypr[2]);
    const UnwrappedBall ball = UnwrapMirrorBall(RenderMirrorBall(InCameraFrame(probe, truth, 0.3f), 400),
                                                BallCamera::Orthographic(400, 400, 200, 200, 200), 256);
    const RotationFit fit = EstimateRotation(probe, ball.probe, ball.measured);
    const double err = DegreesBetween(fit.rotation, truth);
    std::printf("truth yaw %.0f pitch %.0f roll %.0f -> %.2f %.2f %.2f: %.3f deg off, rms log %.3f\n", ypr[0], ypr[1],
                ypr[2], fit.yaw, fit.pitch, fit.roll, err, fit.rms_log);
    EXPECT_LT(err, 0.5);
  }
}

TEST(ProbeAlignment, TooFewMeasuredDirectionsIsAnError) {
  const LatLongProbe p(cv::Mat(32, 64, CV_32FC3, cv::Scalar::all(1)));
  EXPECT_THROW(EstimateRotation(p, p, cv::Mat::zeros(32, 64, CV_8U)), Error);
}

}  // namespace brdfshot
