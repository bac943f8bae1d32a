// What `normals` makes of a photo: the photo read as detection wants it, the
// detected sphere as a SphereView and its sphere file, the share of its rim
// outside the frame, its normal map and a picture of the detection.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "normals/sphere_detect.h"
#include "normals/sphere_view.h"

namespace brdfshot {

// RGB float: HDR files (EXR/HDR/PFM) as stored, 8/16-bit images as their
// codes (detection needs edges, not radiance). FileError naming the file.
cv::Mat ReadPhotoForDetection(const std::string& path);

// A detection in the photo at `photo_path` (for messages): the sphere, its
// view, the detector's wall time, and what the user should know about it.
struct SphereInPhoto {
  SphereDetection detection;
  SphereView view;
  double seconds = 0;
  std::vector<std::string> warnings;  // a rim in shadow, a sphere cut by the border
};

// FileError naming the photo when no single sphere is found.
SphereInPhoto FindSphereInPhoto(const cv::Mat& rgb, const SphereDetectOptions& options, const std::string& photo_path);

// The sphere a detection found, in a photo of `size`.
SphereView ViewOfDetection(const SphereDetection& det, cv::Size size);

// The sphere file: the view, the photo it was found in, and how the rim fit
// went (points, inliers, rms, blur, the coarse circle, seconds).
nlohmann::json SphereFileJson(const SphereView& v, const SphereDetection& det, const std::string& photo,
                              double seconds);

// Percent of the circle's rim outside a photo of `size` (0: fully inside),
// rounded up so any cut shows.
int RimOutsidePercent(const Circle& c, cv::Size size);

// Per pixel the sphere's normal (camera frame, float RGB = xyz), 0 off the
// sphere: what `remap --normal-map` reads for other shapes.
cv::Mat NormalMapOf(const SphereView& v);

// The photo tonemapped, the rim points used (green) and the fitted rim (red): BGR 8-bit.
cv::Mat DetectionOverlay(const cv::Mat& rgb, const SphereDetection& det);

}  // namespace brdfshot
