#include "capture/synthetic_bracket.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "util/check.h"

namespace brdfshot {

double CameraModel::Response(double x) const {
  x = std::clamp(x, 0.0, 1.0);
  const double rolled = x * (1 + shoulder) / (x + shoulder);
  return std::pow(rolled, 1 / gamma);
}

std::vector<cv::Mat> SimulateBracket(const cv::Mat& radiance, const std::vector<double>& times,
                                     const CameraModel& cam) {
  BRDFSHOT_CHECK(radiance.type() == CV_32FC3, "SimulateBracket wants CV_32FC3 radiance");
  const bool raw = cam.raw_bits > 0;
  BRDFSHOT_CHECK(!raw || (cam.raw_bits >= 8 && cam.raw_bits <= 16), "raw_bits must be 8..16");
  // Response as a table over 4096 signal steps: the pow per sample would dominate.
  std::vector<uint8_t> ldr_code(4097);
  for (int i = 0; i <= 4096; ++i) ldr_code[i] = static_cast<uint8_t>(std::lround(255 * cam.Response(i / 4096.0)));
  const double raw_max = raw ? std::ldexp(1.0, cam.raw_bits) - 1 : 0;
  const int raw_shift = raw ? 16 - cam.raw_bits : 0;
  std::vector<cv::Mat> frames;
  for (size_t j = 0; j < times.size(); ++j) {
    cv::Mat f(radiance.size(), raw ? CV_16UC3 : CV_8UC3);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < radiance.rows; ++y) {
      // One generator per row and frame: deterministic whatever the thread count.
      std::mt19937_64 rng(cam.seed * 1000003ull + j * 7919ull + static_cast<uint64_t>(y));
      std::normal_distribution<float> normal(0.0f, 1.0f);
      const cv::Vec3f* e = radiance.ptr<cv::Vec3f>(y);
      for (int x = 0; x < radiance.cols; ++x)
        for (int c = 0; c < 3; ++c) {
          const double electrons = std::max(0.0f, e[x][c]) * times[j] * cam.full_well;
          const double sigma = std::sqrt(electrons + cam.read_noise * cam.read_noise);
          const double s = std::clamp((electrons + sigma * normal(rng)) / cam.full_well, 0.0, 1.0);
          if (raw) {
            f.ptr<cv::Vec3w>(y)[x][c] = static_cast<uint16_t>(std::lround(s * raw_max)) << raw_shift;
          } else {
            // Linear between table steps, then rounding to the code (8-bit quantisation).
            const double u = s * 4096;
            const int i = std::min(4095, static_cast<int>(u));
            const double t = u - i;
            const double code = (1 - t) * ldr_code[i] + t * ldr_code[i + 1];
            f.ptr<cv::Vec3b>(y)[x][c] = static_cast<uint8_t>(std::lround(code));
          }
        }
    }
    frames.push_back(f);
  }
  return frames;
}

std::vector<double> BracketTimes(const cv::Mat& radiance, int frames, double stops) {
  BRDFSHOT_CHECK(frames >= 1 && stops > 0);
  cv::Mat flat = radiance.reshape(1, static_cast<int>(radiance.total()));
  std::vector<float> g;
  g.reserve(radiance.total());
  for (int i = 0; i < flat.rows; ++i) {
    const float* p = flat.ptr<float>(i);
    g.push_back((p[0] + p[1] + p[2]) / 3);
  }
  std::nth_element(g.begin(), g.begin() + g.size() / 2, g.end());
  const double median = std::max(1e-12, static_cast<double>(g[g.size() / 2]));
  const double t_mid = 0.18 / median;
  std::vector<double> t;
  for (int k = 0; k < frames; ++k) t.push_back(t_mid * std::exp2(stops * (k - (frames - 1) / 2.0)));
  return t;
}

std::vector<double> CoveringBracketTimes(const cv::Mat& radiance, double stops, int max_frames, double max_signal,
                                         double dark_quantile, double dark_signal) {
  BRDFSHOT_CHECK(radiance.type() == CV_32FC3 && !radiance.empty(), "CoveringBracketTimes wants CV_32FC3");
  BRDFSHOT_CHECK(stops > 0 && max_frames >= 1 && max_signal > 0 && dark_signal > 0);
  double peak = 0;
  cv::minMaxLoc(radiance.reshape(1), nullptr, &peak);
  std::vector<float> lum;
  lum.reserve(radiance.total());
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x) {
      const cv::Vec3f v = radiance.at<cv::Vec3f>(y, x);
      lum.push_back((v[0] + v[1] + v[2]) / 3);
    }
  const size_t q = std::min(lum.size() - 1, static_cast<size_t>(dark_quantile * lum.size()));
  std::nth_element(lum.begin(), lum.begin() + q, lum.end());
  peak = std::max(peak, 1e-30);
  const double dark = std::max(static_cast<double>(lum[q]), peak * 1e-12);
  const double t_short = std::exp2(std::floor(std::log2(max_signal / peak)));
  const double t_long = dark_signal / dark;
  const int frames = std::clamp(1 + static_cast<int>(std::ceil(std::log2(t_long / t_short) / stops)), 1, max_frames);
  std::vector<double> t;
  for (int k = 0; k < frames; ++k) t.push_back(t_short * std::exp2(stops * k));
  return t;
}

}  // namespace brdfshot
