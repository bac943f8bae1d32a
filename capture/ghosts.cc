#include "capture/ghosts.h"

#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace brdfshot {

std::vector<cv::Mat> DetectGhosts(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                                  const ResponseCurve& response, int reference, const NoiseModel& noise,
                                  const GhostOptions& o) {
  BRDFSHOT_CHECK(!frames.empty() && frames.size() == times.size() && reference >= 0 &&
                 reference < static_cast<int>(frames.size()));
  const int levels = response.levels;
  // Codes that measure: clear of black and of clipping by 5 % of the range.
  const int zlo = static_cast<int>(0.05 * (levels - 1)), zhi = static_cast<int>(0.95 * (levels - 1));
  std::array<std::vector<double>, 3> lin;
  std::array<double, 3> sat{};
  for (int c = 0; c < 3; ++c) {
    for (int z = 0; z < levels; ++z) lin[c].push_back(response.Linear(c, z));
    sat[c] = std::max(1e-30, lin[c][zhi]);
  }
  // Variance of the estimate lin(z)/t under the noise model (as the merge's weights).
  auto variance = [&](int c, int z, double t) {
    const double x = lin[c][z] / sat[c];
    return (noise.shot * x + noise.read) * sat[c] * sat[c] / (t * t);
  };
  const cv::Mat& ref = frames[reference];
  const double tr = times[reference];
  std::vector<cv::Mat> ghosts(frames.size());
  const cv::Mat grow = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * o.grow_px + 1, 2 * o.grow_px + 1));
  for (size_t j = 0; j < frames.size(); ++j) {
    cv::Mat g = cv::Mat::zeros(ref.size(), CV_8U);
    if (static_cast<int>(j) != reference) {
      const cv::Mat& f = frames[j];
      const double tj = times[j];
#pragma omp parallel for schedule(static)
      for (int y = 0; y < ref.rows; ++y)
        for (int x = 0; x < ref.cols; ++x)
          for (int c = 0; c < 3; ++c) {
            const int zr = FrameCode(ref, y, x, c), zj = FrameCode(f, y, x, c);
            if (zr <= zlo || zr >= zhi || zj <= zlo || zj >= zhi) continue;
            const double er = lin[c][zr] / tr, ej = lin[c][zj] / tj;
            const double d = std::abs(ej - er);
            if (d > o.sigmas * std::sqrt(variance(c, zr, tr) + variance(c, zj, tj)) && d > o.min_relative * er) {
              g.at<uint8_t>(y, x) = 255;
              break;
            }
          }
      // Isolated disagreements are noise's tail, not a moving thing: opened
      // away; what stays is grown over the thing's soft edges.
      cv::morphologyEx(g, g, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
      if (o.grow_px > 0) cv::dilate(g, g, grow);
    }
    ghosts[j] = g;
  }
  return ghosts;
}

cv::Mat GhostUnion(const std::vector<cv::Mat>& ghosts) {
  cv::Mat u = cv::Mat::zeros(ghosts.at(0).size(), CV_8U);
  for (const cv::Mat& g : ghosts) u |= g;
  return u;
}

}  // namespace brdfshot
