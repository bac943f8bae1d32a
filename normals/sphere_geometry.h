// Per-pixel geometry of a visible sphere: which pixels see it, their unit normal
// and the unit direction towards the camera (ω_o), all in the probe frame.
// This is the contract between normals/ and fit/: basis images and observations
// are indexed by the same pixel list.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "util/vec3.h"

namespace brdfshot {

struct PixelGeometry {
  int width = 0, height = 0;  // image the pixels live in
  std::vector<int> x, y;      // pixel coordinates
  std::vector<Vec3> normal;   // unit, probe frame
  std::vector<Vec3> view;     // unit, towards the camera, probe frame
  size_t size() const { return x.size(); }
  uint64_t Hash() const;  // keys basis-image caches
};

// An orthographic camera at +Z looking down −Z (image up = +Y) at a unit sphere
// filling a `resolution`² image. Pixels whose normal is more than `max_angle_deg`
// from the view are dropped: at the silhouette a pixel mixes sphere and
// background, and its ω_o is grazing (the MERL table is noisiest there).
PixelGeometry OrthographicSphere(int resolution, double max_angle_deg = 80.0);

// Scatters per-pixel RGB values (pixels × 3) back into a CV_32FC3 image of the
// geometry's size; pixels not in the list stay black.
cv::Mat PixelsToImage(const PixelGeometry& g, const Eigen::MatrixXd& rgb);

// Every `step`-th pixel in x and y — for solving on fewer pixels than were shot.
PixelGeometry Subsample(const PixelGeometry& g, int step);

}  // namespace brdfshot
