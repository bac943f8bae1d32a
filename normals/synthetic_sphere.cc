#include "normals/synthetic_sphere.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "normals/sphere_view.h"
#include "util/check.h"

namespace brdfshot {
namespace {

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
      case 0:
        cv::rectangle(img, p, p + cv::Point(size, size / 2), col, cv::FILLED);
        break;
      case 1:
        cv::circle(img, p, size / 2, col, cv::FILLED);
        break;
      default:
        cv::circle(img, p, size, col, std::max(1, size / 10));
        break;
    }
  }
  // The sphere as a camera model: the same ray tracing the pipeline uses for
  // normals (sphere_view.h, tested there against closed forms).
  auto draw = [&img](const SphereView& view) {
    const cv::Rect box = view.Bounds(3);
    for (int y = box.y; y < box.y + box.height; ++y)
      for (int x = box.x; x < box.x + box.width; ++x) {
        cv::Vec3f& out = img.at<cv::Vec3f>(y, x);
        Vec3 n, w;
        if (std::abs(view.RimDistance(x + 0.5, y + 0.5)) > 1.5) {  // away from the rim: one sample
          if (view.Trace(x + 0.5, y + 0.5, &n, &w)) out = Shade(n);
          continue;
        }
        const int k = 16;
        cv::Vec3f sum(0, 0, 0);
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) sum += view.Trace(x + (i + 0.5) / k, y + (j + 0.5) / k, &n, &w) ? Shade(n) : out;
        out = sum / static_cast<float>(k * k);
      }
  };
  SphereView view;
  view.width = s.width;
  view.height = s.height;
  view.perspective = s.focal_px > 0;
  if (view.perspective) {
    view.focal_px = s.focal_px;
    view.principal = {s.width / 2.0, s.height / 2.0};
    view.cone = TrueCone(s);
    view.circle = ApparentCircle(view.cone, view.focal_px, view.principal);
  } else {
    view.circle = s.circle;
  }
  draw(view);
  if (s.second_sphere.r > 0) {
    SphereView second;
    second.width = s.width;
    second.height = s.height;
    second.circle = s.second_sphere;
    draw(second);
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
