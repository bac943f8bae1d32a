#include "normals/sphere_view.h"

#include <cmath>

#include "util/check.h"
#include "util/json_int.h"

namespace brdfshot {

bool SphereView::Trace(double px, double py, Vec3* normal, Vec3* view) const {
  if (!perspective) {
    const double x = (px - circle.cx) / circle.r, y = -(py - circle.cy) / circle.r, r2 = x * x + y * y;
    if (r2 >= 1) return false;
    *normal = Vec3(x, y, std::sqrt(1 - r2));
    *view = Vec3(0, 0, 1);
    return true;
  }
  const Vec3 d = PixelRay({px, py}, focal_px, principal);
  const Vec3 c = cone.centre_dir * (1 / std::sin(cone.half_angle));
  const double b = Dot(d, c), disc = b * b - (Dot(c, c) - 1);
  if (disc <= 0) return false;
  const double t = b - std::sqrt(disc);
  *normal = Normalize(d * t - c);
  *view = -d;
  return true;
}

double SphereView::RimDistance(double px, double py) const {
  if (!perspective) return circle.r - std::hypot(px - circle.cx, py - circle.cy);
  const Vec3 d = PixelRay({px, py}, focal_px, principal);
  const double angle = std::acos(std::clamp(Dot(d, cone.centre_dir), -1.0, 1.0));
  // Angular distance to the rim, times the local pixels per radian: f / cos²
  // of the angle off axis along the radial direction.
  const double cos_off = -d.z;
  return (cone.half_angle - angle) * focal_px / (cos_off * cos_off);
}

cv::Rect SphereView::Bounds(int margin) const {
  // Under perspective the rim is an ellipse around the apparent circle, longer
  // by up to r (1 − cos θ_c) radially.
  const double reach = circle.r * (perspective ? 1 + (1 + cone.centre_dir.z) : 1.0) + margin;
  const int x0 = std::max(0, static_cast<int>(circle.cx - reach));
  const int x1 = std::min(width, static_cast<int>(circle.cx + reach) + 1);
  const int y0 = std::max(0, static_cast<int>(circle.cy - reach));
  const int y1 = std::min(height, static_cast<int>(circle.cy + reach) + 1);
  return cv::Rect(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
}

nlohmann::json SphereView::ToJson() const {
  nlohmann::json j = {{"format", "brdfshot-sphere-1"},
                      {"width", width},
                      {"height", height},
                      {"circle", {{"cx", circle.cx}, {"cy", circle.cy}, {"r", circle.r}}},
                      {"camera", perspective ? "perspective" : "orthographic"}};
  if (perspective) {
    j["focal_px"] = focal_px;
    j["principal"] = {principal.x, principal.y};
    j["centre_dir"] = {cone.centre_dir.x, cone.centre_dir.y, cone.centre_dir.z};
    j["half_angle_rad"] = cone.half_angle;
  }
  return j;
}

SphereView SphereView::FromJson(const nlohmann::json& j, const std::string& source) {
  SphereView v;
  try {
    if (j.at("format") != "brdfshot-sphere-1") throw FileError(source, "not a brdfshot sphere file");
    v.width = static_cast<int>(JsonInt(j, "width", 1, 1 << 20, source));
    v.height = static_cast<int>(JsonInt(j, "height", 1, 1 << 20, source));
    v.circle = {j.at("circle").at("cx"), j.at("circle").at("cy"), j.at("circle").at("r")};
    const std::string camera = j.at("camera");
    if (camera != "orthographic" && camera != "perspective")
      throw FileError(source, "camera must be 'orthographic' or 'perspective', not '" + camera + "'");
    v.perspective = camera == "perspective";
    if (v.perspective) {
      v.focal_px = j.at("focal_px");
      v.principal = {j.at("principal").at(0), j.at("principal").at(1)};
      v.cone.centre_dir = Vec3(j.at("centre_dir").at(0), j.at("centre_dir").at(1), j.at("centre_dir").at(2));
      v.cone.half_angle = j.at("half_angle_rad");
    }
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("incomplete sphere file: ") + e.what());
  }
  if (v.width <= 0 || v.height <= 0 || !(v.circle.r > 0) || !std::isfinite(v.circle.cx) || !std::isfinite(v.circle.cy))
    throw FileError(source, "sphere file has no valid circle or image size");
  if (v.perspective && (!(v.focal_px > 0) || !(v.cone.half_angle > 0 && v.cone.half_angle < kPi / 2) ||
                        std::abs(Length(v.cone.centre_dir) - 1) > 1e-6))
    throw FileError(source, "sphere file has an invalid perspective cone");
  return v;
}

PixelGeometry SphereViewGeometry(const SphereView& v, const Rotation& camera_to_probe, const SphereMaskOptions& o,
                                 const cv::Mat& exclude) {
  BRDFSHOT_CHECK(exclude.empty() || (exclude.type() == CV_8U && exclude.cols == v.width && exclude.rows == v.height),
                 "exclusion mask must be CV_8U of the photo's size");
  PixelGeometry g;
  g.width = v.width;
  g.height = v.height;
  const double cos_max = std::cos(o.max_angle_deg * kPi / 180);
  const cv::Rect box = v.Bounds(2);
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      Vec3 n, w;
      if (!v.Trace(x + 0.5, y + 0.5, &n, &w)) continue;
      if (Dot(n, w) < cos_max || v.RimDistance(x + 0.5, y + 0.5) < o.rim_margin_px) continue;
      if (!exclude.empty() && exclude.at<uint8_t>(y, x)) continue;
      g.x.push_back(x);
      g.y.push_back(y);
      g.normal.push_back(camera_to_probe(n));
      g.view.push_back(camera_to_probe(w));
    }
  return g;
}

}  // namespace brdfshot
