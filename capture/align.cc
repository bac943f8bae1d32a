#include "capture/align.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <opencv2/video/tracking.hpp>

#include "util/check.h"

namespace brdfshot {

namespace {

cv::Mat Gray8(const cv::Mat& rgb) {
  cv::Mat g;
  cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
  if (g.depth() == CV_16U) g.convertTo(g, CV_8U, 1.0 / 257);
  return g;
}

// MTB's shift that brings `frame` onto `ref` (shifted(x) = frame(x − s)).
cv::Point MtbShift(const cv::Mat& ref_gray, const cv::Mat& frame_gray, int max_shift_px) {
  // MTB searches ±1 px per pyramid level, doubling per level: 2^levels ≥ max shift.
  const int levels = std::max(1, static_cast<int>(std::ceil(std::log2(std::max(2, max_shift_px)))));
  return cv::createAlignMTB(levels)->calculateShift(ref_gray, frame_gray);
}

cv::Matx33d Translation(double dx, double dy) { return {1, 0, dx, 0, 1, dy, 0, 0, 1}; }
cv::Matx33d Scale(double f) { return {f, 0, 0, 0, f, 0, 0, 0, 1}; }

// The frame's codes mapped onto the reference's by matching their histograms
// (cumulative distributions): two exposures of one scene differ by a
// monotone map of codes — through the camera's response, which is unknown
// here — and matching the histograms finds it from the frames alone. ECC,
// invariant to what affine difference remains, then compares like with like.
cv::Mat MatchHistogram(const cv::Mat& frame_gray, const cv::Mat& ref_gray) {
  std::array<double, 256> cf{}, cr{};
  for (int y = 0; y < frame_gray.rows; ++y)
    for (int x = 0; x < frame_gray.cols; ++x) ++cf[frame_gray.at<uint8_t>(y, x)], ++cr[ref_gray.at<uint8_t>(y, x)];
  for (int z = 1; z < 256; ++z) cf[z] += cf[z - 1], cr[z] += cr[z - 1];
  cv::Mat lut(1, 256, CV_8U);
  for (int z = 0, r = 0; z < 256; ++z) {
    // The middle of this code's share of the frame, and the reference code holding that quantile.
    const double q = (cf[z] - 0.5 * (cf[z] - (z ? cf[z - 1] : 0))) / cf[255] * cr[255];
    while (r < 255 && cr[r] < q) ++r;
    lut.at<uint8_t>(z) = static_cast<uint8_t>(r);
  }
  cv::Mat mapped;
  cv::LUT(frame_gray, lut, mapped);
  return mapped;
}

// A frame's grey codes at each scale ECC runs at (halvings from ~250 px up to
// 2000 px or the full image), made once per frame.
struct Pyramid {
  std::vector<double> scales;
  std::vector<cv::Mat> levels;  // CV_8U
};

Pyramid MakePyramid(const cv::Mat& gray8) {
  Pyramid p;
  const int longest = std::max(gray8.cols, gray8.rows);
  p.scales = {std::min(1.0, 2000.0 / longest)};
  while (p.scales.front() * longest > 250) p.scales.insert(p.scales.begin(), p.scales.front() / 2);
  for (double s : p.scales) {
    cv::Mat g = gray8;
    if (s < 1) cv::resize(gray8, g, cv::Size(), s, s, cv::INTER_AREA);
    p.levels.push_back(g);
  }
  return p;
}

std::string FrameName(const AlignOptions& o, int j) {
  return j < static_cast<int>(o.frame_names.size()) ? o.frame_names[j] : "frame " + std::to_string(j);
}

// The share of pixels with signal in both frames below which a pair is left
// to MTB's shift.
constexpr double kMinSharedSignal = 0.2;

// One ECC refinement of W at pyramid level `k`: false when ECC does not converge.
bool EccAtLevel(const Pyramid& ref, const Pyramid& frame, size_t k, int iterations, cv::Matx33d* W, double* rho) {
  const double scale = ref.scales[k];
  const cv::Mat& ref8 = ref.levels[k];
  const cv::Mat& frame8 = frame.levels[k];
  cv::Mat a, b, mask, frame_usable;
  ref8.convertTo(a, CV_32F);
  MatchHistogram(frame8, ref8).convertTo(b, CV_32F);
  cv::inRange(ref8, 16, 240, mask);  // codes with signal: not black, not clipped
  cv::inRange(frame8, 16, 240, frame_usable);
  const cv::Matx33d scaled = Scale(scale) * *W * Scale(1 / scale);
  // Only pixels with signal in both frames are compared: the other frame's
  // black and clipped codes, brought onto the reference by the current warp,
  // are left out too (a clipped sky is flat in one frame and textured in the
  // other, and would pull the fit).
  cv::Mat usable_there;
  cv::warpPerspective(frame_usable, usable_there, cv::Mat(scaled), a.size(), cv::INTER_NEAREST | cv::WARP_INVERSE_MAP,
                      cv::BORDER_CONSTANT, 0);
  mask &= usable_there;
  cv::Mat w(3, 3, CV_32F);
  for (int i = 0; i < 9; ++i) w.at<float>(i / 3, i % 3) = static_cast<float>(scaled.val[i] / scaled.val[8]);
  try {
    const cv::TermCriteria stop(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, iterations, 1e-5);
    *rho = cv::findTransformECC(a, b, w, cv::MOTION_HOMOGRAPHY, stop, mask, 3);
  } catch (const cv::Exception&) {  // OpenCV's way of saying the correlation fell: no warp found
    return false;
  }
  cv::Matx33d ws;
  for (int i = 0; i < 9; ++i) ws.val[i] = w.at<float>(i / 3, i % 3);
  *W = Scale(1 / scale) * ws * Scale(scale);
  return true;
}

// The warp W (pixel of `ref` → pixel of `frame`) with frame(W x) ≈ ref(x).
// ECC converges from within a few pixels of the answer at the scale it runs;
// the pyramid brings a turn of the camera by tens of pixels within reach. It
// starts from each of `starts` at the coarsest level and goes on from the
// best correlated. Error naming the two frames when none converges or the
// frames do not correlate.
cv::Matx33d EccHomography(const Pyramid& ref, const Pyramid& frame, const std::vector<cv::Matx33d>& starts,
                          int ref_index, int frame_index, const AlignOptions& o) {
  cv::Matx33d W;
  double rho = -1;
  for (const cv::Matx33d& start : starts) {
    cv::Matx33d w = start;
    double r = 0;
    if (EccAtLevel(ref, frame, 0, 50, &w, &r) && r > rho) W = w, rho = r;
  }
  bool converged = rho > -1;
  for (size_t k = 1; k < ref.levels.size() && converged; ++k) converged = EccAtLevel(ref, frame, k, 100, &W, &rho);
  if (!converged || rho < o.min_correlation) {
    // Two frames that share too little signal (the longest of a bracket is
    // mostly clipped) cannot tell a homography: they keep MTB's shift, which
    // needs no more than the median's bitmap. Only frames with signal in
    // common that still do not match are refused.
    // (A frame of another scene is still refused when the pixels the two
    // share, under that shift, do not correlate.)
    cv::Mat a, b;
    cv::inRange(ref.levels[0], 16, 240, a);
    cv::inRange(frame.levels[0], 16, 240, b);
    const cv::Mat shared = a & b;
    const int n_shared = cv::countNonZero(shared);
    if (n_shared < kMinSharedSignal * a.total()) {
      const cv::Matx33d shift = Scale(ref.scales[0]) * starts[0] * Scale(1 / ref.scales[0]);
      cv::Mat ref32, moved, moved32;
      ref.levels[0].convertTo(ref32, CV_32F);
      cv::warpPerspective(MatchHistogram(frame.levels[0], ref.levels[0]), moved, cv::Mat(shift), ref32.size(),
                          cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
      moved.convertTo(moved32, CV_32F);
      if (n_shared < 100 || cv::computeECC(ref32, moved32, shared) >= o.min_correlation) return starts[0];
    }
  }
  if (!converged)
    throw Error(FrameName(o, frame_index) + " and " + FrameName(o, ref_index) +
                " cannot be aligned (the correlation of their codes does not converge): not the same scene, "
                "or moved too far");
  if (rho < o.min_correlation)
    throw Error(FrameName(o, frame_index) + " and " + FrameName(o, ref_index) +
                " cannot be aligned: their codes correlate only " + std::to_string(rho) +
                " after the best homography (not the same scene, or moved too far)");
  return W;
}

// The share of the reference's pixels whose warped position lies in the frame.
double Overlap(const cv::Matx33d& W, cv::Size size) {
  long in = 0, n = 0;
  for (int y = 0; y < size.height; y += 8)
    for (int x = 0; x < size.width; x += 8, ++n) {
      const cv::Vec3d p = W * cv::Vec3d(x + 0.5, y + 0.5, 1);
      const double u = p[0] / p[2], v = p[1] / p[2];
      in += p[2] > 0 && u >= 0 && v >= 0 && u < size.width && v < size.height;
    }
  return n ? static_cast<double>(in) / n : 0;
}

}  // namespace

AlignedBracket AlignBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                            const AlignOptions& o) {
  if (frames.size() < 2) throw Error("alignment needs at least two frames");
  BRDFSHOT_CHECK(times.size() == frames.size());
  for (size_t j = 0; j < frames.size(); ++j)
    if (frames[j].size() != frames[0].size())
      throw Error(FrameName(o, static_cast<int>(j)) + " differs in size from " + FrameName(o, 0));
  const int n = static_cast<int>(frames.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  AlignedBracket out;
  const int mid = n / 2;
  out.reference = order[mid];
  std::vector<cv::Mat> gray(n);
  for (int j = 0; j < n; ++j) gray[j] = Gray8(frames[j]);
  std::vector<Pyramid> pyramid(o.model == AlignModel::kHomography ? n : 0);
#pragma omp parallel for schedule(dynamic)
  for (int j = 0; j < static_cast<int>(pyramid.size()); ++j) pyramid[j] = MakePyramid(gray[j]);
  out.warps.assign(n, cv::Matx33d::eye());
  out.shifts.assign(n, cv::Point(0, 0));
  // Each frame onto its neighbour towards the reference in exposure order
  // (pairs are independent: in parallel), then chained outwards:
  // W_j = W_(j→neighbour) · W_neighbour.
  std::vector<cv::Matx33d> pair(n, cv::Matx33d::eye());
  std::vector<std::string> failed(n);
#pragma omp parallel for schedule(dynamic)
  for (int q = 0; q < n; ++q) {
    if (q == mid) continue;
    const int j = order[q], towards = order[q < mid ? q + 1 : q - 1];
    try {
      const cv::Point s = MtbShift(gray[towards], gray[j], o.max_shift_px);
      pair[j] = Translation(-s.x, -s.y);
      if (o.model == AlignModel::kHomography)  // MTB's shift can mislead on fine texture: the identity is tried too
        pair[j] = EccHomography(pyramid[towards], pyramid[j], {pair[j], cv::Matx33d::eye()}, towards, j, o);
    } catch (const Error& e) {
      failed[j] = e.what();
    }
  }
  for (int q = 0; q < n; ++q)  // the first refusal in exposure order, as a serial run would give it
    if (!failed[order[q]].empty()) throw Error(failed[order[q]]);
  for (int step : {-1, 1})
    for (int q = mid + step; q >= 0 && q < n; q += step)
      out.warps[order[q]] = pair[order[q]] * out.warps[order[q - step]];
  // The chain's errors add up; a last refinement straight against the
  // reference, from the chained warp, removes them where the two exposures
  // still share enough signal (else the chain stands).
  if (o.model == AlignModel::kHomography) {
#pragma omp parallel for schedule(dynamic)
    for (int q = 0; q < n; ++q) {
      if (std::abs(q - mid) < 2) continue;
      const int j = order[q];
      cv::Matx33d direct = out.warps[j];
      double rho = 0;
      if (EccAtLevel(pyramid[out.reference], pyramid[j], pyramid[j].levels.size() - 1, 100, &direct, &rho) &&
          rho >= o.min_correlation)
        out.warps[j] = direct;
    }
  }
  for (int j = 0; j < n; ++j) {
    const double overlap = Overlap(out.warps[j], frames[j].size());
    if (overlap < o.min_overlap)
      throw Error(FrameName(o, j) + " covers only " + std::to_string(static_cast<int>(100 * overlap)) +
                  " % of the reference " + FrameName(o, out.reference) + " once aligned (need " +
                  std::to_string(static_cast<int>(100 * o.min_overlap)) + " %): moved too far to merge");
  }
  for (int j = 0; j < n; ++j) {
    const cv::Matx33d& W = out.warps[j];
    out.shifts[j] = cv::Point(static_cast<int>(std::lround(-W(0, 2))), static_cast<int>(std::lround(-W(1, 2))));
    if (j == out.reference) {
      out.frames.push_back(frames[j]);
      continue;
    }
    cv::Mat warped;
    if (o.model == AlignModel::kTranslation)
      cv::warpAffine(frames[j], warped, cv::Matx23d(1, 0, -W(0, 2), 0, 1, -W(1, 2)), frames[j].size(),
                     cv::INTER_NEAREST, cv::BORDER_REPLICATE);
    else
      cv::warpPerspective(frames[j], warped, cv::Mat(W), frames[j].size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                          cv::BORDER_REPLICATE);
    out.frames.push_back(warped);
  }
  return out;
}

}  // namespace brdfshot
