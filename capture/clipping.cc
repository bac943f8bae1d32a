#include "capture/clipping.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace brdfshot {
namespace {

// Two channels or more at the clip code: a highlight near white, whose third
// channel JPEG may have lowered. One channel alone is a saturated colour (a
// red ball's red): its other channels are sound measurements, and dropping
// them left a red plastic's green and blue to the short frames' dark codes
// (relit error 4.3 → 6.4 % in samples_test's rotated capture).
bool ClippedHighlight(const cv::Vec3b& p, int clipped_code) {
  return (p[0] >= clipped_code) + (p[1] >= clipped_code) + (p[2] >= clipped_code) >= 2;
}

}  // namespace

std::vector<cv::Mat> ClippedNearby(const std::vector<cv::Mat>& frames, int clipped_code, int reach) {
  std::vector<cv::Mat> out;
  if (frames.empty() || frames[0].type() != CV_8UC3 || reach < 0) return out;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * reach + 1, 2 * reach + 1));
  for (const cv::Mat& f : frames) {
    BRDFSHOT_CHECK(f.type() == CV_8UC3, "frames of one bracket share a type");
    cv::Mat mask(f.size(), CV_8U);
    for (int y = 0; y < f.rows; ++y) {
      const cv::Vec3b* p = f.ptr<cv::Vec3b>(y);
      uint8_t* m = mask.ptr<uint8_t>(y);
      for (int x = 0; x < f.cols; ++x) m[x] = ClippedHighlight(p[x], clipped_code) ? 255 : 0;
    }
    if (reach > 0) cv::dilate(mask, mask, kernel);
    out.push_back(mask);
  }
  return out;
}

bool IsClippedNearby(const cv::Mat& frame, int x, int y, int clipped_code, int reach) {
  if (reach < 0 || frame.type() != CV_8UC3) return false;
  for (int v = std::max(0, y - reach); v <= std::min(frame.rows - 1, y + reach); ++v) {
    const cv::Vec3b* p = frame.ptr<cv::Vec3b>(v);
    for (int u = std::max(0, x - reach); u <= std::min(frame.cols - 1, x + reach); ++u)
      if (ClippedHighlight(p[u], clipped_code)) return true;
  }
  return false;
}

}  // namespace brdfshot
