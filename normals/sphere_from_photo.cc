#include "normals/sphere_from_photo.h"

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "util/check.h"
#include "util/progress.h"
#include "util/image_io.h"

namespace brdfshot {

cv::Mat ReadPhotoForDetection(const std::string& path) {
  cv::Mat rgb = ReadImageRgb(path);
  rgb.convertTo(rgb, CV_32FC3);  // HDR files are float already: a no-op there
  return rgb;
}

SphereView ViewOfDetection(const SphereDetection& det, cv::Size size) {
  SphereView v;
  v.width = size.width;
  v.height = size.height;
  v.circle = det.circle;
  v.perspective = det.perspective;
  v.focal_px = det.focal_px;
  v.principal = det.principal;
  v.cone = det.cone;
  return v;
}

nlohmann::json SphereFileJson(const SphereView& v, const SphereDetection& det, const std::string& photo,
                              double seconds) {
  nlohmann::json j = v.ToJson();
  j["photo"] = photo;
  j["fit"] = {{"edge_points", det.quality.points},
              {"inliers", det.quality.inliers},
              {"rms_px", det.quality.rms_px},
              {"rim_in_shadow", det.rim_in_shadow},
              {"blur_sigma_px", det.blur_sigma},
              {"coarse", {det.coarse.cx, det.coarse.cy, det.coarse.r}},
              {"seconds", seconds}};
  return j;
}

SphereInPhoto FindSphereInPhoto(const cv::Mat& rgb, const SphereDetectOptions& options, const std::string& photo) {
  SphereInPhoto r;
  Stopwatch sw;
  try {
    r.detection = DetectSphere(rgb, options);
  } catch (const Error& e) {
    throw FileError(photo, e.what());
  }
  r.seconds = sw.Seconds();
  if (r.detection.rim_in_shadow)
    r.warnings.push_back(photo +
                         ": part of the sphere's rim is in shadow; found from log-luminance edges, expect ~0.5 px "
                         "instead of ~0.1 px (a photo lit from the camera's side measures it better)");
  // A sphere cut by the border is still measured (the visible rim fixes the
  // circle), but the user should know part of it is missing.
  if (const int outside = RimOutsidePercent(r.detection.circle, rgb.size()); outside > 0)
    r.warnings.push_back(photo + ": the sphere is cut by the image border (" + std::to_string(outside) +
                         " % of its rim outside); the fit uses the visible rim");
  r.view = ViewOfDetection(r.detection, rgb.size());
  return r;
}

int RimOutsidePercent(const Circle& c, cv::Size size) {
  int outside = 0;
  for (int k = 0; k < 360; ++k) {
    const double a = 2 * kPi * k / 360, x = c.cx + c.r * std::cos(a), y = c.cy + c.r * std::sin(a);
    outside += x < 0 || y < 0 || x > size.width || y > size.height;
  }
  return (outside * 100 + 359) / 360;
}

cv::Mat NormalMapOf(const SphereView& v) {
  cv::Mat map(v.height, v.width, CV_32FC3, cv::Scalar::all(0));
  const cv::Rect box = v.Bounds(2);
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      Vec3 normal, view;
      if (v.Trace(x + 0.5, y + 0.5, &normal, &view))
        map.at<cv::Vec3f>(y, x) = cv::Vec3f(float(normal.x), float(normal.y), float(normal.z));
    }
  return map;
}

cv::Mat DetectionOverlay(const cv::Mat& rgb, const SphereDetection& det) {
  cv::Mat png = TonemapToBgr8(rgb, AutoExposure(rgb));
  for (const auto& p : det.edge_points) cv::circle(png, cv::Point(int(p.x), int(p.y)), 1, {0, 200, 0}, cv::FILLED);
  // 4 fractional bits: the rim drawn at its sub-pixel position.
  cv::circle(png, cv::Point(int(det.circle.cx * 16), int(det.circle.cy * 16)), int(det.circle.r * 16), {0, 0, 255}, 1,
             cv::LINE_AA, 4);
  return png;
}

}  // namespace brdfshot
