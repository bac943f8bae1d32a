#include "fit/photo_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "util/check.h"

namespace brdfshot {

namespace {
// Immerkær's σ of `y` pooled over RGB (the variance averaged over the
// channels); kUnknownNoise without a full 3 × 3 neighbourhood.
double PooledNoiseSigma(const PixelGeometry& g, const Eigen::MatrixXd& y) {
  BRDFSHOT_CHECK(static_cast<size_t>(y.rows()) == g.size() && y.cols() == 3);
  if (g.size() == 0) return kUnknownNoise;
  // Pixel index by position, on the bounding box of the pixels.
  const auto [x0, x1] = std::minmax_element(g.x.begin(), g.x.end());
  const auto [y0, y1] = std::minmax_element(g.y.begin(), g.y.end());
  const int w = *x1 - *x0 + 1, h = *y1 - *y0 + 1;
  std::vector<int> at(static_cast<size_t>(w) * h, -1);
  for (size_t i = 0; i < g.size(); ++i)
    at[static_cast<size_t>(g.y[i] - *y0) * w + (g.x[i] - *x0)] = static_cast<int>(i);
  // The kernel's response at every pixel whose 8 neighbours are all there,
  // per channel, in one pass over the bounding box, its rows spread over the
  // threads. The responses' order does not matter: only their median is
  // read.
  std::array<std::vector<double>, 3> response;
  for (auto& r : response) r.reserve(g.size());
  const Eigen::MatrixXd yt = y.transpose();  // a pixel's RGB contiguous
  const double* v = yt.data();
#pragma omp parallel
  {
    std::array<std::vector<double>, 3> local;
#pragma omp for schedule(static) nowait
    for (int py = 1; py < h - 1; ++py) {
      const int* above = &at[static_cast<size_t>(py - 1) * w];
      const int* here = above + w;
      const int* below = here + w;
      for (int px = 1; px + 1 < w; ++px) {
        const int n[9] = {above[px - 1], above[px],     above[px + 1], here[px - 1], here[px],
                          here[px + 1],  below[px - 1], below[px],     below[px + 1]};
        if (std::min({n[0], n[1], n[2], n[3], n[4], n[5], n[6], n[7], n[8]}) < 0) continue;
        for (int c = 0; c < 3; ++c) {
          const auto p = [&](int k) { return v[3 * static_cast<size_t>(n[k]) + c]; };
          // [1 −2 1] ⊗ [1 −2 1]
          const double s = (p(0) + p(2) + p(6) + p(8)) - 2 * (p(1) + p(3) + p(5) + p(7)) + 4 * p(4);
          local[c].push_back(std::abs(s));
        }
      }
    }
#pragma omp critical
    for (int c = 0; c < 3; ++c) response[c].insert(response[c].end(), local[c].begin(), local[c].end());
  }
  if (response[0].empty()) return kUnknownNoise;
  std::array<double, 3> sigma{};
#pragma omp parallel for schedule(static, 1)
  for (int c = 0; c < 3; ++c) {
    std::vector<double>& r = response[c];
    const auto mid = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2);
    std::nth_element(r.begin(), mid, r.end());
    // median |N(0, 36σ²)| = 0.6745 · 6σ
    sigma[c] = *mid / (6.0 * 0.674489750196);
  }
  const double variance = sigma[0] * sigma[0] + sigma[1] * sigma[1] + sigma[2] * sigma[2];  // summed over channels
  return std::sqrt(variance / 3.0);
}

double RelativeTo(double sigma, const Eigen::MatrixXd& y) {
  const double mean_square = y.squaredNorm() / static_cast<double>(y.size());
  if (!(sigma >= 0) || !(mean_square > 0)) return kUnknownNoise;
  return sigma / std::sqrt(mean_square);
}
}  // namespace

double RelativePixelNoise(const PixelGeometry& g, const Eigen::MatrixXd& y) {
  return RelativeTo(PooledNoiseSigma(g, y), y);
}

double ResidualPixelNoise(const PixelGeometry& g, const Eigen::MatrixXd& y, const Eigen::MatrixXd& fitted) {
  BRDFSHOT_CHECK(fitted.rows() == y.rows() && fitted.cols() == y.cols());
  return RelativeTo(PooledNoiseSigma(g, y - fitted), y);
}

double ConditionBoundForNoise(double relative_noise, const NoiseBoundOptions& opt) {
  BRDFSHOT_CHECK(opt.min_bound >= 1 && opt.max_bound >= opt.min_bound && opt.margin > 0);
  if (!(relative_noise >= 0)) return opt.min_bound;
  if (relative_noise == 0) return opt.max_bound;
  const double r = opt.margin / relative_noise;
  return std::clamp(r * r, opt.min_bound, opt.max_bound);
}

}  // namespace brdfshot
