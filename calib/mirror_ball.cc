#include "calib/mirror_ball.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "calib/probe_layout.h"
#include "util/check.h"

namespace brdfshot {

BallCamera BallCamera::Orthographic(int width, int height, double cx, double cy, double r) {
  BRDFSHOT_CHECK(width > 0 && height > 0 && r > 0, "orthographic ball needs a photo size and a radius");
  BallCamera c;
  c.width = width, c.height = height, c.cx = cx, c.cy = cy, c.r = r;
  return c;
}

BallCamera BallCamera::Perspective(int width, int height, double focal_px, const cv::Point2d& principal,
                                   const Vec3& centre_dir, double half_angle) {
  BRDFSHOT_CHECK(width > 0 && height > 0 && focal_px > 0 && half_angle > 0 && half_angle < kPi / 2 &&
                     std::abs(Length(centre_dir) - 1) < 1e-6 && centre_dir.z < 0,
                 "perspective ball needs a focal length and a cone in front of the camera");
  BallCamera c;
  c.width = width, c.height = height, c.focal_px = focal_px, c.principal = principal;
  c.centre_dir = centre_dir, c.half_angle = half_angle;
  return c;
}

bool BallCamera::Trace(double px, double py, Vec3* normal, Vec3* view) const {
  if (!perspective()) {
    const double x = (px - cx) / r, y = -(py - cy) / r, r2 = x * x + y * y;
    if (r2 >= 1) return false;
    *normal = Vec3(x, y, std::sqrt(1 - r2));
    *view = Vec3(0, 0, 1);
    return true;
  }
  // A unit ball at distance 1/sin α: scale does not change directions.
  const Vec3 d = Normalize(Vec3(px - principal.x, -(py - principal.y), -focal_px));
  const Vec3 c = centre_dir * (1 / std::sin(half_angle));
  const double b = Dot(d, c), disc = b * b - (Dot(c, c) - 1);
  if (disc <= 0) return false;
  *normal = Normalize(d * (b - std::sqrt(disc)) - c);
  *view = -d;
  return true;
}

bool BallCamera::Reflecting(const Vec3& d, cv::Point2d* pixel, Vec3* normal, Vec3* view) const {
  if (!perspective()) {
    const Vec3 h = d + Vec3(0, 0, 1);
    const double len = Length(h);
    if (len < 1e-9) return false;
    *normal = h * (1 / len);
    *view = Vec3(0, 0, 1);
    *pixel = {cx + r * normal->x, cy - r * normal->y};
    return true;
  }
  const Vec3 c = centre_dir * (1 / std::sin(half_angle));
  Vec3 v = -centre_dir, n;
  for (int it = 0; it < 60; ++it) {
    const Vec3 h = d + v;
    const double len = Length(h);
    if (len < 1e-9) return false;
    n = h * (1 / len);
    const Vec3 v_next = Normalize(-(c + n));
    const double moved = Length(v_next - v);
    v = v_next;
    if (moved < 1e-12) break;
  }
  if (Dot(n, v) <= 0) return false;  // the point faces away from the camera
  const Vec3 p = c + n;
  *normal = n;
  *view = v;
  *pixel = {principal.x + focal_px * p.x / -p.z, principal.y - focal_px * p.y / -p.z};
  return true;
}

UnwrappedBall UnwrapMirrorBall(const cv::Mat& photo, const BallCamera& camera, int width, const MirrorBallOptions& o) {
  BRDFSHOT_CHECK(photo.type() == CV_32FC3 && photo.cols == camera.width && photo.rows == camera.height && width >= 4 &&
                     width % 2 == 0 && o.reflectance > 0,
                 "mirror ball photo must be CV_32FC3 of the camera's size");
  const int height = width / 2;
  const LatLongProbe frame(cv::Mat(height, width, CV_32FC3, cv::Scalar::all(0)));
  cv::Mat mapx(height, width, CV_32F), mapy(height, width, CV_32F);
  UnwrappedBall out;
  out.measured = cv::Mat(height, width, CV_8U, cv::Scalar(0));
  const double cos_max = std::cos(o.max_normal_deg * kPi / 180), cos_hole = std::cos(o.camera_hole_deg * kPi / 180);
  for (int row = 0; row < height; ++row)
    for (int col = 0; col < width; ++col) {
      const Vec3 d = frame.DirectionAt(col + 0.5, row + 0.5);
      cv::Point2d p(-1, -1);
      Vec3 n, v;
      const bool hit = camera.Reflecting(d, &p, &n, &v);
      const double cos_nv = hit ? Dot(n, v) : -1;
      const bool ok = hit && cos_nv >= cos_max && (o.camera_hole_deg <= 0 || cos_nv < cos_hole) && p.x >= 0.5 &&
                      p.y >= 0.5 && p.x <= photo.cols - 0.5 && p.y <= photo.rows - 0.5;
      out.measured.at<uint8_t>(row, col) = ok ? 255 : 0;
      mapx.at<float>(row, col) = static_cast<float>(p.x - 0.5);
      mapy.at<float>(row, col) = static_cast<float>(p.y - 0.5);
    }
  cv::Mat ll;
  cv::remap(photo, ll, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  ll /= o.reflectance;
  ll.setTo(cv::Scalar::all(0), out.measured == 0);
  out.probe = LatLongProbe(FillHoles(ll, out.measured), "mirror ball");
  return out;
}

cv::Mat RenderMirrorBall(const LatLongProbe& probe, const BallCamera& camera) {
  cv::Mat out(camera.height, camera.width, CV_32FC3, cv::Scalar::all(0));
  const int ss = 4;
  cv::parallel_for_(cv::Range(0, camera.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y)
      for (int x = 0; x < camera.width; ++x) {
        cv::Vec3f sum(0, 0, 0);
        for (int j = 0; j < ss; ++j)
          for (int i = 0; i < ss; ++i) {
            Vec3 n, v;
            if (camera.Trace(x + (i + 0.5) / ss, y + (j + 0.5) / ss, &n, &v)) sum += probe.Bilinear(Reflect(v, n));
          }
        out.at<cv::Vec3f>(y, x) = sum / static_cast<float>(ss * ss);
      }
  });
  return out;
}

cv::Mat RenderMirrorBall(const LatLongProbe& probe, int size) {
  return RenderMirrorBall(probe, BallCamera::Orthographic(size, size, size / 2.0, size / 2.0, size / 2.0));
}

}  // namespace brdfshot
