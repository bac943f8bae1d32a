#include "normals/normal_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "normals/sphere_detect.h"
#include "normals/sphere_view.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

double Degrees(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(Dot(a, b), -1.0, 1.0)) * 180 / kPi; }

// The normal map a renderer would write for a view of a sphere: float normals
// where the pixel centre sees it, (0, 0, 0) elsewhere.
cv::Mat RenderNormalMap(const SphereView& v) {
  cv::Mat n(v.height, v.width, CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      Vec3 normal, view;
      if (v.Trace(x + 0.5, y + 0.5, &normal, &view))
        n.at<cv::Vec3f>(y, x) = cv::Vec3f(float(normal.x), float(normal.y), float(normal.z));
    }
  return n;
}

// Closed form: the orthographic unit sphere's normals, stored as a 16-bit PNG
// would store them, decode to OrthographicSphere's pixels and normals.
TEST(NormalMap, SixteenBitSphereDecodesToTheAnalyticSphere) {
  const int res = 96;
  cv::Mat png(res, res, CV_16UC3, cv::Scalar::all(0));
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x) {
      const double sx = 2.0 * (x + 0.5) / res - 1, sy = 1 - 2.0 * (y + 0.5) / res, r2 = sx * sx + sy * sy;
      if (r2 >= 1) continue;
      const double n[3] = {sx, sy, std::sqrt(1 - r2)};
      for (int c = 0; c < 3; ++c) png.at<cv::Vec3w>(y, x)[c] = cv::saturate_cast<uint16_t>((n[c] + 1) / 2 * 65535);
    }
  NormalMapOptions o;
  o.erode_px = 0;
  const PixelGeometry got = NormalMapGeometry(DecodeNormalMap(png), cv::Mat(), o, Rotation());
  const PixelGeometry want = OrthographicSphere(res, o.max_angle_deg);
  std::map<std::pair<int, int>, size_t> at;
  for (size_t i = 0; i < want.size(); ++i) at[{want.x[i], want.y[i]}] = i;
  double worst = 0;
  size_t matched = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    const auto it = at.find({got.x[i], got.y[i]});
    if (it == at.end()) continue;
    ++matched;
    worst = std::max(worst, Degrees(got.normal[i], want.normal[it->second]));
    EXPECT_EQ(got.view[i].z, 1.0);
  }
  // The 80° cut may fall either side for a pixel whose quantised normal sits on it.
  EXPECT_GE(matched, want.size() - want.size() / 100);
  EXPECT_LE(got.size(), want.size() + want.size() / 100);
  EXPECT_LT(worst, 0.01);  // 16-bit steps are 3e-5 per component
}

// Perspective: the view of each pixel is its own ray, and the rotation into
// the probe frame applies to both vectors — against the sphere's own geometry.
TEST(NormalMap, PerspectiveNormalMapMatchesTheSphereViewGeometry) {
  SphereView v;
  v.width = 320, v.height = 240, v.perspective = true, v.focal_px = 400, v.principal = {160, 120};
  const Vec3 centre(0.8, 0.3, -5);
  v.cone = {Normalize(centre), std::asin(1 / Length(centre))};
  v.circle = ApparentCircle(v.cone, v.focal_px, v.principal);
  const Rotation R = Rotation::FromYawPitchRoll(30, -10, 5);
  SphereMaskOptions sm;
  sm.rim_margin_px = 0;
  const PixelGeometry want = SphereViewGeometry(v, R, sm);
  NormalMapOptions o;
  o.focal_px = v.focal_px;
  o.erode_px = 0;
  const PixelGeometry got = NormalMapGeometry(RenderNormalMap(v), cv::Mat(), o, R);
  ASSERT_EQ(got.size(), want.size());
  double worst_n = 0, worst_v = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got.x[i], want.x[i]);
    ASSERT_EQ(got.y[i], want.y[i]);
    worst_n = std::max(worst_n, Length(got.normal[i] - want.normal[i]));
    worst_v = std::max(worst_v, Length(got.view[i] - want.view[i]));
  }
  EXPECT_LT(worst_n, 1e-6);  // float storage
  EXPECT_LT(worst_v, 1e-12);
}

TEST(NormalMap, ErosionKeepsPixelsAwayFromTheSilhouette) {
  SphereView v;
  v.width = v.height = 120;
  v.circle = {60, 60, 50};
  NormalMapOptions o;
  o.max_angle_deg = 90;
  o.erode_px = 0;
  const cv::Mat n = RenderNormalMap(v);
  const PixelGeometry all = NormalMapGeometry(n, cv::Mat(), o, Rotation());
  o.erode_px = 2;
  const PixelGeometry inner = NormalMapGeometry(n, cv::Mat(), o, Rotation());
  double closest_all = 1e9, closest_inner = 1e9;
  for (size_t i = 0; i < all.size(); ++i)
    closest_all = std::min(closest_all, v.RimDistance(all.x[i] + 0.5, all.y[i] + 0.5));
  for (size_t i = 0; i < inner.size(); ++i)
    closest_inner = std::min(closest_inner, v.RimDistance(inner.x[i] + 0.5, inner.y[i] + 0.5));
  EXPECT_LT(closest_all, 0.5);
  EXPECT_GT(closest_inner, 1.5);  // two 3×3 erosions: at least ~2 px in
  // A mask of the wrong size is the user's error, named.
  EXPECT_THROW(NormalMapGeometry(n, cv::Mat(10, 10, CV_8U, cv::Scalar(255)), o, Rotation()), Error);
}

// Real data: DiLiGenT's ground-truth normal map and mask, through this path,
// against the sphere our detector finds in the photo (measured separately in
// sphere_view_test: median 0.37°). A wrong axis convention would be ~90° off.
TEST(NormalMap, DiligentGroundTruthMapAgreesWithTheDetectedSphere) {
  const std::string dir = DataPath("real/diligent_ballPNG");
  if (dir.empty() || !std::filesystem::exists(dir + "/Normal_gt.png")) GTEST_SKIP() << "DiLiGenT ball not found";
  cv::Mat bgr = cv::imread(dir + "/Normal_gt.png", cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR), rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const cv::Mat mask = cv::imread(dir + "/mask.png", cv::IMREAD_GRAYSCALE);
  const PixelGeometry got = NormalMapGeometry(DecodeNormalMap(rgb), mask, NormalMapOptions{}, Rotation());
  // Light 4 of 96, lit from the front: the photo sphere_view_test measures.
  cv::Mat photo = cv::imread(dir + "/004.png", cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
  photo.convertTo(photo, CV_32FC3);
  const SphereDetection det = DetectSphere(photo);
  SphereView v;
  v.width = photo.cols, v.height = photo.rows, v.circle = det.circle;
  std::vector<double> err;
  for (size_t i = 0; i < got.size(); ++i) {
    Vec3 n, view;
    if (v.Trace(got.x[i] + 0.5, got.y[i] + 0.5, &n, &view)) err.push_back(Degrees(n, got.normal[i]));
  }
  ASSERT_GT(err.size(), got.size() * 9 / 10);
  std::sort(err.begin(), err.end());
  std::printf("DiLiGenT normal map: %zu pixels, against the detected sphere median %.2f p90 %.2f deg\n", got.size(),
              err[err.size() / 2], err[err.size() * 9 / 10]);
  EXPECT_LT(err[err.size() / 2], 1.0);
  EXPECT_LT(err[err.size() * 9 / 10], 2.0);
}

TEST(ReadNormalMap, UndecodableFileIsNamed) {
  const std::string path = (std::filesystem::temp_directory_path() / "brdfshot_not_a_map.png").string();
  std::ofstream(path) << "not a png";
  try {
    ReadNormalMap(path);
    ADD_FAILURE() << "garbage decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": cannot decode normal map"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace brdfshot
