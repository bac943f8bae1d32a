// Robust fits of a sphere's silhouette to edge points.
//
// Image coordinates are continuous: pixel (i, j) covers [i, i+1) × [j, j+1), so
// its centre is (i + ½, j + ½) — the convention of OrthographicSphere.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "util/vec3.h"

namespace brdfshot {

struct Circle {
  double cx = 0, cy = 0, r = 0;
};

// How well a fit explains its points.
struct FitQuality {
  int points = 0, inliers = 0;
  double rms_px = 0;  // RMS residual of the inliers, pixels
};

// Geometric least squares (distance to the circle), started from the algebraic
// (Kåsa) solution and reweighted with Tukey's biweight at 4.685 robust sigmas,
// so edge points from background clutter get zero weight. Throws Error when
// fewer than 5 points or the points are collinear (no circle).
Circle FitCircleRobust(const std::vector<cv::Point2d>& points, FitQuality* quality = nullptr);

// A sphere seen by a perspective camera (focal length `focal_px`, principal
// point `principal`, camera looking down −Z with image up = +Y): its silhouette
// is the cone of rays at angle `half_angle` around `centre_dir` (an ellipse in
// the image). Rays d satisfy d·w = 1 for w = centre_dir / cos(half_angle): the
// fit is linear in w, reweighted as above.
struct SphereCone {
  Vec3 centre_dir;  // unit, camera frame
  double half_angle = 0;
};
Vec3 PixelRay(const cv::Point2d& p, double focal_px, const cv::Point2d& principal);
SphereCone FitConeRobust(const std::vector<cv::Point2d>& points, double focal_px, const cv::Point2d& principal,
                         FitQuality* quality = nullptr);
// Where the cone's axis meets the image, and the silhouette's mean radius there.
Circle ApparentCircle(const SphereCone& cone, double focal_px, const cv::Point2d& principal);

}  // namespace brdfshot
