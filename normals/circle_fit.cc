#include "normals/circle_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {
namespace {

double MedianOf(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Tukey biweight weights for residuals `r` at 4.685 robust sigmas (1.4826 MAD,
// floored so a perfect fit does not divide by zero).
std::vector<double> TukeyWeights(const std::vector<double>& r, double floor) {
  std::vector<double> a(r.size());
  for (size_t i = 0; i < r.size(); ++i) a[i] = std::abs(r[i]);
  const double sigma = std::max(1.4826 * MedianOf(a), floor);
  const double c = 4.685 * sigma;
  std::vector<double> w(r.size());
  for (size_t i = 0; i < r.size(); ++i) {
    const double u = r[i] / c;
    w[i] = std::abs(u) < 1 ? (1 - u * u) * (1 - u * u) : 0.0;
  }
  return w;
}

FitQuality Quality(const std::vector<double>& r, const std::vector<double>& w) {
  FitQuality q;
  q.points = static_cast<int>(r.size());
  double ss = 0;
  for (size_t i = 0; i < r.size(); ++i)
    if (w[i] > 0) ++q.inliers, ss += r[i] * r[i];
  q.rms_px = q.inliers ? std::sqrt(ss / q.inliers) : 0;
  return q;
}

}  // namespace

Circle FitCircleRobust(const std::vector<cv::Point2d>& pts, FitQuality* quality) {
  if (pts.size() < 5) throw Error("circle fit: " + std::to_string(pts.size()) + " edge points, need at least 5");
  const size_t n = pts.size();
  // Centre the data: the algebraic system is then well conditioned at any image size.
  double mx = 0, my = 0;
  for (const auto& p : pts) mx += p.x, my += p.y;
  mx /= n, my /= n;
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = pts[i].x - mx, y = pts[i].y - my;
    A.row(i) << x, y, 1;
    b(i) = -(x * x + y * y);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) throw Error("circle fit: edge points are collinear or coincident");
  const Eigen::Vector3d s = qr.solve(b);
  double cx = -s(0) / 2, cy = -s(1) / 2;
  const double r2 = cx * cx + cy * cy - s(2);
  if (!(r2 > 0)) throw Error("circle fit: edge points admit no circle");
  double r = std::sqrt(r2);
  std::vector<double> res(n), w(n, 1.0);
  for (int it = 0; it < 30; ++it) {
    // Gauss–Newton on d_i = |p_i − c| − r with the current weights.
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      const double dx = pts[i].x - mx - cx, dy = pts[i].y - my - cy, d = std::hypot(dx, dy);
      res[i] = d - r;
      if (w[i] == 0 || d == 0) continue;
      const Eigen::Vector3d J(-dx / d, -dy / d, -1);
      JtJ += w[i] * J * J.transpose();
      Jtr += w[i] * J * res[i];
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) throw Error("circle fit: singular (too few inlying edge points)");
    cx += step(0), cy += step(1), r += step(2);
    for (size_t i = 0; i < n; ++i) res[i] = std::hypot(pts[i].x - mx - cx, pts[i].y - my - cy) - r;
    w = TukeyWeights(res, 1e-3);
    if (step.norm() < 1e-9 * std::max(1.0, r)) break;
  }
  if (quality) *quality = Quality(res, w);
  return {cx + mx, cy + my, r};
}

Vec3 PixelRay(const cv::Point2d& p, double focal_px, const cv::Point2d& principal) {
  return Normalize(Vec3(p.x - principal.x, -(p.y - principal.y), -focal_px));
}

SphereCone FitConeRobust(const std::vector<cv::Point2d>& pts, double focal_px, const cv::Point2d& principal,
                         FitQuality* quality) {
  if (pts.size() < 5) throw Error("sphere fit: " + std::to_string(pts.size()) + " edge points, need at least 5");
  BRDFSHOT_CHECK(focal_px > 0);
  const size_t n = pts.size();
  std::vector<Vec3> d(n);
  for (size_t i = 0; i < n; ++i) d[i] = PixelRay(pts[i], focal_px, principal);
  std::vector<double> w(n, 1.0), res(n);
  Eigen::Vector3d wv = Eigen::Vector3d::Zero();
  for (int it = 0; it < 30; ++it) {
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d a(d[i].x, d[i].y, d[i].z);
      AtA += w[i] * a * a.transpose();
      Atb += w[i] * a;
    }
    const Eigen::Vector3d next = AtA.ldlt().solve(Atb);
    if (!next.allFinite() || next.norm() <= 1) throw Error("sphere fit: edge points admit no cone");
    const bool done = (next - wv).norm() < 1e-12 * next.norm();
    wv = next;
    // Residual as an angle in pixels: d·ŵ − cos α ≈ −sin α · Δangle.
    const double len = wv.norm(), cos_a = 1 / len, sin_a = std::sqrt(1 - cos_a * cos_a);
    for (size_t i = 0; i < n; ++i) res[i] = (d[i].x * wv(0) + d[i].y * wv(1) + d[i].z * wv(2)) / len - cos_a;
    for (double& r : res) r *= focal_px / std::max(sin_a, 1e-9);
    w = TukeyWeights(res, 1e-3);
    if (done) break;
  }
  if (quality) *quality = Quality(res, w);
  const double len = wv.norm();
  return {Vec3(wv(0) / len, wv(1) / len, wv(2) / len), std::acos(1 / len)};
}

Circle ApparentCircle(const SphereCone& cone, double focal_px, const cv::Point2d& principal) {
  const Vec3& c = cone.centre_dir;
  BRDFSHOT_CHECK(c.z < 0, "sphere behind the camera");
  const double s = focal_px / -c.z;
  // Mean of the silhouette's extent along the radial line through the centre:
  // the two tangent rays at angles θ_c ± α from the optical axis.
  const double theta_c = std::acos(-c.z);
  const double r = 0.5 * focal_px * (std::tan(theta_c + cone.half_angle) - std::tan(theta_c - cone.half_angle));
  return {principal.x + s * c.x, principal.y - s * c.y, r};
}

}  // namespace brdfshot
