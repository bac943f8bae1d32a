// Translation alignment of a hand-held bracket. Exposure changes every
// intensity, so frames are compared through median-threshold bitmaps (Ward's
// MTB, as OpenCV's AlignMTB implements it), which an exposure change leaves
// nearly unchanged.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace brdfshot {

struct AlignedBracket {
  std::vector<cv::Mat> frames;    // shifted onto the reference frame
  std::vector<cv::Point> shifts;  // what was applied to each frame (reference: 0, 0)
  int reference = 0;              // the middle frame by exposure order given
};

// `frames`: 8- or 16-bit RGB, same size. `max_shift_px` bounds the search
// (MTB's pyramid depth is chosen from it). Borders uncovered by a shift are
// filled with the nearest edge pixel so they do not read as black.
AlignedBracket AlignBracket(const std::vector<cv::Mat>& frames, int max_shift_px = 64);

}  // namespace brdfshot
