#include "capture/align.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "capture/synthetic_bracket.h"
#include "util/check.h"

namespace brdfshot {
namespace {

cv::Mat TexturedRadiance(int w, int h) {
  cv::Mat noise(h, w, CV_32FC3);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2);
  cv::Mat e;
  cv::exp((noise - 0.5) * 20, e);  // several decades of radiance, like a scene
  return e;
}

TEST(Align, RecoversAKnownShiftAcrossExposures) {
  const cv::Mat e = TexturedRadiance(640, 480);
  const std::vector<double> t = BracketTimes(e, 3, 2);
  std::vector<cv::Mat> f = SimulateBracket(e, t, CameraModel{});
  // The short frame was taken with the camera moved: content 7 px right, 4 up.
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 7, 0, 1, -4);
  cv::warpAffine(f[0], f[0], M, f[0].size(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  const AlignedBracket a = AlignBracket(f, 16);
  EXPECT_EQ(a.reference, 1);
  EXPECT_EQ(a.shifts[0], cv::Point(-7, 4));
  EXPECT_EQ(a.shifts[1], cv::Point(0, 0));
  EXPECT_LE(std::abs(a.shifts[2].x) + std::abs(a.shifts[2].y), 1);
  EXPECT_THROW(AlignBracket({f[0]}), Error);
}

}  // namespace
}  // namespace brdfshot
