#include "capture/ghosts.h"

#include <algorithm>
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
  // Frames by their distance from the reference in exposure order: where
  // the reference is clipped (or black), the nearest frame that measures the
  // pixel stands in for it — only shorter (or longer) frames can.
  const int n = static_cast<int>(frames.size());
  std::vector<int> by_exposure(n);
  for (int j = 0; j < n; ++j) by_exposure[j] = j;
  std::stable_sort(by_exposure.begin(), by_exposure.end(), [&](int a, int b) { return times[a] < times[b]; });
  const int rank = static_cast<int>(std::find(by_exposure.begin(), by_exposure.end(), reference) - by_exposure.begin());
  std::vector<int> stand_ins = {reference};
  for (int d = 1; d < n; ++d)
    for (int r : {rank - d, rank + d})
      if (r >= 0 && r < n) stand_ins.push_back(by_exposure[r]);
  auto measures = [&](int j, int y, int x) {
    for (int c = 0; c < 3; ++c) {
      const int z = FrameCode(frames[j], y, x, c);
      if (z <= zlo || z >= zhi) return false;
    }
    return true;
  };
  const cv::Size size = frames[reference].size();
  std::vector<cv::Mat> ghosts(frames.size());
  for (cv::Mat& g : ghosts) g = cv::Mat::zeros(size, CV_8U);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      int r = -1;
      for (int j : stand_ins)
        if (measures(j, y, x)) {
          r = j;
          break;
        }
      if (r < 0) continue;  // no frame measures every channel here
      const double tr = times[r];
      for (int j = 0; j < n; ++j) {
        if (j == r) continue;
        const double tj = times[j];
        for (int c = 0; c < 3; ++c) {
          const int zr = FrameCode(frames[r], y, x, c), zj = FrameCode(frames[j], y, x, c);
          if (zj <= zlo || zj >= zhi) continue;
          const double er = lin[c][zr] / tr, ej = lin[c][zj] / tj;
          const double d = std::abs(ej - er);
          if (d > o.sigmas * std::sqrt(variance(c, zr, tr) + variance(c, zj, tj)) && d > o.min_relative * er) {
            ghosts[j].at<uint8_t>(y, x) = 255;
            break;
          }
        }
      }
    }
  const cv::Mat grow = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * o.grow_px + 1, 2 * o.grow_px + 1));
  for (cv::Mat& g : ghosts) {
    // Isolated disagreements are noise's tail, not a moving thing: opened
    // away; what stays is grown over the thing's soft edges.
    cv::morphologyEx(g, g, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    if (o.grow_px > 0) cv::dilate(g, g, grow);
  }
  return ghosts;
}

cv::Mat GhostUnion(const std::vector<cv::Mat>& ghosts) {
  cv::Mat u = cv::Mat::zeros(ghosts.at(0).size(), CV_8U);
  for (const cv::Mat& g : ghosts) u |= g;
  return u;
}

}  // namespace brdfshot
