#include "normals/sphere_geometry.h"

#include <cmath>

#include "util/check.h"
#include "util/fnv_hash.h"

namespace brdfshot {

uint64_t PixelGeometry::Hash() const {
  uint64_t h = kFnv1aOffset;
  auto mix = [&h](const void* p, size_t n) { h = Fnv1a(p, n, h); };
  mix(&width, sizeof width);
  mix(&height, sizeof height);
  for (size_t i = 0; i < size(); ++i) {
    mix(&x[i], sizeof(int));
    mix(&y[i], sizeof(int));
    mix(&normal[i], sizeof(Vec3));
    mix(&view[i], sizeof(Vec3));
  }
  return h;
}

PixelGeometry OrthographicSphere(int resolution, double max_angle_deg) {
  BRDFSHOT_CHECK(resolution > 0);
  PixelGeometry g;
  g.width = g.height = resolution;
  const double cos_max = std::cos(max_angle_deg * kPi / 180.0);
  for (int py = 0; py < resolution; ++py)
    for (int px = 0; px < resolution; ++px) {
      const double sx = 2.0 * (px + 0.5) / resolution - 1.0;
      const double sy = 1.0 - 2.0 * (py + 0.5) / resolution;
      const double r2 = sx * sx + sy * sy;
      if (r2 >= 1.0) continue;
      const Vec3 n(sx, sy, std::sqrt(1.0 - r2));
      if (n.z < cos_max) continue;
      g.x.push_back(px);
      g.y.push_back(py);
      g.normal.push_back(n);
      g.view.push_back(Vec3(0, 0, 1));
    }
  return g;
}

cv::Mat PixelsToImage(const PixelGeometry& g, const Eigen::MatrixXd& rgb) {
  BRDFSHOT_CHECK(static_cast<size_t>(rgb.rows()) == g.size() && rgb.cols() == 3);
  cv::Mat img(g.height, g.width, CV_32FC3, cv::Scalar::all(0));
  for (size_t p = 0; p < g.size(); ++p) img.at<cv::Vec3f>(g.y[p], g.x[p]) = cv::Vec3f(rgb(p, 0), rgb(p, 1), rgb(p, 2));
  return img;
}

PixelGeometry Subsample(const PixelGeometry& g, int step) {
  BRDFSHOT_CHECK(step >= 1);
  PixelGeometry s;
  s.width = g.width;
  s.height = g.height;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.x[i] % step || g.y[i] % step) continue;
    s.x.push_back(g.x[i]);
    s.y.push_back(g.y[i]);
    s.normal.push_back(g.normal[i]);
    s.view.push_back(g.view[i]);
  }
  return s;
}

}  // namespace brdfshot
