// HDR merging measured against ground truth, side by side with OpenCV (and
// pfstools when installed) in one run (`brdfshot bench-merge`). Real HDR maps
// are the scenes; a known camera (response with a shoulder, shot and read
// noise, clipping, 8-bit rounding, optionally JPEG; or linear 12-bit RAW-like)
// makes the brackets; each method recovers its response from the frames and
// merges. Error is measured where the bracket could measure the truth at all,
// after a per-channel scale (responses are only known up to one).
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "capture/synthetic_bracket.h"

namespace brdfshot {

struct MergeErrorStats {
  double median = 0, p95 = 0, mean = 0;  // |scale · merged / truth − 1| over measurable samples
  double bad_fraction = 0;               // non-finite or ≤ 0 where the truth was measurable
  // What a light probe is for: each channel's total power over the measurable
  // pixels, after the same scale, against the truth's (the worst channel). A
  // few wrong pixels (a sun) leave the median alone and move this.
  double power = 0;
  // Colour, apart from brightness: the median distance between the rg
  // chromaticities of the scaled merge and the truth, over pixels measurable
  // in all three channels, and over the darkest 20 % of them (by the truth's
  // luminance), where every frame is noisy.
  double chroma = 0, shadow_chroma = 0;
  double speckle = 0;  // ChromaSpeckle of the merge (capture/merge_quality.h)
};

// Per sample (CV_8UC3, 1/0): some frame measured the truth — not clipped in
// the shortest exposure, above 20× the read noise in the longest.
cv::Mat MeasurableMask(const cv::Mat& truth, const std::vector<double>& times, const CameraModel& camera);

// `merged`, `truth`: CV_32FC3. Each channel is scaled by the median of
// truth / merged over its measurable samples first. `speckle` is left 0.
MergeErrorStats CompareToTruth(const cv::Mat& merged, const cv::Mat& truth, const cv::Mat& measurable);

struct MergeMethod {
  std::string key, name;
  bool raw;  // works on the RAW-like brackets (else 8-bit)
  // The merged radiance (CV_32FC3) of RGB frames at `times`; empty when the
  // method is not available here (pfstools not installed).
  std::function<cv::Mat(const std::vector<cv::Mat>& rgb, const std::vector<double>& times)> merge;
};

// Every method the benchmark knows; `jpeg`: the 8-bit frames went through
// JPEG, and ours treats them as the merge command treats .jpg files.
std::vector<MergeMethod> MergeMethods(const CameraModel& camera, bool jpeg);

struct MergeBenchmarkOptions {
  std::vector<std::string> scenes;  // HDR images
  cv::Size size{4000, 3000};        // the scenes are resampled to this (12 MP)
  int frames = 9;
  double stops = 1;
  CameraModel camera;
  int jpeg_quality = 0;  // > 0: 8-bit frames through JPEG at this quality
  // Every exposure shifted by this many EV from the bracket that covers the
  // scene: < 0 leaves the shadows below the longest frame's noise floor, as
  // in a night bracket exposed for its lights.
  double exposure_shift_ev = 0;
  std::vector<std::string> methods;  // keys of MergeMethods
  bool progress = false;             // a line per scene and method on stdout
};

struct MergeBenchmarkTables {
  std::string markdown, csv;  // per scene and method, then the summary per method
};

// Error naming an unknown method.
MergeBenchmarkTables RunMergeBenchmark(const MergeBenchmarkOptions& options);

}  // namespace brdfshot
