#include "fit/synthetic_capture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

// A Lambertian table: f = albedo / π in every bin.
MerlBrdf Lambertian(double albedo) {
  const MerlGrid grid{30, 30, 60};
  MerlBrdf b(grid);
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < grid.size(); ++i) b.set_raw(c, i, albedo / kPi / kMerlScale[c]);
  return b;
}

std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

// On the optical axis the tangent cone of a unit sphere at distance d has
// half-angle asin(1/d) and images to a circle of radius f·tan(asin(1/d)): the
// shot's radius is what was asked for.
TEST(SyntheticCapture, TheShotsSphereAppearsWithTheAskedRadius) {
  SphereShot shot;
  shot.width = 400, shot.height = 300, shot.focal_px = 800, shot.radius_px = 90;
  shot.centre_px = {200, 150};
  const SphereView v = ShotView(shot);
  EXPECT_NEAR(v.circle.r, 90, 0.05);
  EXPECT_NEAR(v.circle.cx, 200, 1e-6);
  EXPECT_NEAR(v.circle.cy, 150, 1e-6);
}

// A white-furnace scene: a Lambertian sphere of albedo ρ under a uniform sky
// of radiance L has radiance ρL at every pixel (∫ f cos = ρ). The folder holds
// both brackets, the truth (which reads back as written) and a capture.mk.
TEST(SyntheticCapture, AWhiteFurnaceCaptureHasTheClosedFormRadianceAndReadsBack) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "brdfshot_synthetic_capture_test";
  std::filesystem::remove_all(dir);
  const LatLongProbe sky(cv::Mat(32, 64, CV_32FC3, cv::Scalar::all(2.0)), "sky");
  SyntheticCaptureOptions o;
  o.shot.width = 96, o.shot.height = 72, o.shot.focal_px = 200, o.shot.radius_px = 24;
  o.shot.centre_px = {48, 36};
  o.shot.blur_sigma = 0;
  o.yaw_pitch_roll_deg = {30, 0, 0};
  o.shot.camera_to_probe = Rotation::FromYawPitchRoll(30, 0, 0);
  o.quality.theta_samples = 8, o.quality.phi_samples = 12;
  o.probe_shot_width = 64;
  o.material = "white furnace", o.material_args = "--merl furnace.binary", o.probe_path = "sky.exr";
  o.command = "brdfshot synth-capture test";
  const SyntheticCapture c = WriteSyntheticCapture(Lambertian(0.5), sky, o, dir.string());

  const cv::Vec3f centre = c.photo.radiance.at<cv::Vec3f>(36, 48);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(centre[ch], 0.5 * 2.0, 0.03) << "channel " << ch;
  const cv::Mat written = ReadHdrImage((dir / "truth" / "photo.exr").string());
  EXPECT_EQ(cv::norm(written, c.photo.radiance, cv::NORM_INF), 0);

  const SyntheticCaptureTruth t = SyntheticCaptureTruth::Read((dir / "truth" / "truth.json").string());
  EXPECT_EQ(t.ToJson(), SyntheticCaptureTruth::FromJson(t.ToJson(), "again").ToJson());
  EXPECT_EQ(t.material, o.material);
  EXPECT_EQ(t.material_args, o.material_args);
  EXPECT_EQ(t.yaw_pitch_roll_deg, o.yaw_pitch_roll_deg);
  EXPECT_EQ(t.camera_to_probe.m, o.shot.camera_to_probe.m);
  EXPECT_EQ(t.photo_times.size(), c.photo_frames.size());
  EXPECT_EQ(t.probe_times.size(), c.probe_frames.size());
  EXPECT_EQ(t.sphere.circle.r, c.photo.view.circle.r);
  for (const std::string& f : c.photo_frames) EXPECT_TRUE(std::filesystem::exists(dir / "photo" / f)) << f;
  for (const std::string& f : c.probe_frames) EXPECT_TRUE(std::filesystem::exists(dir / "probe" / f)) << f;
  const std::string mk = Slurp(dir / "capture.mk");
  EXPECT_NE(mk.find("ROTATE       = 30,0,0\n"), std::string::npos) << mk;
  EXPECT_NE(mk.find("FOCAL_PX     = 200\n"), std::string::npos) << mk;
  EXPECT_NE(mk.find("TRUTH        = --merl furnace.binary\n"), std::string::npos) << mk;
  EXPECT_EQ(mk.find("BALL_FILE"), std::string::npos) << "no ball was asked for";

  nlohmann::json other = t.ToJson();
  other["format"] = "brdfshot-fit-3";
  EXPECT_THROW(SyntheticCaptureTruth::FromJson(other, "x.json"), Error);
  std::filesystem::remove_all(dir);
}

}  // namespace brdfshot
