#include "capture/clipping.h"

#include <gtest/gtest.h>

namespace brdfshot {
namespace {

TEST(ClippedNearby, TwoClippedChannelsMarkTheirSquareOfReach) {
  cv::Mat f(9, 9, CV_8UC3, cv::Scalar::all(120));
  f.at<cv::Vec3b>(4, 4) = {250, 250, 120};  // a highlight near white
  const std::vector<cv::Mat> m = ClippedNearby({f}, 249, 2);
  ASSERT_EQ(m.size(), 1u);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 9; ++x)
      EXPECT_EQ(m[0].at<uint8_t>(y, x), std::max(std::abs(x - 4), std::abs(y - 4)) <= 2 ? 255 : 0) << x << "," << y;
  // Below the clip code nothing is marked, nor is one clipped channel (a
  // saturated colour); reach 0 marks the pixel alone.
  f.at<cv::Vec3b>(4, 4) = {248, 248, 248};
  EXPECT_EQ(cv::countNonZero(ClippedNearby({f}, 249, 2)[0]), 0);
  f.at<cv::Vec3b>(4, 4) = {255, 0, 0};
  EXPECT_EQ(cv::countNonZero(ClippedNearby({f}, 249, 2)[0]), 0);
  f.at<cv::Vec3b>(4, 4) = {255, 0, 255};
  EXPECT_EQ(cv::countNonZero(ClippedNearby({f}, 249, 0)[0]), 1);
  // The point query agrees with the masks; reach < 0 marks nothing.
  f.at<cv::Vec3b>(4, 4) = {120, 250, 250};
  const cv::Mat mask = ClippedNearby({f}, 249, 2)[0];
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 9; ++x) EXPECT_EQ(IsClippedNearby(f, x, y, 249, 2), mask.at<uint8_t>(y, x) != 0);
  EXPECT_TRUE(ClippedNearby({f}, 249, -1).empty());
  EXPECT_FALSE(IsClippedNearby(f, 4, 4, 249, -1));
}

TEST(ClippedNearby, SixteenBitFramesHaveNoMasks) {
  const cv::Mat f(4, 4, CV_16UC3, cv::Scalar::all(65535));
  EXPECT_TRUE(ClippedNearby({f, f}, 249, 2).empty());
}

}  // namespace
}  // namespace brdfshot
