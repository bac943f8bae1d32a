// A detected sphere in camera terms, and the per-pixel geometry it implies.
//
// Camera frame: looking down −Z, image right = +X, image up = +Y (the frame of
// OrthographicSphere). Orthographic: the silhouette circle is the sphere, every
// view ray is +Z. Perspective: pixel rays through the principal point with focal
// length f; the sphere is the unit sphere at distance 1/sin α along the cone's
// axis (scale does not matter to directions).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "normals/circle_fit.h"
#include "normals/sphere_geometry.h"
#include "util/rotation.h"

namespace brdfshot {

struct SphereView {
  int width = 0, height = 0;  // of the photo
  Circle circle;              // silhouette (orthographic) or apparent circle (perspective)
  bool perspective = false;
  double focal_px = 0;
  cv::Point2d principal;
  SphereCone cone;

  // Normal and direction towards the camera (both unit, camera frame) where the
  // ray through continuous image point (px, py) meets the sphere; false if it
  // misses.
  bool Trace(double px, double py, Vec3* normal, Vec3* view) const;
  // How far inside the silhouette the point is, in pixels (negative outside).
  double RimDistance(double px, double py) const;
  // Pixels that can see the sphere, grown by `margin` px, clipped to the image.
  cv::Rect Bounds(int margin) const;

  nlohmann::json ToJson() const;
  static SphereView FromJson(const nlohmann::json& j, const std::string& source);
};

struct SphereMaskOptions {
  double max_angle_deg = 80;   // drop pixels whose normal is further than this from the view
  double rim_margin_px = 1.5;  // ...and pixels this close to the silhouette (they mix background)
};

// Every pixel whose centre sees the sphere, kept by `options` and not set in
// `exclude` (CV_8U, nonzero = unreliable, e.g. the merge's mask; may be empty),
// with normal and view rotated into the probe frame by `camera_to_probe`.
PixelGeometry SphereViewGeometry(const SphereView& view, const Rotation& camera_to_probe,
                                 const SphereMaskOptions& options, const cv::Mat& exclude = cv::Mat());

}  // namespace brdfshot
