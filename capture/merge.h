// Merging a bracket into linear radiance (relative units: value / exposure).
//
// Weights (default kNoise): each frame's estimate lin(z)/t is weighted by its
// inverse variance under a noise model estimated from the bracket itself, and
// falls to exactly zero at the clipping and near-black codes (OpenCV's
// MergeDebevec weights 0 and 255 with 1, so a clipped window leaks its clip
// level into the result). `brdfshot bench-merge` measures the choices. A pixel no
// frame measured well is flagged in the mask and gets the bound its frames
// imply (clipped even in the shortest: ≥ clip/t_min; dark even in the longest).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "capture/response.h"

namespace brdfshot {

enum class MergeWeights {
  kHat,    // Debevec & Malik's triangle × t
  kFlat,   // flat top tapering to zero near black and clipping, × t (shot-noise optimal)
  kNoise,  // inverse variance: t² / (shot + read + code-step quantisation), tapered
};

// Sensor noise in units of the clipping level x = lin / lin(clip): variance of
// x is shot · x + read (+ the code step's rounding, known from the response).
struct NoiseModel {
  double shot = 1e-4;    // 1 / full well in electrons
  double read = 1.6e-7;  // (read noise / full well)²
};

// The code of channel c at pixel (x, y) of an 8- or 16-bit three-channel
// frame (the merge's input; inline: it is read per pixel and channel).
inline int FrameCode(const cv::Mat& frame, int y, int x, int c) {
  return frame.type() == CV_8UC3 ? frame.ptr<cv::Vec3b>(y)[x][c] : frame.ptr<cv::Vec3w>(y)[x][c];
}

struct MergeOptions {
  double low = 0.02;   // fraction of the code range below which a code is near-black
  double high = 0.98;  // ...above which it is clipped
  MergeWeights weights = MergeWeights::kNoise;
  bool estimate_noise = true;  // kNoise: EstimateNoise from the bracket, else `noise`
  NoiseModel noise;
  // 8-bit frames: a frame does not count within this many pixels of a pixel
  // with two channels clipped — kJpegClipReach for JPEG light probes
  // (clipping.h: JPEG lowers the third); < 0: each channel on its own.
  int clip_reach = -1;
  // kNoise: where some channel's estimate is noisier than 30 % (deep shadows
  // of a high-ISO bracket), the pixel keeps its brightness and takes its
  // colour from its noisy neighbours (merge.cc, PoolNoisyChroma): no chroma
  // speckle. Off: every channel as merged.
  bool pool_noisy_chroma = true;
  // Per frame, CV_8U nonzero where the frame does not count (ghosts,
  // capture/ghosts.h), on top of clipping; empty: every frame counts.
  std::vector<cv::Mat> excluded;
};

// The noise model of a bracket, from the frames themselves: where two frames
// adjacent in exposure both measured a pixel well, their radiance estimates
// differ by noise alone, and the squared difference is linear in (shot, read).
// Solved by least squares over a grid of pixels (the top 2 % trimmed as
// misregistration or edges), clamped to ≥ 0; the default model when fewer
// than 100 such pixels exist.
NoiseModel EstimateNoise(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt);

struct MergeResult {
  cv::Mat radiance;  // CV_32FC3, RGB
  cv::Mat mask;      // CV_8U, 255 where no frame measured some channel well
  double unreliable_fraction = 0;
  double chroma_pooled_fraction = 0;  // pixels whose colour came from their neighbours (pool_noisy_chroma)
  // Wall time of the merge's parts, for `bench-merge --bracket`: the noise
  // model estimated from the frames, and the colour pooling of noisy pixels.
  double noise_seconds = 0, pool_seconds = 0;
};

// `frames`: RGB, all CV_8UC3 or all CV_16UC3, same size; `times` relative
// exposures. Error naming the problem on a size or type mismatch. One 16-bit
// frame is allowed (a single RAW or linear image): its radiance is code / t,
// and only its clipped pixels are flagged.
MergeResult MergeBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                         const ResponseCurve& response, const MergeOptions& opt = {});

}  // namespace brdfshot

namespace brdfshot {

// The response the merge uses by default (here, not in response.h, because its
// refinement is a merge): Debevec & Malik's solution, then
// `iterations` of Robertson's fixed point on a grid of ~`pixels` pixels —
// merge with the current curve, then set each code's linear value to the mean
// of E·t over every frame sample showing that code. Debevec alone is biased
// where noise is large (it fits ln g to noisy codes); the linear-domain mean
// is not. Codes never seen keep Debevec's value; the result is made monotone.
// `clip_reach` as MergeOptions' (kJpegClipReach for JPEG light probes):
// samples clipped nearby in a frame are not used.
ResponseCurve RecoverResponse(const std::vector<cv::Mat>& frames, const std::vector<double>& times, int iterations = 3,
                              int pixels = 200000, int clip_reach = -1);

}  // namespace brdfshot
