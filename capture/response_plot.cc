#include "capture/response_plot.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace brdfshot {

std::vector<XYSeries> ResponseSeries(const ResponseCurve& r, const std::vector<cv::Mat>& frames) {
  // A grid of ~250 000 pixels per frame: the plot needs no more, and a 12 MP
  // bracket would otherwise cost half a merge.
  std::vector<std::array<long, 3>> count(r.levels, {0, 0, 0});
  const int step = std::max(1, static_cast<int>(std::sqrt(frames[0].total() / 250000.0)));
  long counted = 0;
  for (const cv::Mat& f : frames)
    for (int y = 0; y < f.rows; y += step)
      for (int x = 0; x < f.cols; x += step, ++counted)
        for (int c = 0; c < 3; ++c) ++count[f.at<cv::Vec3b>(y, x)[c]][c];
  const long min_count = std::max<long>(10, counted / 100000);
  std::vector<XYSeries> series;
  const char* names[3] = {"R", "G", "B"};
  const cv::Scalar bgr[3] = {{40, 40, 220}, {40, 160, 40}, {220, 80, 40}};
  for (int c = 0; c < 3; ++c) {
    XYSeries s{names[c], {}, {}, bgr[c]};
    for (int z = 1; z + 1 < r.levels; ++z)
      if (count[z][c] >= min_count) s.x.push_back(z), s.y.push_back(r.Linear(c, z));
    series.push_back(s);
  }
  return series;
}

cv::Mat ResponsePlot(const ResponseCurve& r, const std::vector<cv::Mat>& frames) {
  return LogLogPlot(ResponseSeries(r, frames), "response curve (" + r.kind + "), codes seen in the frames",
                    "pixel code", "relative exposure");
}

}  // namespace brdfshot
