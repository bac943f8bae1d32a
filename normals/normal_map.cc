#include "normals/normal_map.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "normals/circle_fit.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {

cv::Mat DecodeNormalMap(const cv::Mat& rgb) {
  if (rgb.channels() != 3)
    throw Error("a normal map needs 3 channels (x, y, z), not " + std::to_string(rgb.channels()));
  cv::Mat n;
  switch (rgb.depth()) {
    case CV_8U:
      rgb.convertTo(n, CV_32F, 2.0 / 255, -1);
      break;
    case CV_16U:
      rgb.convertTo(n, CV_32F, 2.0 / 65535, -1);
      break;
    case CV_32F:
      n = rgb.clone();
      break;
    default:
      throw Error("a normal map must be 8-bit, 16-bit or float");
  }
  for (int y = 0; y < n.rows; ++y)
    for (int x = 0; x < n.cols; ++x) {
      cv::Vec3f& v = n.at<cv::Vec3f>(y, x);
      const float len = static_cast<float>(cv::norm(v));
      v = std::isfinite(len) && len > 0.5f && len < 1.5f ? v / len : cv::Vec3f(0, 0, 0);
    }
  return n;
}

PixelGeometry NormalMapGeometry(const cv::Mat& normals, const cv::Mat& mask, const NormalMapOptions& o,
                                const Rotation& camera_to_probe, const cv::Mat& exclude) {
  BRDFSHOT_CHECK(normals.type() == CV_32FC3, "normal map must be decoded (DecodeNormalMap)");
  if (!mask.empty() && (mask.type() != CV_8U || mask.size() != normals.size()))
    throw Error("the mask must be a single-channel image of the normal map's size");
  if (!exclude.empty() && (exclude.type() != CV_8U || exclude.size() != normals.size()))
    throw Error("the exclusion mask must be a single-channel image of the normal map's size");
  // The object: the mask, or every pixel that has a normal; then shrunk.
  cv::Mat object = mask.empty() ? cv::Mat(normals.size(), CV_8U, cv::Scalar(255)) : (mask != 0);
  for (int y = 0; y < normals.rows; ++y)
    for (int x = 0; x < normals.cols; ++x)
      if (normals.at<cv::Vec3f>(y, x) == cv::Vec3f(0, 0, 0)) object.at<uint8_t>(y, x) = 0;
  if (o.erode_px > 0)
    cv::erode(object, object, cv::Mat(), cv::Point(-1, -1), o.erode_px, cv::BORDER_CONSTANT, cv::Scalar(0));
  const cv::Point2d principal = o.principal.x >= 0 ? o.principal : cv::Point2d(normals.cols / 2.0, normals.rows / 2.0);
  const double cos_max = std::cos(o.max_angle_deg * kPi / 180);
  PixelGeometry g;
  g.width = normals.cols;
  g.height = normals.rows;
  for (int y = 0; y < normals.rows; ++y)
    for (int x = 0; x < normals.cols; ++x) {
      if (!object.at<uint8_t>(y, x) || (!exclude.empty() && exclude.at<uint8_t>(y, x))) continue;
      const cv::Vec3f& v = normals.at<cv::Vec3f>(y, x);
      const Vec3 n = Normalize(Vec3(v[0], v[1], v[2]));  // unit in double: float storage is not
      const Vec3 view = o.focal_px > 0 ? -PixelRay({x + 0.5, y + 0.5}, o.focal_px, principal) : Vec3(0, 0, 1);
      if (Dot(n, view) < cos_max) continue;
      g.x.push_back(x);
      g.y.push_back(y);
      g.normal.push_back(camera_to_probe(n));
      g.view.push_back(camera_to_probe(view));
    }
  return g;
}

cv::Mat ReadNormalMap(const std::string& path) {
  const cv::Mat rgb = ReadImageRgb(path, "normal map");
  try {
    return DecodeNormalMap(rgb);
  } catch (const Error& e) {
    throw FileError(path, e.what());
  }
}

}  // namespace brdfshot
