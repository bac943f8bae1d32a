#include "normals/synthetic_sphere.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "util/check.h"

namespace brdfshot {
namespace {

// Coverage and shading of one sample point: false if it misses the sphere.
struct Hit {
  bool hit = false;
  Vec3 normal;
};

cv::Vec3f Shade(const Vec3& n) {
  const Vec3 l = Normalize(Vec3(-0.4, 0.5, 0.77));
  const double d = 0.3 + 0.7 * std::max(0.0, Dot(n, l));
  return cv::Vec3f(0.9f, 0.75f, 0.6f) * static_cast<float>(d);
}

}  // namespace

SphereCone TrueCone(const SyntheticSphereScene& s) {
  const double dist = Length(s.centre);
  return {s.centre * (1 / dist), std::asin(1 / dist)};
}

cv::Mat RenderSyntheticSphere(const SyntheticSphereScene& s) {
  BRDFSHOT_CHECK(s.width > 0 && s.height > 0);
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> U(0, 1);
  // Background: a smooth gradient and clutter.
  cv::Mat img(s.height, s.width, CV_32FC3);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const float g = static_cast<float>(0.08 + 0.1 * x / s.width + 0.05 * y / s.height);
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(g, g * 1.1f, g * 1.2f);
    }
  const int side = std::min(s.width, s.height);
  for (int i = 0; i < s.clutter; ++i) {
    const cv::Point p(static_cast<int>(U(rng) * s.width), static_cast<int>(U(rng) * s.height));
    const int size = static_cast<int>((0.02 + 0.15 * U(rng)) * side);
    const cv::Scalar col(0.05 + 0.6 * U(rng), 0.05 + 0.6 * U(rng), 0.05 + 0.6 * U(rng));
    switch (i % 3) {
      case 0: cv::rectangle(img, p, p + cv::Point(size, size / 2), col, cv::FILLED); break;
      case 1: cv::circle(img, p, size / 2, col, cv::FILLED); break;
      default: cv::circle(img, p, size, col, std::max(1, size / 10)); break;
    }
  }
  const bool persp = s.focal_px > 0;
  const cv::Point2d pp(s.width / 2.0, s.height / 2.0);
  const SphereCone cone = persp ? TrueCone(s) : SphereCone{};
  auto trace = [&](double px, double py) -> Hit {
    Hit h;
    if (!persp) {
      const double dx = (px - s.circle.cx) / s.circle.r, dy = -(py - s.circle.cy) / s.circle.r;
      const double r2 = dx * dx + dy * dy;
      if (r2 >= 1) return h;
      h.hit = true;
      h.normal = Vec3(dx, dy, std::sqrt(1 - r2));
      return h;
    }
    const Vec3 d = PixelRay({px, py}, s.focal_px, pp);
    const double b = Dot(d, s.centre), c = Dot(s.centre, s.centre) - 1, disc = b * b - c;
    if (disc <= 0) return h;
    const double t = b - std::sqrt(disc);
    h.hit = true;
    h.normal = Normalize(d * t - s.centre);
    return h;
  };
  // Which pixels are near the rim (supersampled) — in pixels of distance.
  auto rim_distance = [&](double px, double py) {
    if (!persp) return std::abs(std::hypot(px - s.circle.cx, py - s.circle.cy) - s.circle.r);
    const Vec3 d = PixelRay({px, py}, s.focal_px, pp);
    return std::abs(std::acos(std::clamp(Dot(d, cone.centre_dir), -1.0, 1.0)) - cone.half_angle) * s.focal_px * 0.8;
  };
  const Circle box = persp ? ApparentCircle(cone, s.focal_px, pp) : s.circle;
  const double reach = box.r * (persp ? 1.0 + (1 + cone.centre_dir.z) : 1.0) + 3;
  const int x0 = std::max(0, static_cast<int>(box.cx - reach)), x1 = std::min(s.width, static_cast<int>(box.cx + reach) + 1);
  const int y0 = std::max(0, static_cast<int>(box.cy - reach)), y1 = std::min(s.height, static_cast<int>(box.cy + reach) + 1);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      cv::Vec3f& out = img.at<cv::Vec3f>(y, x);
      if (rim_distance(x + 0.5, y + 0.5) > 1.5) {
        const Hit h = trace(x + 0.5, y + 0.5);
        if (h.hit) out = Shade(h.normal);
        continue;
      }
      const int n = 16;
      cv::Vec3f sum(0, 0, 0);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Hit h = trace(x + (i + 0.5) / n, y + (j + 0.5) / n);
          sum += h.hit ? Shade(h.normal) : out;
        }
      out = sum / static_cast<float>(n * n);
    }
  if (s.blur_sigma > 0) cv::GaussianBlur(img, img, cv::Size(), s.blur_sigma);
  if (s.noise > 0) {
    cv::Mat n(img.size(), CV_32FC3);
    cv::theRNG().state = s.seed * 2654435761u + 1;
    cv::randn(n, 0.0, s.noise);
    img += n;
  }
  return img;
}

}  // namespace brdfshot
