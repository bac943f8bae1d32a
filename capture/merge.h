// Merging a bracket into linear radiance (relative units: value / exposure).
//
// Weights: hat(z) · t — the hat falls to exactly zero at the clipping and
// near-black codes (OpenCV's MergeDebevec weights 0 and 255 with 1, so a
// clipped window leaks its clip level into the result), and the factor t
// favours the longer, less noisy exposure where both are valid. A pixel no
// frame measured well is flagged in the mask and gets the bound its frames
// imply (clipped even in the shortest: ≥ clip/t_min; dark even in the longest).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "capture/response.h"

namespace brdfshot {

struct MergeOptions {
  double low = 0.02;   // fraction of the code range below which a code is near-black
  double high = 0.98;  // ...above which it is clipped
};

struct MergeResult {
  cv::Mat radiance;  // CV_32FC3, RGB
  cv::Mat mask;      // CV_8U, 255 where no frame measured some channel well
  double unreliable_fraction = 0;
};

// `frames`: RGB, all CV_8UC3 or all CV_16UC3, same size; `times` relative
// exposures. Error naming the problem on a size or type mismatch.
MergeResult MergeBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt = {});

}  // namespace brdfshot
