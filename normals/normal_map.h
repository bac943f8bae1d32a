// Per-pixel geometry of any convex object from a normal map the user supplies
// (photometric stereo, a scan, a render of its CAD model) instead of a
// detected sphere. Normals are in the camera frame of sphere_view.h: x right,
// y up, z towards the camera (DiLiGenT's Normal_gt convention).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "normals/sphere_geometry.h"
#include "util/rotation.h"

namespace brdfshot {

// An image of normals as stored: float (EXR, PFM: x, y, z in R, G, B as they
// are) or 8/16-bit (n = 2 v / max − 1, the usual PNG encoding), RGB order.
// Returns CV_32FC3 of unit normals; a pixel whose stored vector is far from
// unit length (|n| outside 0.5…1.5, e.g. a black background) becomes (0, 0, 0).
cv::Mat DecodeNormalMap(const cv::Mat& rgb);

// A normal map as the user gives it: 8/16-bit PNG ((n + 1)/2) or float
// EXR/HDR/PFM, decoded by DecodeNormalMap; FileError naming the file.
cv::Mat ReadNormalMap(const std::string& path);

struct NormalMapOptions {
  double focal_px = 0;            // > 0: pinhole camera (view = −pixel ray); 0: orthographic (view = +Z)
  cv::Point2d principal{-1, -1};  // default: the image centre
  double max_angle_deg = 80;      // drop pixels whose normal is further than this from the view
  int erode_px = 1;               // the mask shrunk by this many pixels: its edge mixes background
};

// Every pixel with a normal, set in `mask` (CV_8U, nonzero = object; empty:
// every pixel with a normal) after erosion, not set in `exclude` (may be
// empty), kept by the view angle; normal and view rotated into the probe
// frame. Error when the mask or exclusion is not the normal map's size.
PixelGeometry NormalMapGeometry(const cv::Mat& normals, const cv::Mat& mask, const NormalMapOptions& options,
                                const Rotation& camera_to_probe, const cv::Mat& exclude = cv::Mat());

}  // namespace brdfshot
