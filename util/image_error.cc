#include "util/image_error.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {

ImageError CompareLinearImages(const cv::Mat& ra, const cv::Mat& rb, bool fit_scale) {
  BRDFSHOT_CHECK(ra.type() == CV_32FC3 && rb.type() == CV_32FC3 && ra.size() == rb.size(),
                 "CompareLinearImages wants two CV_32FC3 images of one size");
  // Σ p², Σ pq, Σ q² in double: the scale s = Σpq / Σq² and the error
  // Σ (p − s q)² = Σp² − 2 s Σpq + s² Σq² follow from them.
  double pp = 0, pq = 0, qq = 0;
  ImageError e;
  for (int y = 0; y < ra.rows; ++y)
    for (int x = 0; x < ra.cols; ++x) {
      const cv::Vec3f p = ra.at<cv::Vec3f>(y, x), q = rb.at<cv::Vec3f>(y, x);
      if (p[0] + p[1] + p[2] <= 0) continue;  // background
      for (int c = 0; c < 3; ++c) pp += double(p[c]) * p[c], pq += double(p[c]) * q[c], qq += double(q[c]) * q[c];
      ++e.pixels;
    }
  if (e.pixels == 0 || pp <= 0) {
    e.pixels = 0;
    e.relative_rmse = NAN;
    return e;
  }
  e.scale = fit_scale ? (qq > 0 ? pq / qq : 0) : 1.0;
  e.relative_rmse = std::sqrt(std::max(0.0, pp - 2 * e.scale * pq + e.scale * e.scale * qq) / pp);
  return e;
}

}  // namespace brdfshot
