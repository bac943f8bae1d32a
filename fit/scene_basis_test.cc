#include "fit/scene_basis.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "fit/test_databases.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

SceneBasisOptions DemoScene(const std::string& probe) {
  SceneBasisOptions o;
  o.probe = probe;
  o.sphere = 16;
  o.quality.theta_samples = 8;
  o.quality.phi_samples = 12;
  o.database = DemoStandins();
  return o;
}

}  // namespace

// Light transport is linear in the lighting: the same scene under a probe of
// twice the radiance has twice every basis image. The header names what the
// images are of, so a later fit can refuse images of another scene.
TEST(SceneBasis, ImagesAreLinearInTheProbeAndTheHeaderNamesTheScene) {
  const fs::path dir = fs::temp_directory_path() / "brdfshot_scene_basis_test";
  fs::create_directories(dir);
  cv::Mat sky(16, 32, CV_32FC3);
  cv::randu(sky, cv::Scalar::all(0.1), cv::Scalar::all(2.0));
  const std::string one = (dir / "one.exr").string(), two = (dir / "two.exr").string();
  WriteExr(one, sky);
  WriteExr(two, cv::Mat(sky * 2));
  const SceneBasis a = ComputeSceneBasis(DemoScene(one)), b = ComputeSceneBasis(DemoScene(two));
  const uint64_t one_hash = LatLongProbe::Read(one).Hash();
  fs::remove_all(dir);

  ASSERT_EQ(a.images.Y[0].cols(), a.bases);
  EXPECT_EQ(a.bases, 3 * 16) << "the 16 demo stand-ins, three channels each";
  EXPECT_EQ(a.images.geometry.size(), OrthographicSphere(16, 80).size());
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(a.images.Y[c].norm(), 0);
    EXPECT_LT((b.images.Y[c] - 2 * a.images.Y[c]).norm(), 1e-5 * b.images.Y[c].norm()) << "channel " << c;
  }
  const nlohmann::json& h = a.images.header;
  EXPECT_EQ(h.at("probe"), one);
  EXPECT_EQ(h.at("probe_hash"), one_hash);
  EXPECT_NE(h.at("probe_hash"), b.images.header.at("probe_hash"));
  EXPECT_EQ(h.at("geometry_hash"), a.images.geometry.Hash());
  EXPECT_EQ(h.at("bases").size(), static_cast<size_t>(a.bases));
  EXPECT_EQ(h.at("geometry"), "orthographic-sphere");
  EXPECT_FALSE(a.search.has_value());
}

}  // namespace brdfshot
