// A photographed mirror ball as a light probe: which pixel of the photo shows
// the light from each direction, for an orthographic or a perspective camera.
//
// Camera frame: looking down −Z, image right = +X, image up = +Y (the frame of
// normals/sphere_view.h). A ball point with unit normal n, seen along the unit
// direction v towards the camera, reflects the light arriving from
// d = 2(n·v)n − v. Orthographic: v = +Z everywhere, so n = normalize(d + z).
// Perspective: v depends on the point, so n is found by a fixed-point
// iteration n ← normalize(d + v(n)); it contracts by about sin α per step for
// a ball subtending the half-angle α, i.e. a few steps for any real ball.
//
// Near the ball's rim one pixel covers a huge solid angle and the camera sees
// its own reflection at the centre, so both are left out and filled from their
// surroundings.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"
#include "util/vec3.h"

namespace brdfshot {

// Where the ball is in the photo. calib does not depend on normals/: the app
// fills this from the sphere detector's circle or cone.
struct BallCamera {
  int width = 0, height = 0;  // of the photo
  // Orthographic (focal_px == 0): the silhouette circle, continuous pixel
  // coordinates (pixel centres at +½).
  double cx = 0, cy = 0, r = 0;
  // Perspective (focal_px > 0): a pinhole with this focal length and principal
  // point; the ball fills the cone of rays at `half_angle` around `centre_dir`.
  double focal_px = 0;
  cv::Point2d principal;
  Vec3 centre_dir{0, 0, -1};
  double half_angle = 0;

  static BallCamera Orthographic(int width, int height, double cx, double cy, double r);
  static BallCamera Perspective(int width, int height, double focal_px, const cv::Point2d& principal,
                                const Vec3& centre_dir, double half_angle);
  bool perspective() const { return focal_px > 0; }

  // Normal and direction towards the camera where the ray through image point
  // (px, py) meets the ball; false if it misses.
  bool Trace(double px, double py, Vec3* normal, Vec3* view) const;
  // The image point whose ball normal reflects light from direction `d` into
  // the camera, with that normal and view; false where the iteration cannot
  // settle (d straight behind the ball, which the rim limit drops anyway).
  bool Reflecting(const Vec3& d, cv::Point2d* pixel, Vec3* normal, Vec3* view) const;
};

struct MirrorBallOptions {
  double max_normal_deg = 70;  // ball normals further than this from the view are the unreliable rim
  double camera_hole_deg = 0;  // ball normals this close to the view see the camera (0: keep)
  double reflectance = 1;      // of the ball (chrome ≈ 0.6–0.8): radiance is divided by it
};

struct UnwrappedBall {
  LatLongProbe probe;  // in the camera's frame
  cv::Mat measured;    // CV_8U, 255 where the ball saw the texel, 0 where it was filled in
};

// `photo`: CV_32FC3 linear, of the camera's size. Output `width` × width/2.
UnwrappedBall UnwrapMirrorBall(const cv::Mat& photo, const BallCamera& camera, int width,
                               const MirrorBallOptions& options = {});

// The photo of a mirror ball under `probe` (camera frame) as `camera` sees it,
// 4×4 samples per pixel, probe read bilinearly; outside the ball is black.
cv::Mat RenderMirrorBall(const LatLongProbe& probe, const BallCamera& camera);
// An orthographic ball filling a `size`² image.
cv::Mat RenderMirrorBall(const LatLongProbe& probe, int size);

}  // namespace brdfshot
