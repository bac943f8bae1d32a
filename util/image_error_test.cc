#include "util/image_error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace brdfshot {
namespace {

TEST(CompareLinearImages, ClosedFormsOnTwoPixelsAndBlackBackground) {
  // Reference: one lit pixel (1,2,2) (‖·‖ = 3) and one black background pixel.
  cv::Mat ref(1, 2, CV_32FC3, cv::Scalar::all(0)), test(1, 2, CV_32FC3, cv::Scalar::all(0));
  ref.at<cv::Vec3f>(0, 0) = {1, 2, 2};
  test.at<cv::Vec3f>(0, 0) = {2, 4, 4};  // twice the reference
  test.at<cv::Vec3f>(0, 1) = {9, 9, 9};  // over background: not scored
  const ImageError plain = CompareLinearImages(ref, test);
  EXPECT_EQ(plain.pixels, 1u);
  EXPECT_DOUBLE_EQ(plain.scale, 1.0);
  EXPECT_NEAR(plain.relative_rmse, 1.0, 1e-12);  // ‖ref − 2 ref‖ / ‖ref‖
  const ImageError fitted = CompareLinearImages(ref, test, true);
  EXPECT_NEAR(fitted.scale, 0.5, 1e-12);
  EXPECT_NEAR(fitted.relative_rmse, 0.0, 1e-7);
  // An all-black reference has nothing to score.
  const ImageError none = CompareLinearImages(cv::Mat(1, 2, CV_32FC3, cv::Scalar::all(0)), test);
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_TRUE(std::isnan(none.relative_rmse));
}

}  // namespace
}  // namespace brdfshot
