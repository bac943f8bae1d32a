// How far a linear image is from a reference: the error `compare` prints and
// the report's relit-vs-truth numbers, computed one way.
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>

namespace brdfshot {

struct ImageError {
  double relative_rmse = 0;  // ‖ref − s·test‖ / ‖ref‖ over the pixels below
  double scale = 1;          // s: 1, or the least-squares Σpq / Σq² when fitted
  size_t pixels = 0;         // reference pixels with any light (black ones are background)
};

// Both CV_32FC3 of one size (checked). Sums in double. `fit_scale`: score
// `test` after the scale that fits it best (an HDR merge is known only up to
// one). With no lit reference pixel, pixels = 0 and relative_rmse = NaN.
ImageError CompareLinearImages(const cv::Mat& reference, const cv::Mat& test, bool fit_scale = false);

}  // namespace brdfshot
