#include "capture/response_plot.h"

#include <gtest/gtest.h>

namespace brdfshot {

// The curve is drawn over the codes the frames contain and nowhere else: a
// frame whose red codes run 100…149 (each on 40 pixels) and whose green holds
// one code on only 5 pixels (below the 10-pixel floor) plots red at exactly
// those codes, green not at all; blue's one code covers the rest of the frame.
TEST(ResponsePlot, SeriesCoverOnlyTheCodesTheFramesContain) {
  cv::Mat frame(40, 50, CV_8UC3, cv::Scalar(0, 0, 200));
  for (int y = 0; y < frame.rows; ++y)
    for (int x = 0; x < frame.cols; ++x) frame.at<cv::Vec3b>(y, x)[0] = static_cast<uint8_t>(100 + x);
  for (int x = 0; x < 5; ++x) frame.at<cv::Vec3b>(0, x)[1] = 77;
  ResponseCurve linear;  // code / 255
  const std::vector<XYSeries> s = ResponseSeries(linear, {frame});
  ASSERT_EQ(s.size(), 3u);
  ASSERT_EQ(s[0].x.size(), 50u);
  for (size_t k = 0; k < s[0].x.size(); ++k) {
    EXPECT_EQ(s[0].x[k], 100 + static_cast<int>(k));
    EXPECT_DOUBLE_EQ(s[0].y[k], s[0].x[k] / 255.0);
  }
  EXPECT_TRUE(s[1].x.empty()) << "code 0 is never drawn and code 77 is too rare";
  ASSERT_EQ(s[2].x.size(), 1u);
  EXPECT_EQ(s[2].x[0], 200);
  const cv::Mat plot = ResponsePlot(linear, {frame});
  EXPECT_EQ(plot.type(), CV_8UC3);
  EXPECT_GT(plot.total(), 0u);
}

}  // namespace brdfshot
