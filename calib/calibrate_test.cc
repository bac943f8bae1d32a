#include "calib/calibrate.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "calib/test_probes.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("brdfshot_calibrate_" + name)).string();
}

double DegreesBetween(const Rotation& a, const Rotation& b) { return (a * b.Inverse()).Angle() * 180 / kPi; }

}  // namespace

// A generated sun: the probe's irradiance on a surface facing it is the
// irradiance asked for (E = ∫ L cos over the sun's disc), and the rotation and
// scale given pass through unchanged.
TEST(Calibrate, ASunDeliversItsIrradianceAndKeepsTheGivenRotationAndScale) {
  CalibrateOptions o;
  o.sun = SunLight{Normalize(Vec3(0.3, 0.8, 0.5)), cv::Vec3d(2, 1, 0.5), 2.0};
  o.width = 256;
  o.camera_to_probe = Rotation::FromYawPitchRoll(30, 5, 0);
  o.yaw_pitch_roll_deg = {30, 5, 0};
  o.scale = {2, 2, 2};
  const CalibrateResult r = Calibrate(o);
  EXPECT_EQ(r.calibration.layout, "sun");
  EXPECT_EQ(r.probe.width(), 256);
  EXPECT_EQ(r.calibration.width, 256);
  const cv::Vec3d e = Irradiance(r.probe, o.sun->direction);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], o.sun->irradiance[c], 0.01 * o.sun->irradiance[c]);
  EXPECT_EQ(r.calibration.camera_to_probe.m, o.camera_to_probe.m);
  EXPECT_EQ(r.calibration.scale, o.scale);
  EXPECT_FALSE(r.card.has_value());
}

// A grey card under a uniform sky of radiance L receives E = πL whatever its
// normal, so its radiance is a·L; photographed at k times that, the measured
// scale is k — the closed form, independent of the probe's sampling.
TEST(Calibrate, AReferenceCardUnderAUniformSkyGivesTheKnownScale) {
  const std::string probe_path = TempPath("uniform.exr"), card_path = TempPath("card.exr");
  WriteExr(probe_path, cv::Mat(64, 128, CV_32FC3, cv::Scalar::all(2.0)));
  const cv::Vec3d k(0.5, 1.5, 3.0);
  const double albedo = 0.18;
  cv::Mat photo(48, 64, CV_32FC3, cv::Scalar::all(0));
  photo(cv::Rect(10, 8, 20, 16)).setTo(cv::Scalar(albedo * 2 * k[0], albedo * 2 * k[1], albedo * 2 * k[2]));
  WriteExr(card_path, photo);
  CalibrateOptions o;
  o.probe_path = probe_path;
  o.card_photo = card_path;
  o.card = {cv::Rect(10, 8, 20, 16), albedo, Vec3(0.2, 0.1, 1)};
  const CalibrateResult r = Calibrate(o);
  std::filesystem::remove(probe_path);
  std::filesystem::remove(card_path);
  ASSERT_TRUE(r.card.has_value());
  EXPECT_EQ(r.card->pixels, 20 * 16);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.calibration.scale[c], k[c], 1e-3 * k[c]);
  EXPECT_TRUE(r.warnings.empty()) << "an evenly lit card is not flagged";
  EXPECT_TRUE(r.calibration.provenance.contains("scale_from_card"));
}

// The rotation from a mirror-ball photo: the studio probe turned by a known
// rotation, rendered in an orthographic ball whose circle the user marks, is
// recovered within a texel (1.4° at 256 wide).
TEST(Calibrate, TheRotationFromAMarkedMirrorBallIsTheOneItWasShotWith) {
  const std::string exr = AssetPath("envmaps/studio_256.exr");
  if (exr.empty()) GTEST_SKIP() << "samples/assets not found";
  const LatLongProbe probe = LatLongProbe::Read(exr);
  const Rotation truth = Rotation::FromYawPitchRoll(-60, 10, 0);
  const std::string ball_path = TempPath("ball.exr");
  WriteExr(ball_path, RenderMirrorBall(probe.Rotated(truth), 300));
  CalibrateOptions o;
  o.probe_path = exr;
  o.rotation_from_ball = ball_path;
  o.ball_location.circle = Circle{150, 150, 150};
  const CalibrateResult r = Calibrate(o);
  std::filesystem::remove(ball_path);
  EXPECT_LT(DegreesBetween(r.calibration.camera_to_probe, truth), 1.0);
  EXPECT_NEAR(r.calibration.yaw_pitch_roll_deg[0], -60, 1.0);
  EXPECT_TRUE(r.calibration.provenance.at("rotation_from_ball").at("circle_given").get<bool>());
}

TEST(Calibrate, BadInputsNameTheFile) {
  const std::string square = TempPath("not_square.exr");
  WriteExr(square, cv::Mat(16, 32, CV_32FC3, cv::Scalar::all(1)));
  CalibrateOptions o;
  o.probe_path = square;
  o.layout = "angular";
  try {
    Calibrate(o);
    ADD_FAILURE() << "a non-square angular map is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(square), std::string::npos) << e.what();
  }
  std::filesystem::remove(square);
  o.probe_path = TempPath("missing.exr");
  o.layout = "latlong";
  try {
    Calibrate(o);
    ADD_FAILURE() << "a missing probe is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
  }
}

TEST(Calibrate, ThirtySixMillimetresAreTheLongerSide) {
  EXPECT_DOUBLE_EQ(FocalPxFrom35mm(36, cv::Size(4000, 3000)), 4000);
  EXPECT_DOUBLE_EQ(FocalPxFrom35mm(18, cv::Size(3000, 4000)), 2000);
}

}  // namespace brdfshot
