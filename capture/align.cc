#include "capture/align.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "util/check.h"

namespace brdfshot {

namespace {
cv::Mat Gray8(const cv::Mat& rgb) {
  cv::Mat g;
  cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
  if (g.depth() == CV_16U) g.convertTo(g, CV_8U, 1.0 / 257);
  return g;
}
}  // namespace

AlignedBracket AlignBracket(const std::vector<cv::Mat>& frames, int max_shift_px) {
  if (frames.size() < 2) throw Error("alignment needs at least two frames");
  AlignedBracket out;
  out.reference = static_cast<int>(frames.size() / 2);
  // MTB searches ±1 px per pyramid level, doubling per level: 2^levels ≥ max shift.
  const int levels = std::max(1, static_cast<int>(std::ceil(std::log2(std::max(2, max_shift_px)))));
  cv::Ptr<cv::AlignMTB> mtb = cv::createAlignMTB(levels);
  const cv::Mat ref = Gray8(frames[out.reference]);
  for (size_t j = 0; j < frames.size(); ++j) {
    if (frames[j].size() != frames[0].size())
      throw Error("frame " + std::to_string(j) + " differs in size from frame 0");
    const cv::Point s =
        static_cast<int>(j) == out.reference ? cv::Point(0, 0) : mtb->calculateShift(ref, Gray8(frames[j]));
    out.shifts.push_back(s);
    const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, s.x, 0, 1, s.y);
    cv::Mat shifted;
    cv::warpAffine(frames[j], shifted, M, frames[j].size(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
    out.frames.push_back(shifted);
  }
  return out;
}

}  // namespace brdfshot
