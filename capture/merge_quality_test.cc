#include "capture/merge_quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace brdfshot {
namespace {

// A smooth scene of varied colour, radiance 0.02 … 1.
cv::Mat Scene(cv::Size size) {
  cv::Mat e(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double u = double(x) / size.width, v = double(y) / size.height;
      e.at<cv::Vec3f>(y, x) = cv::Vec3f(0.02 + 0.9 * u * u, 0.03 + 0.6 * v, 0.05 + 0.5 * u * v);
    }
  return e;
}

// A linear 8-bit camera (code = 255 · min(1, E·t)), exact but for rounding.
std::vector<cv::Mat> Bracket(const cv::Mat& e, const std::vector<double>& times) {
  std::vector<cv::Mat> frames;
  for (double t : times) {
    cv::Mat f;
    cv::Mat(e * (255 * t)).convertTo(f, CV_8UC3);
    frames.push_back(f);
  }
  return frames;
}

// Our merge with its defaults, as a BracketMerger.
const BracketMerger kOurs = [](const std::vector<cv::Mat>& f, const std::vector<double>& t) { return OurMerge(f, t); };

}  // namespace

// A grey image has no speckle; one in which every 25th dark pixel is pure red
// has 4 % — the closed form, since the 5 × 5 median ignores isolated pixels.
TEST(ChromaSpeckle, CountsIsolatedHuesAmongTheDarkestPixels) {
  cv::Mat img(100, 100, CV_32FC3);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) img.at<cv::Vec3f>(y, x) = cv::Vec3f::all(y < 20 ? 0.01f : 1.0f);
  EXPECT_EQ(ChromaSpeckle(img), 0);
  long dark = 0, red = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < img.cols; ++x, ++dark)
      if (dark % 25 == 12) {  // single-pixel columns away from the border: 1 in 5 of a window
        const float v = img.at<cv::Vec3f>(y, x)[0];
        img.at<cv::Vec3f>(y, x) = cv::Vec3f(v, 0, 0);  // darker than the grey (luminance 0.21 v): still dark
        ++red;
      }
  EXPECT_NEAR(ChromaSpeckle(img), double(red) / dark, 1e-12);
}

// A clean bracket predicts every left-out frame to within a code; the same
// bracket with one frame shifted by 3 px (misregistration) does not.
TEST(LeaveOneFrameOut, ACleanBracketPredictsEachFrameAndAShiftedFrameShows) {
  const std::vector<double> times = {0.25, 0.5, 1, 2, 4};
  std::vector<cv::Mat> frames = Bracket(Scene({160, 120}), times);
  const std::vector<LeftOutFrame> clean = LeaveOneFrameOut(frames, times, kOurs);
  ASSERT_EQ(clean.size(), 3u) << "all but the shortest and the longest";
  for (const LeftOutFrame& f : clean) {
    EXPECT_GT(f.pixels, 1000);
    for (int c = 0; c < 3; ++c) EXPECT_LE(f.code_error[c], 1.0) << "frame " << f.frame << " channel " << c;
    EXPECT_LT(f.chroma_error, 0.01) << "frame " << f.frame;
  }
  cv::Mat shifted;
  cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, 3, 0, 1, 0);
  cv::warpAffine(frames[2], shifted, m, frames[2].size(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  frames[2] = shifted;
  const std::vector<LeftOutFrame> moved = LeaveOneFrameOut(frames, times, kOurs);
  const auto& f2 = *std::find_if(moved.begin(), moved.end(), [](const LeftOutFrame& f) { return f.frame == 2; });
  EXPECT_GT(f2.code_error[0], 2 * std::max(1.0, clean[1].code_error[0]));
  EXPECT_THROW(LeaveOneFrameOut({frames[0], frames[1]}, {0.25, 0.5}, kOurs), Error);
}

}  // namespace brdfshot
