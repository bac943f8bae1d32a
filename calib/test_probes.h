// Test helpers shared by calib's tests (not part of the library).
#pragma once

#include <cmath>
#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"

namespace brdfshot {

// A smooth probe with a known closed form per direction: the round trips are
// measured against it, not against our own resampling.
inline LatLongProbe SmoothProbe(int width) {
  LatLongProbe frame(cv::Mat(width / 2, width, CV_32FC3, cv::Scalar::all(0)));
  cv::Mat m(width / 2, width, CV_32FC3);
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) {
      const Vec3 d = frame.DirectionAt(c + 0.5, r + 0.5);
      m.at<cv::Vec3f>(r, c) = cv::Vec3f(1.5 + d.x, 1.5 + d.y, 1.5 + d.z * d.x);
    }
  return LatLongProbe(m);
}

// Relative RMSE of `a` against `b` (CV_32FC3) over the nonzero texels of `mask`
// (all when empty).
inline double RelRmse(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = cv::Mat()) {
  double se = 0, ref = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      if (!mask.empty() && !mask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f d = a.at<cv::Vec3f>(y, x) - b.at<cv::Vec3f>(y, x), t = b.at<cv::Vec3f>(y, x);
      se += d.dot(d), ref += t.dot(t);
    }
  return std::sqrt(se / ref);
}

}  // namespace brdfshot
