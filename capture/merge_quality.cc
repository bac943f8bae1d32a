#include "capture/merge_quality.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "capture/merge.h"
#include "util/check.h"
#include "util/progress.h"
#include "util/stats.h"

namespace brdfshot {
namespace {

// The codes a frame is judged on: mid-tones in every channel. A real frame's
// darkest codes are its black level and noise (a film scan's floor sits at
// 13–20), which no merge predicts, and its brightest are near clipping.
constexpr int kMidLow = 32, kMidHigh = 223;

// The rg chromaticity of a linear RGB triple; false when it is not positive.
bool Chromaticity(double r, double g, double b, cv::Vec2d* rg) {
  const double s = r + g + b;
  if (!(s > 0) || !std::isfinite(s)) return false;
  *rg = {r / s, g / s};
  return true;
}

// The code whose linear value is nearest `v` (lin monotone non-decreasing).
int NearestCode(const std::vector<double>& lin, double v) {
  const auto it = std::lower_bound(lin.begin(), lin.end(), v);
  if (it == lin.begin()) return 0;
  if (it == lin.end()) return static_cast<int>(lin.size()) - 1;
  const int hi = static_cast<int>(it - lin.begin());
  return v - lin[hi - 1] <= lin[hi] - v ? hi - 1 : hi;
}

}  // namespace

MergeAndResponse OurMerge(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times, int clip_reach) {
  const ResponseCurve r = RecoverResponse(rgb8, times, 3, 200000, clip_reach);
  MergeOptions opt;
  opt.clip_reach = clip_reach;
  MergeAndResponse out;
  out.radiance = MergeBracket(rgb8, times, r, opt).radiance;
  for (int c = 0; c < 3; ++c)
    for (int z = 0; z < r.levels; ++z) out.lin[c].push_back(r.Linear(c, z));
  return out;
}

MergeAndResponse OpenCvDebevecMerge(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times) {
  const std::vector<float> t(times.begin(), times.end());
  cv::Mat response;  // 256 × 1, CV_32FC3: the linear value of each code, in the frames' channel order
  cv::createCalibrateDebevec()->process(rgb8, response, t);
  MergeAndResponse out;
  cv::createMergeDebevec()->process(rgb8, out.radiance, t, response);
  for (int c = 0; c < 3; ++c)
    for (int z = 0; z < 256; ++z) out.lin[c].push_back(response.at<cv::Vec3f>(z)[c]);
  return out;
}

std::vector<LeftOutFrame> LeaveOneFrameOut(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times,
                                           const BracketMerger& merge) {
  if (rgb8.size() < 3 || rgb8.size() != times.size())
    throw Error("leaving one frame out needs a bracket of three frames or more, each with its exposure");
  std::vector<int> order(rgb8.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  std::vector<LeftOutFrame> out;
  for (size_t q = 1; q + 1 < order.size(); ++q) {
    const int k = order[q];
    std::vector<cv::Mat> frames;
    std::vector<double> t;
    for (size_t j = 0; j < rgb8.size(); ++j)
      if (static_cast<int>(j) != k) frames.push_back(rgb8[j]), t.push_back(times[j]);
    const MergeAndResponse m = merge(frames, t);
    // The responses are known up to a factor per channel only when a method
    // normalises them differently from its merge: the prediction uses the
    // method's own pair, so no factor enters.
    std::array<std::vector<double>, 3> errors;
    std::vector<double> chroma;
    const cv::Mat& real = rgb8[k];
    const int step = std::max(1, static_cast<int>(std::sqrt(real.total() / 1e6)));
    for (int y = 0; y < real.rows; y += step)
      for (int x = 0; x < real.cols; x += step) {
        const cv::Vec3b z = real.at<cv::Vec3b>(y, x);
        if (*std::min_element(z.val, z.val + 3) < kMidLow || *std::max_element(z.val, z.val + 3) > kMidHigh) continue;
        const cv::Vec3f e = m.radiance.at<cv::Vec3f>(y, x);
        double predicted[3], measured[3];
        for (int c = 0; c < 3; ++c) {
          predicted[c] = e[c] * times[k];
          measured[c] = m.lin[c][z[c]];
          errors[c].push_back(std::abs(NearestCode(m.lin[c], predicted[c]) - z[c]));
        }
        cv::Vec2d a, b;
        if (Chromaticity(predicted[0], predicted[1], predicted[2], &a) &&
            Chromaticity(measured[0], measured[1], measured[2], &b))
          chroma.push_back(cv::norm(a - b));
      }
    LeftOutFrame f;
    f.frame = k;
    f.time = times[k];
    f.pixels = static_cast<long>(errors[0].size());
    for (int c = 0; c < 3; ++c) f.code_error[c] = Median(errors[c]);
    f.chroma_error = Median(chroma);
    out.push_back(f);
  }
  return out;
}

double ChromaSpeckle(const cv::Mat& radiance, double dark_quantile, double distance, int window) {
  BRDFSHOT_CHECK(radiance.type() == CV_32FC3 && window >= 3 && window % 2 == 1);
  cv::Mat r(radiance.size(), CV_32F), g(radiance.size(), CV_32F), lum(radiance.size(), CV_32F);
  std::vector<float> lums;
  lums.reserve(radiance.total());
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x) {
      const cv::Vec3f v = radiance.at<cv::Vec3f>(y, x);
      const double s = std::max(0.0f, v[0]) + std::max(0.0f, v[1]) + std::max(0.0f, v[2]);
      r.at<float>(y, x) = s > 0 ? std::max(0.0f, v[0]) / s : 1 / 3.0;
      g.at<float>(y, x) = s > 0 ? std::max(0.0f, v[1]) / s : 1 / 3.0;
      lum.at<float>(y, x) = static_cast<float>(0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]);
      lums.push_back(lum.at<float>(y, x));
    }
  // The darkest ⌈quantile · n⌉ pixels (and any tied with the last of them).
  const size_t q = std::min(lums.size(), static_cast<size_t>(std::ceil(dark_quantile * lums.size()))) - 1;
  std::nth_element(lums.begin(), lums.begin() + q, lums.end());
  const float dark = lums[q];
  // The neighbourhood's median chromaticity per component (OpenCV's median
  // filter takes 8-bit or, for 3 and 5 px, float images).
  cv::Mat rm, gm;
  if (window <= 5) {
    cv::medianBlur(r, rm, window);
    cv::medianBlur(g, gm, window);
  } else {
    cv::Mat r8, g8;
    r.convertTo(r8, CV_8U, 255), g.convertTo(g8, CV_8U, 255);
    cv::medianBlur(r8, rm, window), cv::medianBlur(g8, gm, window);
    rm.convertTo(rm, CV_32F, 1 / 255.0), gm.convertTo(gm, CV_32F, 1 / 255.0);
  }
  long n = 0, far = 0;
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x) {
      if (lum.at<float>(y, x) > dark) continue;
      ++n;
      far += std::hypot(r.at<float>(y, x) - rm.at<float>(y, x), g.at<float>(y, x) - gm.at<float>(y, x)) > distance;
    }
  return n ? static_cast<double>(far) / n : 0;
}

MergeCheck CheckMerges(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times, int clip_reach) {
  for (const cv::Mat& f : rgb8)
    if (f.type() != CV_8UC3) throw Error("checking a merge needs 8-bit frames (JPEG, PNG, TIFF), not RAW or 16-bit");
  MergeCheck c;
  const BracketMerger ours = [clip_reach](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
    return OurMerge(f, t, clip_reach);
  };
  c.ours = LeaveOneFrameOut(rgb8, times, ours);
  c.opencv = LeaveOneFrameOut(rgb8, times, OpenCvDebevecMerge);
  Stopwatch sw;
  c.ours_speckle = ChromaSpeckle(OurMerge(rgb8, times, clip_reach).radiance);
  c.ours_seconds = sw.Seconds();
  Stopwatch sc;
  c.opencv_speckle = ChromaSpeckle(OpenCvDebevecMerge(rgb8, times).radiance);
  c.opencv_seconds = sc.Seconds();
  return c;
}

std::string MergeCheckTable(const MergeCheck& c) {
  std::string t =
      "| left out | exposure | method | pixels | code error R / G / B (median) | chroma error (median) |\n"
      "|---|---|---|---|---|---|\n";
  char buf[256];
  std::array<std::vector<double>, 2> code, chroma;
  for (size_t i = 0; i < c.ours.size(); ++i)
    for (int m = 0; m < 2; ++m) {
      const LeftOutFrame& f = m == 0 ? c.ours[i] : c.opencv[i];
      std::snprintf(buf, sizeof buf, "| %d | %.4g | %s | %ld | %.1f / %.1f / %.1f | %.4f |\n", f.frame, f.time,
                    m == 0 ? "brdfshot" : "OpenCV Debevec", f.pixels, f.code_error[0], f.code_error[1], f.code_error[2],
                    f.chroma_error);
      t += buf;
      code[m].push_back((f.code_error[0] + f.code_error[1] + f.code_error[2]) / 3);
      chroma[m].push_back(f.chroma_error);
    }
  t += "\n| method | code error (median over frames, mean of channels) | chroma error | shadow speckle | merge s |\n"
       "|---|---|---|---|---|\n";
  for (int m = 0; m < 2; ++m) {
    std::snprintf(buf, sizeof buf, "| %s | %.2f | %.4f | %.4f | %.2f |\n", m == 0 ? "brdfshot" : "OpenCV Debevec",
                  Median(code[m]), Median(chroma[m]), m == 0 ? c.ours_speckle : c.opencv_speckle,
                  m == 0 ? c.ours_seconds : c.opencv_seconds);
    t += buf;
  }
  return t;
}

}  // namespace brdfshot
