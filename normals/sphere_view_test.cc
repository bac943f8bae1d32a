#include "normals/sphere_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "normals/observation.h"
#include "normals/sphere_detect.h"
#include "util/check.h"
#include "util/atomic_file.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

TEST(SphereView, OrthographicMatchesTheSyntheticSphereLayout) {
  const int res = 96;
  SphereView v;
  v.width = v.height = res;
  v.circle = {res / 2.0, res / 2.0, res / 2.0};
  SphereMaskOptions o;
  o.max_angle_deg = 70;
  o.rim_margin_px = 0;
  const PixelGeometry a = SphereViewGeometry(v, Rotation(), o);
  const PixelGeometry b = OrthographicSphere(res, 70);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.x[i], b.x[i]);
    EXPECT_EQ(a.y[i], b.y[i]);
    EXPECT_LT(Length(a.normal[i] - b.normal[i]), 1e-12);
  }
}

TEST(SphereView, PerspectiveNormalsLieOnTheSphereAndTurnAwayAtTheRim) {
  SphereView v;
  v.width = 800;
  v.height = 600;
  v.perspective = true;
  v.focal_px = 900;
  v.principal = {400, 300};
  const Vec3 centre(1.8, -0.9, -7.0);
  v.cone = {Normalize(centre), std::asin(1 / Length(centre))};
  v.circle = ApparentCircle(v.cone, v.focal_px, v.principal);
  SphereMaskOptions o;
  o.max_angle_deg = 90;
  o.rim_margin_px = 0;
  const PixelGeometry g = SphereViewGeometry(v, Rotation(), o);
  ASSERT_GT(g.size(), 1000u);
  double min_dot = 1;
  for (size_t i = 0; i < g.size(); ++i) {
    // The surface point is where the ray meets the sphere: on the pixel's ray,
    // at unit distance from the centre along the normal.
    const Vec3 d = -g.view[i];
    const Vec3 p = centre + g.normal[i];
    EXPECT_LT(Length(Cross(Normalize(p), d)), 1e-9);
    EXPECT_GT(Dot(g.normal[i], g.view[i]), -1e-9);
    min_dot = std::min(min_dot, Dot(g.normal[i], g.view[i]));
  }
  EXPECT_LT(min_dot, 0.1);  // pixels near the rim see grazing normals
}

TEST(Observations, RoundTripAndCorruptFilesAreErrors) {
  Observations o;
  o.geometry = OrthographicSphere(16);
  o.rgb = Eigen::MatrixXd::Random(o.geometry.size(), 3).cwiseAbs();
  o.header["photo"] = "x.exr";
  const std::string path = (std::filesystem::temp_directory_path() / "brdfshot_obs_test.bsobs").string();
  o.Write(path);
  const Observations r = Observations::Read(path);
  EXPECT_EQ(r.geometry.Hash(), o.geometry.Hash());
  EXPECT_LT((r.rgb - o.rgb).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(r.header["photo"], "x.exr");
  std::string bytes = ReadFileBytes(path);
  EXPECT_THROW(Observations::Parse(bytes.substr(0, bytes.size() - 5), path), Error);
  EXPECT_THROW(Observations::Parse("BSHOTBI1" + bytes.substr(8), path), Error);
  std::string bad = bytes;
  bad[bad.size() - 1] ^= 0x40;  // the last view component: no longer unit
  EXPECT_THROW(Observations::Parse(bad, path), Error);
  std::filesystem::remove(path);
}

// Real photos: the DiLiGenT ball (16-bit PNGs, the dataset's own mask and
// ground-truth normals, 8-bit encoded as (n + 1)/2 with x right, y up).
TEST(SphereView, DiligentBallMaskAndNormalsAgainstTheDatasetsGroundTruth) {
  const std::string dir = DataPath("real/diligent_ballPNG");
  if (dir.empty() || !std::filesystem::exists(dir + "/Normal_gt.png")) GTEST_SKIP() << "DiLiGenT ball not found";
  // One photo lit from the front-ish direction (light 4 of 96): a capture.
  cv::Mat bgr = cv::imread(dir + "/004.png", cv::IMREAD_UNCHANGED), rgb;
  ASSERT_FALSE(bgr.empty());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const SphereDetection det = DetectSphere(rgb);
  SphereView v;
  v.width = rgb.cols;
  v.height = rgb.rows;
  v.circle = det.circle;
  cv::Mat gt_mask = cv::imread(dir + "/mask.png", cv::IMREAD_GRAYSCALE);
  cv::Mat gt_n = cv::imread(dir + "/Normal_gt.png", cv::IMREAD_COLOR);
  // IoU of the silhouette (every pixel whose centre sees the sphere).
  long inter = 0, uni = 0;
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      const bool ours = v.RimDistance(x + 0.5, y + 0.5) > 0, theirs = gt_mask.at<uint8_t>(y, x) > 127;
      inter += ours && theirs;
      uni += ours || theirs;
    }
  const double iou = double(inter) / uni;
  // Normals inside a 1.5 px rim margin, against theirs.
  SphereMaskOptions o;
  o.max_angle_deg = 90;
  const PixelGeometry g = SphereViewGeometry(v, Rotation(), o);
  std::vector<double> err;
  for (size_t i = 0; i < g.size(); ++i) {
    if (gt_mask.at<uint8_t>(g.y[i], g.x[i]) < 128) continue;
    const cv::Vec3b c = gt_n.at<cv::Vec3b>(g.y[i], g.x[i]);  // B, G, R = z, y, x
    const Vec3 n = Normalize(Vec3(c[2] / 127.5 - 1, c[1] / 127.5 - 1, c[0] / 127.5 - 1));
    err.push_back(std::acos(std::clamp(Dot(n, g.normal[i]), -1.0, 1.0)) * 180 / kPi);
  }
  std::sort(err.begin(), err.end());
  const double median = err[err.size() / 2], p90 = err[err.size() * 9 / 10];
  std::printf("DiLiGenT ball: circle (%.2f, %.2f) r %.2f, IoU %.4f, normals median %.2f deg, p90 %.2f deg (%zu px)\n",
              det.circle.cx, det.circle.cy, det.circle.r, iou, median, p90, err.size());
  EXPECT_GE(iou, 0.98);
  EXPECT_LE(median, 1.0);
  EXPECT_LE(p90, 2.0);
}

}  // namespace
}  // namespace brdfshot
