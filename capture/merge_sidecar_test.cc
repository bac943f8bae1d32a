#include "capture/merge_sidecar.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "util/check.h"

namespace brdfshot {
namespace {

MergeSidecar Example(bool raw) {
  MergeSidecar m;
  for (int k = 0; k < 3; ++k)
    m.frames.push_back(
        {{"file", "f" + std::to_string(k) + ".nef"}, {"exposure", 0.01 * (1 << k)}, {"wb", {2.0, 1.0, 1.5}}});
  m.camera = "Nikon D700";
  m.focal_35mm = 54;
  m.response = ResponseCurve::Linear16();
  m.raw = raw;
  m.aligned = true;
  m.unreliable_fraction = 0.125;
  m.clip_reach = 2;
  m.output = "photo.exr";
  m.mask = "photo_mask.png";
  m.command = "brdfshot merge photo/ -o photo.exr";
  return m;
}

TEST(MergeSidecar, RoundTripsThroughItsFile) {
  const MergeSidecar m = Example(true);
  const std::string path = (std::filesystem::temp_directory_path() / "brdfshot_merge_sidecar_test.json").string();
  m.Write(path);
  const MergeSidecar r = MergeSidecar::Read(path);
  std::filesystem::remove(path);
  EXPECT_EQ(r.ToJson(), m.ToJson());
  EXPECT_EQ(r.frames, m.frames);
  EXPECT_EQ(r.camera, m.camera);
  EXPECT_EQ(r.focal_35mm, 54);
  EXPECT_EQ(r.response.g, m.response.g);
  EXPECT_TRUE(r.raw && r.aligned && !r.half);
  EXPECT_EQ(r.unreliable_fraction, 0.125);
  EXPECT_EQ(r.clip_reach, 2);
  EXPECT_EQ(r.WhiteBalance("p.json"), cv::Vec3d(2, 1, 1.5));
  EXPECT_EQ(Example(false).WhiteBalance("p.json"), cv::Vec3d(1, 1, 1)) << "white balance applies to RAW only";
}

TEST(MergeSidecar, RefusesWhatIsNotOneNamingTheFile) {
  auto message = [](const nlohmann::json& j) {
    try {
      MergeSidecar::FromJson(j, "m.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const nlohmann::json good = Example(false).ToJson();
  EXPECT_EQ(message(good), "accepted");
  EXPECT_NE(message({{"format", "brdfshot-calib-1"}}).find("m.json: not a brdfshot merge sidecar"), std::string::npos);
  EXPECT_NE(message({{"format", 5}}).find("m.json: not a brdfshot merge sidecar"), std::string::npos);
  nlohmann::json j = good;
  j["frames"] = nlohmann::json::array();
  EXPECT_NE(message(j).find("m.json: lists no frames"), std::string::npos);
  j = good;
  j["focal_35mm"] = -3;
  EXPECT_NE(message(j).find("m.json: focal_35mm must be"), std::string::npos);
  j = good;
  j.erase("response");
  EXPECT_NE(message(j).find("m.json: incomplete merge sidecar"), std::string::npos);
  MergeSidecar mixed = Example(true);
  mixed.frames[1]["wb"] = {2.0, 1.0, 1.4};
  EXPECT_THROW(mixed.WhiteBalance("m.json"), Error);
}

}  // namespace
}  // namespace brdfshot
