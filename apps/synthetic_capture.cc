#include "apps/synthetic_capture.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "normals/circle_fit.h"
#include "util/check.h"

namespace brdfshot {

SphereView ShotView(const SphereShot& s) {
  BRDFSHOT_CHECK(s.width > 0 && s.height > 0 && s.focal_px > 0 && s.radius_px > 0, "bad SphereShot");
  SphereView v;
  v.width = s.width;
  v.height = s.height;
  v.perspective = true;
  v.focal_px = s.focal_px;
  v.principal = {s.width / 2.0, s.height / 2.0};
  // A unit sphere whose cone of tangent rays has half-angle α = atan(r / f):
  // its apparent circle then has about the asked radius (exactly on axis).
  v.cone = {PixelRay(s.centre_px, s.focal_px, v.principal), std::atan(s.radius_px / s.focal_px)};
  v.circle = ApparentCircle(v.cone, v.focal_px, v.principal);
  return v;
}

SyntheticPhoto RenderSphereShot(const MerlBrdf& brdf, const LatLongProbe& probe, const SphereShot& s,
                                const RenderQuality& quality) {
  SyntheticPhoto out;
  out.view = ShotView(s);
  const SphereView& v = out.view;
  cv::Mat img(s.height, s.width, CV_32FC3);
  // Background: the environment along each pixel's ray (probe frame).
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      img.at<cv::Vec3f>(y, x) =
          probe.Bilinear(s.camera_to_probe(PixelRay({x + 0.5, y + 0.5}, v.focal_px, v.principal)));

  // Sphere samples: one per pixel inside, rim_supersample² where the rim
  // crosses the pixel, all rendered in one operator, then box-filtered.
  PixelGeometry g;
  g.width = s.width;
  g.height = s.height;
  struct Target {
    int x, y;
    float weight;
  };
  std::vector<Target> target;
  std::vector<std::pair<cv::Point, float>> background_share;  // rim pixels: how much background stays
  const int k = std::max(1, s.rim_supersample);
  const cv::Rect box = v.Bounds(2);
  auto add = [&](int x, int y, double px, double py, float w) {
    Vec3 n, o;
    if (!v.Trace(px, py, &n, &o)) return false;
    g.x.push_back(x);
    g.y.push_back(y);
    g.normal.push_back(s.camera_to_probe(n));
    g.view.push_back(s.camera_to_probe(o));
    target.push_back({x, y, w});
    return true;
  };
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const double inside = v.RimDistance(x + 0.5, y + 0.5);
      if (inside > 1.0) {
        add(x, y, x + 0.5, y + 0.5, 1.0f);
      } else if (inside > -1.0) {
        int hits = 0;
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) hits += add(x, y, x + (i + 0.5) / k, y + (j + 0.5) / k, 1.0f / (k * k));
        background_share.push_back({{x, y}, 1.0f - static_cast<float>(hits) / (k * k)});
      }
    }
  for (const auto& [p, share] : background_share) img.at<cv::Vec3f>(p) *= share;
  for (const Target& t : target)
    if (t.weight == 1.0f) img.at<cv::Vec3f>(t.y, t.x) = cv::Vec3f(0, 0, 0);
  const Eigen::MatrixXd rgb = TransportOperator::Build(g, probe, brdf.grid(), quality).Render(brdf);
  for (size_t i = 0; i < target.size(); ++i) {
    cv::Vec3f& px = img.at<cv::Vec3f>(target[i].y, target[i].x);
    for (int c = 0; c < 3; ++c) px[c] += target[i].weight * static_cast<float>(std::max(0.0, rgb(i, c)));
  }
  if (s.blur_sigma > 0) cv::GaussianBlur(img, img, cv::Size(), s.blur_sigma);
  out.radiance = img;
  return out;
}

}  // namespace brdfshot
