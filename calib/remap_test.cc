#include "calib/remap.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "calib/calibration.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

struct Scene {
  // One folder per test: ctest runs the tests of a binary in parallel.
  fs::path dir =
      fs::temp_directory_path() /
      ("brdfshot_remap_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  std::string photo, sphere, calib;
  Rotation rotation = Rotation::FromYawPitchRoll(90, 20, 0);

  Scene() {
    fs::create_directories(dir);
    photo = (dir / "photo.exr").string();
    sphere = (dir / "sphere.json").string();
    calib = (dir / "probe.json").string();
    WriteExr(photo, cv::Mat(60, 80, CV_32FC3, cv::Scalar(2, 4, 6)));
    SphereView v;
    v.width = 80, v.height = 60;
    v.circle = {40, 30, 20};
    WriteFileAtomic(sphere, [&](std::ostream& o) { o << v.ToJson().dump() << "\n"; });
    Calibration c;
    c.source = c.probe = "probe.exr";
    c.layout = "latlong";
    c.width = 64;
    c.camera_to_probe = rotation;
    c.scale = {2, 2, 2};
    c.Write(calib);
  }
  ~Scene() { fs::remove_all(dir); }
};

}  // namespace

// An orthographic camera looks along −Z, so every pixel's view direction is
// +Z in the camera frame and R·Z in the probe's; radiance is divided by the
// calibration's scale.
TEST(RemapPhoto, PixelsInTheProbeFrameAndUnits) {
  Scene s;
  RemapOptions o;
  o.photo = s.photo;
  o.sphere = s.sphere;
  o.calibration = s.calib;
  const Observations obs = RemapPhoto(o);
  ASSERT_GT(obs.geometry.size(), 600u) << "most of a 20-px sphere's disc";
  EXPECT_LT(obs.geometry.size(), static_cast<size_t>(kPi * 20 * 20));
  const Vec3 view = s.rotation(Vec3(0, 0, 1));
  for (size_t i = 0; i < obs.geometry.size(); ++i) {
    ASSERT_NEAR(Length(obs.geometry.view[i] - view), 0, 1e-12) << i;
    ASSERT_GE(Dot(obs.geometry.normal[i], view), std::cos(kPi / 180 * 80) - 1e-12) << "within the 80° margin";
    ASSERT_NEAR(obs.rgb(i, 0), 1, 1e-6);
    ASSERT_NEAR(obs.rgb(i, 1), 2, 1e-6);
    ASSERT_NEAR(obs.rgb(i, 2), 3, 1e-6);
  }
  EXPECT_EQ(obs.header.at("calib"), s.calib);
  EXPECT_EQ(obs.header.at("scale"), nlohmann::json({2.0, 2.0, 2.0}));
}

TEST(RemapPhoto, AGeometryForAnotherPhotoSizeIsNamed) {
  Scene s;
  WriteExr(s.photo, cv::Mat(50, 80, CV_32FC3, cv::Scalar::all(1)));
  RemapOptions o;
  o.photo = s.photo;
  o.sphere = s.sphere;
  try {
    RemapPhoto(o);
    ADD_FAILURE() << "a sphere file for another photo is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(s.sphere + ": is for a 80x60 photo"), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot
