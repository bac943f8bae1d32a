// Sphere detection measured against known truth, beside OpenCV's
// HoughCircles alone, in one run (`brdfshot bench-detect`). Scenes are
// normals/synthetic_sphere renders (cluttered background, optical blur,
// sensor noise; orthographic or perspective) with random centre and radius per
// seed, at each image size.
//
// "Hough alone" is cv::HoughCircles (HOUGH_GRADIENT_ALT) on the full-resolution
// 8-bit log luminance, scored by its strongest circle — what a user gets from
// OpenCV without our coarse ranking and sub-pixel stages. Errors: centre
// distance and |radius difference| in pixels (perspective: of the silhouette
// cone's axis and half-angle, times the focal length); medians and maxima over
// the seeds; times are medians.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "normals/circle_fit.h"

namespace brdfshot {

struct DetectBenchmarkOptions {
  std::vector<cv::Size> sizes{{640, 480}, {4000, 3000}};
  int seeds = 8;              // scenes per size and camera
  double noise = 0.01;        // additive Gaussian (image values ~0.05 … 1)
  double blur = 1.2;          // optical blur sigma, px
  int clutter = 30;           // background shapes
  double focal_factor = 1.4;  // perspective focal length, in image widths
  bool verbose = false;       // every scene's truth and detection on stderr
  std::string dump;           // "" or a folder for every scene as a tone-mapped PNG
  bool progress = false;
};

struct DetectBenchmarkRow {
  cv::Size size;
  bool perspective = false;
  std::string method;                                                           // "ours" | "HoughCircles alone"
  double centre_median = 0, centre_max = 0, radius_median = 0, radius_max = 0;  // px
  int misses = 0, scenes = 0;
  double seconds_median = 0;
};

std::vector<DetectBenchmarkRow> RunDetectBenchmark(const DetectBenchmarkOptions& options);

// The rows as a markdown table.
std::string DetectBenchmarkTable(const std::vector<DetectBenchmarkRow>& rows);

// cv::HoughCircles alone on the full-resolution log luminance: its strongest
// circle (pixel centres at +½, as ours), {0, 0, 0} when it finds none.
Circle HoughAlone(const cv::Mat& rgb, double min_radius, double max_radius);

}  // namespace brdfshot
