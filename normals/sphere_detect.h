// Finding a sphere in a photo: coarse then sub-pixel.
//
//  1. Coarse: OpenCV's HoughCircles (gradient-alt) on a log-luminance copy
//     reduced to ≤ 512 px (and, when that finds no sphere, on its colour
//     ratios too), candidates ranked by how many radial rays find an edge
//     near their rim (clutter makes circles too; a sphere's rim is closed).
//  2. Sub-pixel: along `rays` radial profiles through the full-resolution
//     image (luminance; in the colour fallback each ray's colour projected on
//     its own step, so a rim in colour counts as one in luminance), the edge is the
//     peak of the profile's derivative, interpolated by a parabola, then the
//     rim model's (rim_profile.h); the points are fitted robustly
//     (FitCircleRobust, or the perspective cone when the focal length is
//     known). Three passes, each in a narrower band around the last fit.
//
// Why log luminance: an HDR photo spans many stops; in log the sphere's rim
// has the same contrast in a dark corner and next to a window.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "normals/circle_fit.h"
#include "util/check.h"

namespace brdfshot {

struct SphereDetectOptions {
  int coarse_max_side = 512;  // the Hough search runs on a copy this small
  double min_radius = 0.04;   // of the image's shorter side
  double max_radius = 0.5;
  int rays = 720;                 // radial profiles for the sub-pixel edge
  double focal_px = 0;            // > 0: perspective model (silhouette is an ellipse)
  cv::Point2d principal{-1, -1};  // default: image centre
  // When the photo holds several spheres, the one around this pixel
  // (continuous coordinates). Default (negative): the photo must hold one.
  cv::Point2d near{-1, -1};
  // Pick each ray's edge in log luminance (see DetectSphere). Off: tried when
  // the linear picks find no sphere.
  bool log_edges = false;
  // Rims in colour: coarse circles from the colour ratios log(R/G), log(B/G)
  // as well as from log luminance, and each ray's profile projected on its
  // colour step instead of luminance. Off: tried when luminance finds no
  // sphere (JPEG's colour has half its resolution).
  bool colour_rims = false;
};

struct SphereDetection {
  Circle coarse;  // Hough's circle, full-resolution pixels
  Circle circle;  // refined: the silhouette (orthographic) or the cone's apparent circle
  bool perspective = false;
  SphereCone cone;  // perspective only
  double focal_px = 0;
  cv::Point2d principal;
  FitQuality quality;
  double blur_sigma = 0;                 // optical blur at the rim, px (rim model)
  bool rim_in_shadow = false;            // found only by log-luminance edges: expect ~0.5 px, not ~0.1 px
  std::vector<cv::Point2d> edge_points;  // of the last pass, for pictures
};

// Single-channel float log luminance of an RGB image (any depth), floored at
// 1 % of its 99th percentile so the noise of a black background is not
// magnified into edges.
cv::Mat LogLuminance(const cv::Mat& rgb);

// "no sphere found ...": no candidate has a closed rim.
class NoSphereFound : public Error {
 public:
  using Error::Error;
};

// Throws NoSphereFound when no candidate has a closed rim, and
// Error("two spheres found ...") when a second, separate candidate is shaded
// like a sphere and passes the same rim test (unless options.near picks one).
// Edges are picked on linear profiles (a blurred step's steepest point is the
// step); when that finds no sphere or fits its rim only marginally, again in
// log luminance, which finds a rim partly in attached shadow, and the better
// fit wins (rim_in_shadow is then set; DiLiGenT's ball: 29 of its 96 lights
// found linearly, 89 with log edges, all within 0.9 px). When neither finds
// a sphere, both again with colour_rims.
SphereDetection DetectSphere(const cv::Mat& rgb, const SphereDetectOptions& options = {});

// Edge points along `rays` radial profiles of `image` (float, one channel or
// RGB — then the luminance, or with `colour` per ray the colour projection
// that shows its step best; luminance for log picks)
// between radii r_lo and r_hi around `centre` (continuous coordinates): the
// steepest point of each, or — when `rim_blur` is given — the rim model's fit
// (rim_profile.h) around it, with the blur it estimated written there. Rays
// whose strongest step is weaker than a quarter of the median ray's are dropped.
// `log_pick`: the steepest point in log luminance instead (its strength still
// linear), for rims whose linear steepest point is a shading terminator.
std::vector<cv::Point2d> RadialEdgePoints(const cv::Mat& image, const cv::Point2d& centre, double r_lo, double r_hi,
                                          int rays, double* rim_blur = nullptr, bool log_pick = false,
                                          bool colour = false);

// OpenCV's HoughCircles on the reduced log luminance (and colour ratios with
// options.colour_rims) of an RGB image: the coarse candidates. Empty
// vector if it finds nothing.
std::vector<Circle> HoughCandidates(const cv::Mat& rgb, const SphereDetectOptions& options);

}  // namespace brdfshot
