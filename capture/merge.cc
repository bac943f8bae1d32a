#include "capture/merge.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {

MergeResult MergeBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt) {
  if (frames.size() < 2) throw Error("a bracket needs at least two frames, got " + std::to_string(frames.size()));
  if (times.size() != frames.size())
    throw Error(std::to_string(frames.size()) + " frames but " + std::to_string(times.size()) + " exposure times");
  const int type = frames[0].type();
  if (type != CV_8UC3 && type != CV_16UC3) throw Error("frames must be 8- or 16-bit RGB");
  for (size_t j = 0; j < frames.size(); ++j) {
    if (frames[j].size() != frames[0].size())
      throw Error("frame " + std::to_string(j) + " is " + std::to_string(frames[j].cols) + "x" +
                  std::to_string(frames[j].rows) + ", frame 0 is " + std::to_string(frames[0].cols) + "x" +
                  std::to_string(frames[0].rows));
    if (frames[j].type() != type) throw Error("frame " + std::to_string(j) + " has another bit depth than frame 0");
    if (!(times[j] > 0)) throw Error("exposure of frame " + std::to_string(j) + " is not positive");
  }
  const int levels = type == CV_8UC3 ? 256 : 65536;
  if (response.levels != levels)
    throw Error("response curve has " + std::to_string(response.levels) + " codes, frames have " + std::to_string(levels));
  const int zlo = static_cast<int>(std::ceil(opt.low * (levels - 1)));
  const int zhi = static_cast<int>(std::floor(opt.high * (levels - 1)));
  // Per-code tables: linear value and hat weight (0 outside (zlo, zhi)).
  std::array<std::vector<float>, 3> lin;
  std::vector<float> hat(levels);
  const double mid = 0.5 * (zlo + zhi);
  for (int z = 0; z < levels; ++z)
    hat[z] = z <= zlo || z >= zhi ? 0.0f : static_cast<float>(1 - std::abs(z - mid) / (mid - zlo));
  for (int c = 0; c < 3; ++c) {
    lin[c].resize(levels);
    for (int z = 0; z < levels; ++z) lin[c][z] = static_cast<float>(response.Linear(c, z));
  }
  const int N = static_cast<int>(frames.size());
  std::vector<int> order(N);
  for (int j = 0; j < N; ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  const int shortest = order.front(), longest = order.back();

  MergeResult out;
  out.radiance.create(frames[0].size(), CV_32FC3);
  out.mask = cv::Mat::zeros(frames[0].size(), CV_8U);
  const int rows = frames[0].rows, cols = frames[0].cols;
  auto code = [type, &frames](int j, int y, int x, int c) -> int {
    return type == CV_8UC3 ? frames[j].ptr<cv::Vec3b>(y)[x][c] : frames[j].ptr<cv::Vec3w>(y)[x][c];
  };
  long unreliable = 0;
#pragma omp parallel for schedule(static) reduction(+ : unreliable)
  for (int y = 0; y < rows; ++y) {
    cv::Vec3f* dst = out.radiance.ptr<cv::Vec3f>(y);
    uint8_t* m = out.mask.ptr<uint8_t>(y);
    for (int x = 0; x < cols; ++x) {
      bool bad = false;
      for (int c = 0; c < 3; ++c) {
        double num = 0, den = 0;
        for (int j = 0; j < N; ++j) {
          const int z = code(j, y, x, c);
          const double w = hat[z] * times[j];
          num += w * lin[c][z] / times[j];
          den += w;
        }
        if (den > 0) {
          dst[x][c] = static_cast<float>(num / den);
          continue;
        }
        bad = true;
        const int zs = code(shortest, y, x, c), zl = code(longest, y, x, c);
        dst[x][c] = zs >= zhi ? lin[c][zs] / static_cast<float>(times[shortest])
                              : lin[c][zl] / static_cast<float>(times[longest]);
      }
      if (bad) m[x] = 255, ++unreliable;
    }
  }
  out.unreliable_fraction = static_cast<double>(unreliable) / (static_cast<double>(rows) * cols);
  return out;
}

}  // namespace brdfshot
