#include "calib/sun_probe.h"

#include <cmath>

#include "util/check.h"

namespace brdfshot {

LatLongProbe SunProbe(const Vec3& direction, const cv::Vec3f& irradiance, double radius_deg, int width) {
  if (!(Length(direction) > 0)) throw Error("the light direction must not be zero");
  for (int c = 0; c < 3; ++c)
    if (!(irradiance[c] >= 0)) throw Error("the light intensity must be non-negative and finite");
  BRDFSHOT_CHECK(width >= 8 && width % 2 == 0, "SunProbe width must be even and >= 8");
  const Vec3 d = Normalize(direction);
  LatLongProbe probe(cv::Mat(width / 2, width, CV_32FC3, cv::Scalar::all(0)), "sun");
  // Texels whose centre lies within the disc; the nearest one if none does
  // (a disc smaller than a texel).
  const double cos_r = std::cos(radius_deg * kPi / 180);
  double omega = 0, best = -2;
  cv::Point nearest;
  std::vector<cv::Point> lit;
  for (int row = 0; row < probe.height(); ++row)
    for (int col = 0; col < probe.width(); ++col) {
      const double c = Dot(probe.DirectionAt(col + 0.5, row + 0.5), d);
      if (c > best) best = c, nearest = {col, row};
      if (c >= cos_r) lit.push_back({col, row}), omega += probe.TexelSolidAngle(row);
    }
  if (lit.empty()) lit.push_back(nearest), omega = probe.TexelSolidAngle(nearest.y);
  cv::Mat rgb = probe.rgb().clone();
  for (const cv::Point& p : lit) rgb.at<cv::Vec3f>(p) = irradiance * static_cast<float>(1 / omega);
  return LatLongProbe(rgb, "sun");
}

LatLongProbe SunOverSkyProbe(const Vec3& direction, const cv::Vec3f& irradiance, const cv::Vec3f& sky_radiance,
                             double radius_deg, int width) {
  for (int c = 0; c < 3; ++c)
    if (!(sky_radiance[c] >= 0)) throw Error("the sky radiance must be non-negative and finite");
  cv::Mat rgb = SunProbe(direction, irradiance, radius_deg, width).rgb().clone();
  const LatLongProbe frame(rgb, "sun");
  for (int row = 0; row < frame.height(); ++row)
    if (frame.DirectionAt(0, row + 0.5).y > 0)
      for (int col = 0; col < frame.width(); ++col) rgb.at<cv::Vec3f>(row, col) += sky_radiance;
  return LatLongProbe(rgb, "sun");
}

}  // namespace brdfshot
