// Test scenes with a known sphere: a shaded ball over a cluttered background,
// anti-aliased exactly (edge pixels supersampled 16×16), then optical blur and
// sensor noise. The truth the detector is measured against (tests and
// `brdfshot bench-detect`).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "normals/circle_fit.h"

namespace brdfshot {

struct SyntheticSphereScene {
  int width = 640, height = 480;
  Circle circle{320, 240, 150};  // orthographic silhouette (continuous coords)
  // Perspective instead when focal_px > 0: a unit sphere centred at `centre`
  // (camera frame, camera looking down −Z), principal point at the image centre.
  double focal_px = 0;
  Vec3 centre{0, 0, -10};
  double blur_sigma = 1.0;  // px, Gaussian optical blur
  double noise = 0.01;      // additive Gaussian, image values are ~0.05 … 1
  int clutter = 30;         // random rectangles, discs and rings behind the sphere
  // A second ball, orthographic, drawn like the first when its radius is > 0
  // (a photo the detector must refuse as ambiguous).
  Circle second_sphere{0, 0, 0};
  uint64_t seed = 1;
};

// CV_32FC3 RGB.
cv::Mat RenderSyntheticSphere(const SyntheticSphereScene& scene);

// The true silhouette of a perspective scene as a cone (for error reports).
SphereCone TrueCone(const SyntheticSphereScene& scene);

}  // namespace brdfshot
