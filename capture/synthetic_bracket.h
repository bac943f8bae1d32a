// A known camera, for measuring merges against ground truth: scene radiance in,
// the frames a real camera would record out. Used by `bench-merge`, the tests,
// and `synth-capture`.
//
// Per frame and channel: electrons = Poisson(full_well · E t) approximated as
// Gaussian (shot noise) plus Gaussian read noise; the sensor clips at the full
// well; then either the response curve and 8-bit rounding (an LDR camera) or
// linear `raw_bits` quantisation stored in the top bits of 16 (a RAW-like file).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace brdfshot {

struct CameraModel {
  double gamma = 2.2;        // 8-bit code = 255 (x^(1/γ)) with a soft shoulder, x = signal / full well
  double shoulder = 0.25;    // x ↦ x (1 + s) / (x + s) before the power: highlights roll off
  double full_well = 20000;  // electrons at clipping
  double read_noise = 4;     // electrons RMS
  int raw_bits = 0;          // 0: 8-bit LDR through the response; 12 or 14: linear RAW-like
  uint64_t seed = 1;
  // Normalised code (0..1) of a normalised sensor signal x ∈ [0, 1] (LDR only).
  double Response(double x) const;
};

// Frames of `radiance` (CV_32FC3, relative units) at exposures `times`:
// CV_8UC3 for LDR, CV_16UC3 for RAW-like. Deterministic for a seed.
std::vector<cv::Mat> SimulateBracket(const cv::Mat& radiance, const std::vector<double>& times,
                                     const CameraModel& camera);

// Exposure times 2^(stops·(k − (n−1)/2)) · t_mid, with t_mid putting the
// radiance's median at 18 % of the full well: a photographer's bracket.
std::vector<double> BracketTimes(const cv::Mat& radiance, int frames, double stops);

// A bracket that measures all of `radiance` (CV_32FC3, in units where signal =
// radiance · t reaches full well at 1): the shortest frame keeps the brightest
// pixel below `max_signal` of full well (mid-curve, where an 8-bit response is well measured), the longest lifts the
// `dark_quantile` pixel luminance to `dark_signal`; times step by `stops` from the shortest, which is rounded down to a
// power of two (so times are exact in EXIF, 1/n or n). At most `max_frames` frames: the dark end is given up first.
std::vector<double> CoveringBracketTimes(const cv::Mat& radiance, double stops, int max_frames = 16,
                                         double max_signal = 0.35, double dark_quantile = 0.02,
                                         double dark_signal = 0.25);

}  // namespace brdfshot
