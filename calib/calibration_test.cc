#include "calib/calibration.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "util/check.h"

namespace brdfshot {
namespace {

std::string TempPath(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

TEST(Calibration, RoundTripsThroughItsFile) {
  Calibration c;
  c.source = "studio.exr";
  c.layout = "mirrorball";
  c.probe = "probe.exr";
  c.width = 512;
  c.camera_to_probe = Rotation::FromYawPitchRoll(40, 10, -5);
  c.yaw_pitch_roll_deg = {40, 10, -5};
  c.scale = {0.5, 0.25, 2.0};
  c.provenance["ball"] = {{"circle", {1, 2, 3}}};
  const std::string path = TempPath("brdfshot_calibration_test.json");
  c.Write(path);
  const Calibration r = Calibration::Read(path);
  std::filesystem::remove(path);
  EXPECT_EQ(r.source, c.source);
  EXPECT_EQ(r.layout, c.layout);
  EXPECT_EQ(r.probe, c.probe);
  EXPECT_EQ(r.width, c.width);
  EXPECT_EQ(r.camera_to_probe.m, c.camera_to_probe.m) << "doubles survive JSON exactly";
  EXPECT_EQ(r.yaw_pitch_roll_deg, c.yaw_pitch_roll_deg);
  EXPECT_EQ(r.scale, c.scale);
  EXPECT_EQ(r.provenance, c.provenance);
  EXPECT_EQ(r.ToJson(), c.ToJson());
}

TEST(Calibration, OneScaleNumberMeansAllChannels) {
  Calibration c;
  nlohmann::json j = c.ToJson();
  j["scale"] = 3.0;
  EXPECT_EQ(Calibration::FromJson(j, "c.json").scale, cv::Vec3d(3, 3, 3));
}

TEST(Calibration, RefusesOtherFormatsAndBadGeometryNamingTheFile) {
  auto message = [](const nlohmann::json& j) {
    try {
      Calibration::FromJson(j, "c.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const nlohmann::json good = Calibration().ToJson();
  EXPECT_EQ(message(good), "accepted");
  EXPECT_NE(message({{"format", "brdfshot-merge-1"}}).find("c.json: not a brdfshot calibration"), std::string::npos);
  EXPECT_NE(message({{"format", 5}}).find("c.json: not a brdfshot calibration"), std::string::npos);
  EXPECT_NE(message(nlohmann::json::array()).find("c.json: not a brdfshot calibration"), std::string::npos);
  nlohmann::json sheared = good;
  sheared["rotation_camera_to_probe"][0][1] = 0.5;
  EXPECT_NE(message(sheared).find("c.json: rotation is not orthonormal"), std::string::npos);
  nlohmann::json dark = good;
  dark["scale"] = {1, 0, 1};
  EXPECT_NE(message(dark).find("c.json: scale must be positive"), std::string::npos);
  nlohmann::json missing = good;
  missing.erase("scale");
  EXPECT_NE(message(missing).find("c.json: incomplete calibration"), std::string::npos);
}

}  // namespace
}  // namespace brdfshot
