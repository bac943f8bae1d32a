#include "calib/radiometric_scale.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <string>

#include "capture/merge_sidecar.h"
#include "capture/response.h"
#include "util/check.h"

namespace brdfshot {

cv::Vec3d Irradiance(const LatLongProbe& probe, const Vec3& normal) {
  BRDFSHOT_CHECK(Length(normal) > 0, "irradiance needs a non-zero normal");
  const Vec3 n = Normalize(normal);
  cv::Vec3d e(0, 0, 0);
  for (int r = 0; r < probe.height(); ++r) {
    const double omega = probe.TexelSolidAngle(r);
    for (int c = 0; c < probe.width(); ++c) {
      const double cosine = Dot(n, probe.DirectionAt(c + 0.5, r + 0.5));
      if (cosine <= 0) continue;
      const cv::Vec3f l = probe.Texel(c, r);
      for (int k = 0; k < 3; ++k) e[k] += l[k] * cosine * omega;
    }
  }
  return e;
}

RadiometricScale ScaleFromReferenceCard(const cv::Mat& photo, const ReferenceCard& card, const LatLongProbe& probe,
                                        const Rotation& camera_to_probe) {
  BRDFSHOT_CHECK(photo.type() == CV_32FC3, "reference card: photo must be CV_32FC3");
  const cv::Rect& r = card.region;
  const std::string where = "reference card region " + std::to_string(r.x) + "," + std::to_string(r.y) + "," +
                            std::to_string(r.width) + "," + std::to_string(r.height);
  if (r.width <= 0 || r.height <= 0 || (r & cv::Rect(0, 0, photo.cols, photo.rows)) != r)
    throw Error(where + " is empty or leaves the " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows) +
                " photo");
  if (!(card.albedo > 0 && card.albedo <= 1)) throw Error("reference card albedo must be in (0, 1]");
  RadiometricScale s;
  // Mean and luminance spread in double: a 12 MP card region sums millions of floats.
  cv::Vec3d sum(0, 0, 0);
  double lum_sum = 0, lum_sq = 0;
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) {
      const cv::Vec3f v = photo.at<cv::Vec3f>(y, x);
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) continue;
      const double lum = (v[0] + v[1] + v[2]) / 3;
      for (int k = 0; k < 3; ++k) sum[k] += v[k];
      lum_sum += lum, lum_sq += lum * lum;
      ++s.pixels;
    }
  if (s.pixels == 0) throw Error(where + " holds no finite pixel");
  s.measured = sum / s.pixels;
  if (!(s.measured[0] > 0 && s.measured[1] > 0 && s.measured[2] > 0))
    throw Error(where + " is black in some channel: not a lit card");
  const double mean = lum_sum / s.pixels;
  s.spread = std::sqrt(std::max(0.0, lum_sq / s.pixels - mean * mean)) / mean;
  const cv::Vec3d e = Irradiance(probe, camera_to_probe(card.normal_camera));
  for (int k = 0; k < 3; ++k) {
    if (!(e[k] > 0))
      throw Error("the probe sends no light onto the reference card (normal " + std::to_string(card.normal_camera.x) +
                  "," + std::to_string(card.normal_camera.y) + "," + std::to_string(card.normal_camera.z) +
                  " in the camera frame): check the rotation and the normal");
    s.predicted[k] = card.albedo / kPi * e[k];
    s.scale[k] = s.measured[k] / s.predicted[k];
  }
  return s;
}

RadiometricScale ScaleFromMergeSidecars(const nlohmann::json& photo_json, const std::string& photo_source,
                                        const nlohmann::json& probe_json, const std::string& probe_source) {
  const MergeSidecar photo = MergeSidecar::FromJson(photo_json, photo_source);
  const MergeSidecar probe = MergeSidecar::FromJson(probe_json, probe_source);
  const cv::Vec3d photo_wb = photo.WhiteBalance(photo_source), probe_wb = probe.WhiteBalance(probe_source);
  if (!photo.camera.empty() && !probe.camera.empty() && photo.camera != probe.camera)
    throw FileError(photo_source, "is from camera '" + photo.camera + "', " + probe_source + " from '" + probe.camera +
                                      "': exposure metadata cannot relate two cameras' "
                                      "sensitivities; measure the scale on a reference card (--card)");
  if (photo.raw != probe.raw)
    throw FileError(photo_source, std::string("is ") + (photo.raw ? "RAW" : "developed") + ", " + probe_source +
                                      " is " + (probe.raw ? "RAW" : "developed") +
                                      ": their processing differs; measure the scale on a reference card (--card)");
  RadiometricScale s;
  if (photo.raw) {
    for (int c = 0; c < 3; ++c) s.scale[c] = photo_wb[c] / probe_wb[c];
    return s;
  }
  if (photo.response.levels != probe.response.levels)
    throw FileError(photo_source, "has " + std::to_string(photo.response.levels) + " code levels, " + probe_source +
                                      " " + std::to_string(probe.response.levels));
  // Ratio of the curves over the middle 60 % of the codes, where both are
  // well constrained by their brackets; the median per channel.
  const int lo = photo.response.levels / 5, hi = photo.response.levels * 4 / 5;
  const int step = std::max(1, (hi - lo) / 256);
  double rmin = std::numeric_limits<double>::infinity(), rmax = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> ratio;
    for (int z = lo; z <= hi; z += step) {
      const double a = photo.response.Linear(c, z), b = probe.response.Linear(c, z);
      if (a > 0 && b > 0) ratio.push_back(a / b);
    }
    if (ratio.empty()) throw FileError(photo_source, "response curve has no positive mid codes");
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    s.scale[c] = ratio[ratio.size() / 2];
    for (double r : ratio) rmin = std::min(rmin, r / s.scale[c]), rmax = std::max(rmax, r / s.scale[c]);
  }
  s.spread = rmax / rmin - 1;
  return s;
}

}  // namespace brdfshot
