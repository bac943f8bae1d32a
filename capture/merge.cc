#include "capture/merge.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "capture/clipping.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

namespace {

void CheckBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times) {
  if (frames.empty()) throw Error("a bracket needs at least one frame");
  // One frame is a bracket only when it is linear: an 8-bit frame's response
  // is recovered from several exposures.
  if (frames.size() < 2 && frames[0].type() != CV_16UC3)
    throw Error("a bracket of 8-bit frames needs at least two frames, got " + std::to_string(frames.size()));
  if (frames.size() > 64) throw Error("a bracket of " + std::to_string(frames.size()) + " frames: at most 64");
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
}

// Per-code tables of one bracket's codes.
struct CodeTables {
  int levels, zlo, zhi;
  std::array<std::vector<float>, 3> lin;  // linear value of each code
  std::array<double, 3> sat;              // linear value at clipping
  std::vector<float> taper;               // 0 outside (zlo, zhi), ramps to 1 over 10 % of the range
  // Variance of x = lin/sat of code z from rounding to a code step.
  double QuantVar(int c, int z) const {
    const double dx = (lin[c][std::min(levels - 1, z + 1)] - lin[c][std::max(0, z - 1)]) / (2 * sat[c]);
    return dx * dx / 12;
  }
};

CodeTables MakeTables(int type, const ResponseCurve& response, const MergeOptions& opt) {
  CodeTables t;
  t.levels = type == CV_8UC3 ? 256 : 65536;
  if (response.levels != t.levels)
    throw Error("response curve has " + std::to_string(response.levels) + " codes, frames have " +
                std::to_string(t.levels));
  t.zlo = static_cast<int>(std::ceil(opt.low * (t.levels - 1)));
  t.zhi = static_cast<int>(std::floor(opt.high * (t.levels - 1)));
  const double ramp = 0.1 * (t.zhi - t.zlo);
  t.taper.assign(t.levels, 0.0f);
  for (int z = t.zlo + 1; z < t.zhi; ++z)
    t.taper[z] = static_cast<float>(std::min({1.0, (z - t.zlo) / ramp, (t.zhi - z) / ramp}));
  for (int c = 0; c < 3; ++c) {
    t.lin[c].resize(t.levels);
    for (int z = 0; z < t.levels; ++z) t.lin[c][z] = static_cast<float>(response.Linear(c, z));
    t.sat[c] = std::max(1e-30, static_cast<double>(t.lin[c][t.zhi]));
  }
  return t;
}

}  // namespace

NoiseModel EstimateNoise(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt) {
  CheckBracket(frames, times);
  const CodeTables T = MakeTables(frames[0].type(), response, opt);
  std::vector<int> order(frames.size());
  for (size_t j = 0; j < order.size(); ++j) order[j] = static_cast<int>(j);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  // Rows: [x_j/t_j² + x_k/t_k², 1/t_j² + 1/t_k²] · (shot, read) = d² − quantisation.
  struct Row {
    double a, b, y;
  };
  std::vector<Row> rows;
  const int step = std::max(1, static_cast<int>(std::sqrt(frames[0].total() / 20000.0)));
  for (size_t p = 0; p + 1 < order.size(); ++p) {
    const int j = order[p], k = order[p + 1];
    const double tj = times[j], tk = times[k];
    for (int y = 0; y < frames[0].rows; y += step)
      for (int x = 0; x < frames[0].cols; x += step)
        for (int c = 0; c < 3; ++c) {
          const int zj = FrameCode(frames[j], y, x, c), zk = FrameCode(frames[k], y, x, c);
          if (T.taper[zj] < 1 || T.taper[zk] < 1) continue;
          const double xj = T.lin[c][zj] / T.sat[c], xk = T.lin[c][zk] / T.sat[c];
          const double d = xj / tj - xk / tk;
          rows.push_back({xj / (tj * tj) + xk / (tk * tk), 1 / (tj * tj) + 1 / (tk * tk),
                          d * d - T.QuantVar(c, zj) / (tj * tj) - T.QuantVar(c, zk) / (tk * tk)});
        }
  }
  if (rows.size() < 100) return opt.noise;
  std::sort(rows.begin(), rows.end(), [](const Row& p, const Row& q) { return p.y < q.y; });
  rows.resize(rows.size() * 98 / 100);
  // 2×2 normal equations in double, each row scaled by 1/b (the terms span
  // decades of t²; unscaled, the longest exposures would decide everything).
  double aa = 0, ab = 0, bb = 0, ay = 0, by = 0;
  for (const Row& r : rows) {
    const double s = 1 / r.b, a = r.a * s, b = 1.0, yv = r.y * s;
    aa += a * a, ab += a * b, bb += b * b, ay += a * yv, by += b * yv;
  }
  const double det = aa * bb - ab * ab;
  NoiseModel m = opt.noise;
  if (std::abs(det) > 1e-12 * aa * bb) {
    m.shot = std::max(0.0, (ay * bb - ab * by) / det);
    m.read = std::max(0.0, (aa * by - ab * ay) / det);
  }
  // A perfectly clean bracket (synthetic, no noise) leaves only quantisation:
  // keep a floor so the weights stay finite.
  m.shot = std::max(m.shot, 1e-7);
  m.read = std::max(m.read, 1e-10);
  return m;
}

namespace {

// Where every frame is noisy (deep shadows of a high-ISO bracket), each
// channel's estimate carries its own noise — tens of percent — and the
// channels disagree at random: isolated pixels of saturated hue ("chroma
// speckle") where the scene is grey. No weighting across frames removes it,
// since the noise is in the best frame already; what a camera's own
// processing does, and what is done here, is to pool colour over
// neighbours: such a pixel keeps its brightness (the sum over channels) and
// takes its chromaticity from the noisy pixels of its 7 × 7 neighbourhood,
// up to seven times less noisy. A pixel is noisy when some channel's
// relative standard deviation, 1 / (√(Σ_j w_j) · E) under the
// inverse-variance weights, exceeds kChromaNoise (a signal-to-noise ratio of
// 3.3), or when some channel is unmeasured for want of light. The threshold
// is high because the noise model's absolute level is only as good as its
// fit: on a film scan (Debevec's memorial) the fitted shot noise is high, and
// a lower threshold would pool the colour of much of a well-exposed image
// (docs/benchmarks.md).
constexpr double kChromaNoise = 0.3;

void PoolNoisyChroma(const cv::Mat& noisy, cv::Mat* radiance) {
  // Pooled over the noisy neighbours only: a lamp beside a dark corner must
  // not lend the corner its colour.
  cv::Mat only_noisy = cv::Mat::zeros(radiance->size(), CV_32FC3);
  radiance->copyTo(only_noisy, noisy);
  cv::Mat pooled;
  cv::boxFilter(only_noisy, pooled, CV_32F, cv::Size(7, 7), cv::Point(-1, -1), false, cv::BORDER_REFLECT);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < radiance->rows; ++y)
    for (int x = 0; x < radiance->cols; ++x) {
      if (!noisy.at<uint8_t>(y, x)) continue;
      cv::Vec3f& v = radiance->at<cv::Vec3f>(y, x);
      const cv::Vec3f p = pooled.at<cv::Vec3f>(y, x);
      const float sum = v[0] + v[1] + v[2], pooled_sum = p[0] + p[1] + p[2];
      if (pooled_sum > 0 && sum > 0) v = p * (sum / pooled_sum);
    }
}

// MergeBracket, with `given_clipped` (one mask per frame, or empty: per
// channel) saying where each frame does not count; null: opt.clip_reach's.
// `pool_noisy_chroma`: the final merge's colour pooling (PoolNoisyChroma);
// off in the response's refinement, whose fixed point needs every pixel's own
// estimate.
MergeResult MergeWithClipping(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                              const ResponseCurve& response, const MergeOptions& opt,
                              const std::vector<cv::Mat>* given_clipped, bool pool_noisy_chroma) {
  const int type = frames[0].type();
  const CodeTables T = MakeTables(type, response, opt);
  const int levels = T.levels, zlo = T.zlo, zhi = T.zhi;
  // A frame does not count where it is clipped nearby (clipping.h: JPEG
  // lowers the codes around a clipped highlight). Empty: per channel.
  std::vector<cv::Mat> clipped = given_clipped ? *given_clipped : ClippedNearby(frames, zhi, opt.clip_reach);
  if (!opt.excluded.empty()) {
    BRDFSHOT_CHECK(opt.excluded.size() == frames.size(), "an exclusion mask per frame");
    if (clipped.empty())
      clipped = opt.excluded;
    else
      for (size_t j = 0; j < frames.size(); ++j) clipped[j] = clipped[j] | opt.excluded[j];
  }
  const auto& lin = T.lin;
  const Stopwatch noise_clock;
  const NoiseModel noise = opt.weights == MergeWeights::kNoise && opt.estimate_noise
                               ? EstimateNoise(frames, times, response, opt)
                               : opt.noise;
  const double noise_seconds = noise_clock.Seconds();
  // Weight of a frame's estimate lin(z)/t, up to the power of t.
  std::array<std::vector<float>, 3> wz;
  const double mid = 0.5 * (zlo + zhi);
  for (int c = 0; c < 3; ++c) {
    wz[c].assign(levels, 0.0f);
    for (int z = zlo + 1; z < zhi; ++z) {
      double w = T.taper[z];
      if (opt.weights == MergeWeights::kHat) {
        w = 1 - std::abs(z - mid) / (mid - zlo);
      } else if (opt.weights == MergeWeights::kNoise) {
        const double x = lin[c][z] / T.sat[c];
        w = T.taper[z] / ((noise.shot * x + noise.read + T.QuantVar(c, z)) * T.sat[c] * T.sat[c]);
      }
      wz[c][z] = static_cast<float>(w);
    }
  }
  const int t_power = opt.weights == MergeWeights::kNoise ? 2 : 1;
  const int N = static_cast<int>(frames.size());
  std::vector<int> order(N);
  for (int j = 0; j < N; ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  const int shortest = order.front(), longest = order.back();

  MergeResult out;
  out.noise_seconds = noise_seconds;
  out.radiance.create(frames[0].size(), CV_32FC3);
  out.mask = cv::Mat::zeros(frames[0].size(), CV_8U);
  const int rows = frames[0].rows, cols = frames[0].cols;
  auto code = [&frames](int j, int y, int x, int c) { return FrameCode(frames[j], y, x, c); };
  long unreliable = 0, noisy_pixels = 0;
  // Inverse-variance weights tell each estimate's noise; the other weightings do not.
  pool_noisy_chroma = pool_noisy_chroma && opt.pool_noisy_chroma && opt.weights == MergeWeights::kNoise && N > 1;
  cv::Mat noisy = pool_noisy_chroma ? cv::Mat::zeros(frames[0].size(), CV_8U) : cv::Mat();
#pragma omp parallel for schedule(static) reduction(+ : unreliable, noisy_pixels)
  for (int y = 0; y < rows; ++y) {
    cv::Vec3f* dst = out.radiance.ptr<cv::Vec3f>(y);
    uint8_t* m = out.mask.ptr<uint8_t>(y);
    // This row of each frame's clipping mask (null: per channel), read once:
    // the mask writes below may alias anything, so the compiler would not.
    std::vector<const uint8_t*> clip_rows(N, nullptr);
    if (!clipped.empty())
      for (int j = 0; j < N; ++j) clip_rows[j] = clipped[j].ptr<uint8_t>(y);
    for (int x = 0; x < cols; ++x) {
      bool bad = false, noisy_here = false;  // some channel's estimate too noisy for its colour
      uint64_t skip = 0;                     // bit j: frame j is clipped nearby here (≤ 64 frames, CheckBracket)
      if (!clipped.empty())
        for (int j = 0; j < N; ++j) skip |= (clip_rows[j][x] ? uint64_t{1} : 0) << j;
      for (int c = 0; c < 3; ++c) {
        double num = 0, den = 0;
        for (int j = 0; j < N; ++j) {
          if (skip >> j & 1) continue;
          const int z = code(j, y, x, c);
          const double w = wz[c][z] * (t_power == 2 ? times[j] * times[j] : times[j]);
          num += w * lin[c][z] / times[j];
          den += w;
        }
        if (den > 0) {
          dst[x][c] = static_cast<float>(num / den);
          if (pool_noisy_chroma)
            noisy_here = noisy_here || num <= 0 || 1 / std::sqrt(den) > kChromaNoise * (num / den);
          continue;
        }
        // Unmeasured: the bound the frames imply — bright when the shortest
        // frame is clipped there or nearby, dark otherwise.
        const int zs = code(shortest, y, x, c), zl = code(longest, y, x, c);
        const bool bright = zs >= zhi || (skip >> shortest & 1);
        dst[x][c] =
            bright ? lin[c][zs] / static_cast<float>(times[shortest]) : lin[c][zl] / static_cast<float>(times[longest]);
        // A single linear frame's dark codes are still its measurement (there
        // is no other frame to prefer); only its clipped ones are unreliable.
        bad = bad || N > 1 || zs >= zhi;
        noisy_here = noisy_here || !bright;
      }
      if (bad) m[x] = 255, ++unreliable;
      if (noisy_here && pool_noisy_chroma) noisy.at<uint8_t>(y, x) = 1, ++noisy_pixels;
    }
  }
  out.unreliable_fraction = static_cast<double>(unreliable) / (static_cast<double>(rows) * cols);
  const Stopwatch pool_clock;
  if (noisy_pixels > 0) PoolNoisyChroma(noisy, &out.radiance);
  out.pool_seconds = pool_clock.Seconds();
  out.chroma_pooled_fraction = static_cast<double>(noisy_pixels) / (static_cast<double>(rows) * cols);
  return out;
}

}  // namespace

MergeResult MergeBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt) {
  CheckBracket(frames, times);
  return MergeWithClipping(frames, times, response, opt, nullptr, true);
}

}  // namespace brdfshot

namespace brdfshot {

ResponseCurve RecoverResponse(const std::vector<cv::Mat>& frames, const std::vector<double>& times, int iterations,
                              int pixels, int clip_reach) {
  DebevecOptions debevec;
  debevec.clip_reach = clip_reach;
  ResponseCurve r = RecoverResponseDebevec(frames, times, debevec);  // checks: ≥ 2 frames, 8-bit, same size
  if (iterations <= 0) return r;
  // A regular grid of the frames: the fixed point needs many pixels per code,
  // not every pixel.
  const int step = std::max(1, static_cast<int>(std::sqrt(frames[0].total() / static_cast<double>(pixels))));
  // The samples clipped nearby in a frame (JPEG: clip_reach ≥ 0) are left
  // out of that frame's codes, as the merge leaves them out.
  std::vector<cv::Mat> sub, sub_clipped;
  for (size_t j = 0; j < frames.size(); ++j) {
    const cv::Mat& f = frames[j];
    cv::Mat s(f.rows / step, f.cols / step, f.type()), c(s.size(), CV_8U);
    for (int y = 0; y < s.rows; ++y)
      for (int x = 0; x < s.cols; ++x) {
        s.at<cv::Vec3b>(y, x) = f.at<cv::Vec3b>(y * step, x * step);
        c.at<uint8_t>(y, x) = IsClippedNearby(f, x * step, y * step, kClippedCode8, clip_reach) ? 255 : 0;
      }
    sub.push_back(s);
    sub_clipped.push_back(c);
  }
  // The grid's samples are not adjacent pixels: their clipping is the full
  // frames', sampled (sub_clipped), in the merge as in the sums below.
  if (clip_reach < 0) sub_clipped.clear();
  const MergeOptions opt;
  // Robertson's update sets g(z) to the mean exposure of the samples showing
  // z. A pixel that only one frame measures well (the blue of green leaves,
  // dark wherever green is not clipped) merges to that frame's own reading,
  // so its sample says nothing about g(z) — but with the noise weights and
  // the monotone repair such samples let g drift: dark blue codes rose by
  // e^1.2 in 3 iterations on a forest bracket, and the night scene's power
  // came out 5.9 % off in bench-merge. So a sample counts only when some
  // other frame measured its pixel's channel well (the weights' flat top).
  const std::vector<float> taper = MakeTables(CV_8UC3, r, opt).taper;
  auto well_measured = [&](size_t j, int y, int x, int c) {
    return taper[sub[j].at<cv::Vec3b>(y, x)[c]] >= 1.0f && (sub_clipped.empty() || !sub_clipped[j].at<uint8_t>(y, x));
  };
  // evidence[j]: per sample and channel (CV_8UC3), whether a frame other
  // than j measured that pixel's channel well.
  std::vector<cv::Mat> evidence(sub.size());
  {
    cv::Mat count = cv::Mat::zeros(sub[0].size(), CV_8UC3);
    for (size_t j = 0; j < sub.size(); ++j)
      for (int y = 0; y < count.rows; ++y)
        for (int x = 0; x < count.cols; ++x)
          for (int c = 0; c < 3; ++c) count.at<cv::Vec3b>(y, x)[c] += well_measured(j, y, x, c) ? 1 : 0;
    for (size_t j = 0; j < sub.size(); ++j) {
      evidence[j].create(count.size(), CV_8UC3);
      for (int y = 0; y < count.rows; ++y)
        for (int x = 0; x < count.cols; ++x)
          for (int c = 0; c < 3; ++c)
            evidence[j].at<cv::Vec3b>(y, x)[c] = count.at<cv::Vec3b>(y, x)[c] > (well_measured(j, y, x, c) ? 1 : 0);
    }
  }
  for (int it = 0; it < iterations; ++it) {
    const MergeResult m = MergeWithClipping(sub, times, r, opt, &sub_clipped, false);
    for (int c = 0; c < 3; ++c) {
      std::vector<double> sum(256, 0.0), count(256, 0.0);
      for (size_t j = 0; j < sub.size(); ++j)
        for (int y = 0; y < sub[j].rows; ++y)
          for (int x = 0; x < sub[j].cols; ++x) {
            if (m.mask.at<uint8_t>(y, x) || (!sub_clipped.empty() && sub_clipped[j].at<uint8_t>(y, x))) continue;
            const int z = sub[j].at<cv::Vec3b>(y, x)[c];
            // A sample is evidence about g(z) only if another frame pins its
            // pixel's exposure; alone, it just returns g(z) to itself.
            if (!evidence[j].at<cv::Vec3b>(y, x)[c]) continue;
            sum[z] += m.radiance.at<cv::Vec3f>(y, x)[c] * times[j];
            count[z] += 1;
          }
      std::vector<double>& g = r.g[c];
      for (int z = 1; z < 255; ++z)
        if (count[z] >= 10 && sum[z] > 0) g[z] = std::log(sum[z] / count[z]);
      const double g128 = g[128];
      for (double& v : g) v -= g128;  // keep g(128) = 0
      for (int z = 1; z < 256; ++z) g[z] = std::max(g[z], g[z - 1] + 1e-6);
    }
  }
  return r;
}

}  // namespace brdfshot
