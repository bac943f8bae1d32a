#include "calib/probe_layout.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace brdfshot {
LatLongProbe AngularMapToLatLong(const cv::Mat& angular, int width) {
  BRDFSHOT_CHECK(angular.type() == CV_32FC3 && angular.cols == angular.rows && width >= 4 && width % 2 == 0);
  const int height = width / 2, size = angular.cols;
  cv::Mat mapx(height, width, CV_32F), mapy(height, width, CV_32F);
  const LatLongProbe frame(cv::Mat(height, width, CV_32FC3, cv::Scalar::all(0)));
  for (int row = 0; row < height; ++row)
    for (int col = 0; col < width; ++col) {
      const Vec3 d = frame.DirectionAt(col + 0.5, row + 0.5);
      const double r = std::acos(std::clamp(-d.z, -1.0, 1.0)) / kPi, len = std::hypot(d.x, d.y);
      const double u = len > 0 ? r * d.x / len : 0, v = len > 0 ? r * d.y / len : 0;
      mapx.at<float>(row, col) = static_cast<float>((u + 1) / 2 * size - 0.5);
      mapy.at<float>(row, col) = static_cast<float>((1 - v) / 2 * size - 0.5);
    }
  cv::Mat out;
  cv::remap(angular, out, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return LatLongProbe(out, "angular map");
}

cv::Mat LatLongToAngularMap(const LatLongProbe& probe, int size) {
  cv::Mat out(size, size, CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = 2 * (x + 0.5) / size - 1, v = 1 - 2 * (y + 0.5) / size, r = std::hypot(u, v);
      if (r > 1) continue;
      const double theta = r * kPi;  // angle from −Z
      const double s = r > 0 ? std::sin(theta) / r : 0;
      out.at<cv::Vec3f>(y, x) = probe.Bilinear(Vec3(u * s, v * s, -std::cos(theta)));
    }
  return out;
}

cv::Mat FillHoles(const cv::Mat& rgb, const cv::Mat& known) {
  BRDFSHOT_CHECK(rgb.type() == CV_32FC3 && known.type() == CV_8U && known.size() == rgb.size());
  // Push–pull: average the known texels down a pyramid until every cell has
  // some, then fill each level's holes from the level above. Smooth, bounded
  // by the known values, and fast; a probe's missing cap needs no more.
  cv::Mat w;
  known.convertTo(w, CV_32F, 1.0 / 255);
  std::vector<cv::Mat> wsum = {w}, vsum;
  {
    std::vector<cv::Mat> w3 = {w, w, w};
    cv::Mat w3m;
    cv::merge(w3, w3m);
    vsum.push_back(rgb.mul(w3m));
  }
  while (wsum.back().cols > 1 && wsum.back().rows > 1) {
    double lo;
    cv::minMaxLoc(wsum.back(), &lo);
    if (lo > 0) break;
    cv::Mat w2, v2;
    const cv::Size half((wsum.back().cols + 1) / 2, (wsum.back().rows + 1) / 2);
    cv::resize(wsum.back(), w2, half, 0, 0, cv::INTER_AREA);
    cv::resize(vsum.back(), v2, half, 0, 0, cv::INTER_AREA);
    wsum.push_back(w2);
    vsum.push_back(v2);
  }
  // Top level: normalised average (cells with no weight at all get 0).
  auto normalised = [](const cv::Mat& v, const cv::Mat& w) {
    cv::Mat out(v.size(), CV_32FC3);
    for (int y = 0; y < v.rows; ++y)
      for (int x = 0; x < v.cols; ++x) {
        const float ww = w.at<float>(y, x);
        out.at<cv::Vec3f>(y, x) = ww > 0 ? v.at<cv::Vec3f>(y, x) / ww : cv::Vec3f(0, 0, 0);
      }
    return out;
  };
  cv::Mat filled = normalised(vsum.back(), wsum.back());
  for (int l = static_cast<int>(wsum.size()) - 2; l >= 0; --l) {
    cv::Mat up;
    cv::resize(filled, up, wsum[l].size(), 0, 0, cv::INTER_LINEAR);
    const cv::Mat here = normalised(vsum[l], wsum[l]);
    filled = cv::Mat(here.size(), CV_32FC3);
    for (int y = 0; y < here.rows; ++y)
      for (int x = 0; x < here.cols; ++x) {
        const float a = std::min(1.0f, wsum[l].at<float>(y, x));
        filled.at<cv::Vec3f>(y, x) = a * here.at<cv::Vec3f>(y, x) + (1 - a) * up.at<cv::Vec3f>(y, x);
      }
  }
  // Known texels keep their exact values.
  rgb.copyTo(filled, known);
  return filled;
}

}  // namespace brdfshot
