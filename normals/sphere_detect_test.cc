#include "normals/sphere_detect.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <opencv2/imgcodecs.hpp>
#include <filesystem>

#include "normals/synthetic_sphere.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

double CentreError(const Circle& a, const Circle& b) { return std::hypot(a.cx - b.cx, a.cy - b.cy); }

// Sub-pixel goal of the issue (≤ 0.1 px in centre and radius) on blurred, noisy
// scenes with clutter, and better than HoughCircles alone on the same image.
TEST(SphereDetect, OrthographicSubPixelAndBetterThanHough) {
  double worst_ours = 0, worst_hough = 0;
  for (int seed = 1; seed <= 6; ++seed) {
    SyntheticSphereScene s;
    s.seed = seed;
    s.circle = {300.3 + 7.1 * seed, 231.7 + 3.3 * seed, 60.0 + 27.37 * seed};
    s.blur_sigma = 0.8 + 0.2 * seed;
    s.noise = 0.01;
    const cv::Mat img = RenderSyntheticSphere(s);
    const SphereDetection d = DetectSphere(img);
    // HoughCircles alone: of all its candidates, the one nearest the truth
    // (an oracle's pick — the most favourable reading of Hough's accuracy).
    std::vector<Circle> hough = HoughCandidates(img, {});
    ASSERT_FALSE(hough.empty());
    std::sort(hough.begin(), hough.end(), [&](const Circle& a, const Circle& b) {
      return std::max(CentreError(a, s.circle), std::abs(a.r - s.circle.r)) <
             std::max(CentreError(b, s.circle), std::abs(b.r - s.circle.r));
    });
    const double e = std::max(CentreError(d.circle, s.circle), std::abs(d.circle.r - s.circle.r));
    const double eh = std::max(CentreError(hough[0], s.circle), std::abs(hough[0].r - s.circle.r));
    std::printf("seed %d r %.1f: ours %.3f px (%d/%d inliers), Hough %.3f px\n", seed, s.circle.r, e, d.quality.inliers,
                d.quality.points, eh);
    EXPECT_LE(e, 0.1) << "seed " << seed;
    worst_ours = std::max(worst_ours, e);
    worst_hough = std::max(worst_hough, eh);
  }
  EXPECT_LT(worst_ours, worst_hough);
}

// A red ball before textured green leaves of the same luminance (the ball
// evenly lit, as under an overcast sky): in luminance there is no ball at all
// (Hough on log luminance put a real case, NBRDF red plastic under
// forest.exr, 27 px off), in colour its rim is a full step. Found through
// the colour fallback, to the same sub-pixel goal.
TEST(SphereDetect, RimAtEqualLuminanceFoundByItsColour) {
  const int w = 640, h = 480;
  const Circle truth{331.4, 244.7, 121.3};
  const cv::Vec3f red(0.4f, 0.1f, 0.05f);
  const float lum = 0.2126f * red[0] + 0.7152f * red[1] + 0.0722f * red[2];
  cv::Mat img(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Leaves: the green's saturation varies at constant luminance.
      const float t = static_cast<float>(0.5 + 0.5 * std::sin(0.11 * x) * std::cos(0.07 * y));
      cv::Vec3f g(0.02f + 0.06f * t, 0, 0.03f);
      g[1] = (lum - 0.2126f * g[0] - 0.0722f * g[2]) / 0.7152f;
      cv::Vec3f sum(0, 0, 0);
      const int k = 4;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const double nx = (x + (i + 0.5) / k - truth.cx) / truth.r, ny = (y + (j + 0.5) / k - truth.cy) / truth.r;
          sum += nx * nx + ny * ny < 1 ? red : g;
        }
      img.at<cv::Vec3f>(y, x) = sum / static_cast<float>(k * k);
    }
  cv::GaussianBlur(img, img, cv::Size(), 1.0);
  cv::Mat noise(h, w, CV_32FC3);
  cv::RNG(7).fill(noise, cv::RNG::NORMAL, 0.0, 0.002);
  img += noise;
  const SphereDetection d = DetectSphere(img);
  EXPECT_LE(CentreError(d.circle, truth), 0.1);
  EXPECT_NEAR(d.circle.r, truth.r, 0.1);
  // Luminance alone does not see this rim: no candidate near the truth.
  for (const Circle& c : HoughCandidates(img, {}))
    EXPECT_GT(std::max(CentreError(c, truth), std::abs(c.r - truth.r)), 3.0) << c.cx << " " << c.cy << " " << c.r;
}

TEST(SphereDetect, PerspectiveSphereThroughTheConeModel) {
  SyntheticSphereScene s;
  s.width = 800;
  s.height = 600;
  s.focal_px = 900;
  s.centre = Vec3(1.8, -0.9, -7.0);  // off axis: a visibly elliptical rim
  const cv::Mat img = RenderSyntheticSphere(s);
  SphereDetectOptions o;
  o.focal_px = s.focal_px;
  const SphereDetection d = DetectSphere(img, o);
  const SphereCone t = TrueCone(s);
  const double dir_px = Length(Cross(d.cone.centre_dir, t.centre_dir)) * s.focal_px;
  const double radius_px = std::abs(d.cone.half_angle - t.half_angle) * s.focal_px;
  std::printf("perspective: centre %.3f px, radius %.3f px\n", dir_px, radius_px);
  EXPECT_LE(dir_px, 0.1);
  EXPECT_LE(radius_px, 0.1);
  // The orthographic model does not fit this elliptical rim (px-sized
  // residuals): detection refuses rather than return a biased circle.
  EXPECT_THROW(DetectSphere(img), Error);
}

TEST(SphereDetect, NoSphereIsAnError) {
  SyntheticSphereScene s;
  s.circle.r = 0;  // nothing drawn: background gradient and noise only
  s.clutter = 0;
  EXPECT_THROW(DetectSphere(RenderSyntheticSphere(s)), Error);
}

// Two lit balls apart (a chrome ball beside the sample, two samples in one
// shot): measuring either silently could fit the wrong material, so the
// detector refuses; a point inside one picks it, to the same sub-pixel goal.
TEST(SphereDetect, TwoSpheresAreRefusedUnlessAPointPicksOne) {
  SyntheticSphereScene s;
  s.circle = {190.4, 250.2, 95.3};
  s.second_sphere = {470.7, 215.6, 72.1};
  const cv::Mat img = RenderSyntheticSphere(s);
  try {
    DetectSphere(img);
    ADD_FAILURE() << "a photo with two spheres was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("two spheres found"), std::string::npos) << e.what();
  }
  for (const Circle& truth : {s.circle, s.second_sphere}) {
    SphereDetectOptions o;
    o.near = {truth.cx + 0.3 * truth.r, truth.cy - 0.2 * truth.r};
    const SphereDetection d = DetectSphere(img, o);
    EXPECT_LE(std::max(CentreError(d.circle, truth), std::abs(d.circle.r - truth.r)), 0.1)
        << "picked the ball at " << truth.cx << "," << truth.cy << ", found " << d.circle.cx << "," << d.circle.cy
        << " r " << d.circle.r;
  }
  SphereDetectOptions nowhere;
  nowhere.near = {5, 5};
  EXPECT_THROW(DetectSphere(img, nowhere), Error);
}

// Real photos lit from the side: DiLiGenT's ball under its 96 lights (every
// third here). Where part of the rim is in attached shadow, the linear
// steepest step is the terminator inside the ball: the detector refused 67 of
// 96 lights and put two more 1.8 px off (rim rms 0.97–0.99 px, just passing);
// the log-luminance fallback finds those rims. Every sphere found must lie
// within 1 px of the one found in the frontally lit photo 004.
TEST(SphereDetect, DiligentSideLitBallsFoundThroughTheLogFallback) {
  const std::string dir = DataPath("real/diligent_ballPNG");
  if (dir.empty() || !std::filesystem::exists(dir + "/004.png")) GTEST_SKIP() << "DiLiGenT ball not found";
  auto load = [&](int light) {
    char name[16];
    std::snprintf(name, sizeof name, "/%03d.png", light);
    cv::Mat bgr = cv::imread(dir + name, cv::IMREAD_UNCHANGED), rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    return rgb;
  };
  const SphereDetection front = DetectSphere(load(4));
  ASSERT_FALSE(front.rim_in_shadow);
  int tried = 0, found = 0, in_shadow = 0;
  double worst_centre = 0, worst_radius = 0;
  for (int light = 1; light <= 96; light += 3) {
    ++tried;
    SphereDetection d;
    try {
      d = DetectSphere(load(light));
    } catch (const NoSphereFound&) {
      continue;
    }
    ++found;
    in_shadow += d.rim_in_shadow;
    worst_centre = std::max(worst_centre, std::hypot(d.circle.cx - front.circle.cx, d.circle.cy - front.circle.cy));
    worst_radius = std::max(worst_radius, std::abs(d.circle.r - front.circle.r));
  }
  std::printf(
      "DiLiGenT: %d of %d lights found, %d by log edges; all within %.2f px (centre), %.2f px "
      "(radius) of light 4's sphere\n",
      found, tried, in_shadow, worst_centre, worst_radius);
  EXPECT_GE(found, tried * 8 / 10);
  EXPECT_GE(in_shadow, tried / 3);
  EXPECT_LT(worst_centre, 1.0);
  EXPECT_LT(worst_radius, 1.0);
}

}  // namespace
}  // namespace brdfshot
