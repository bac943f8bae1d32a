// Light probes in the layouts people shoot them in, resampled to the lat-long
// frame of the whole pipeline (latlong_probe.h).
//
//  * Angular map (Debevec's light-probe layout): a disc whose centre looks
//    along −Z, radius ∝ the angle from −Z, the rim is +Z:
//    r = acos(−d_z)/π, (u, v) = r (d_x, d_y)/|(d_x, d_y)|, u right, v up.
//  * Mirror ball photographed by an orthographic camera at +Z: a direction d
//    is seen where the ball's normal is n = normalize(d + z), at
//    (cx + R n_x, cy − R n_y). Near the ball's rim one pixel covers a huge
//    solid angle and the camera sees its own reflection at the centre, so both
//    are left out and filled from their surroundings.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"

namespace brdfshot {

// `angular`: CV_32FC3, square. Output `width` × width/2.
LatLongProbe AngularMapToLatLong(const cv::Mat& angular, int width);
cv::Mat LatLongToAngularMap(const LatLongProbe& probe, int size);  // for round trips and pictures

struct MirrorBallOptions {
  double max_normal_deg = 70;   // ball normals further from the camera are the unreliable rim
  double camera_hole_deg = 0;   // ball normals this close to the camera see the camera (0: keep)
  double reflectance = 1;       // of the ball (chrome ≈ 0.6–0.8): radiance is divided by it
};

struct UnwrappedBall {
  LatLongProbe probe;  // in the camera's frame
  cv::Mat measured;    // CV_8U, 255 where the ball saw the texel, 0 where it was filled in
};

// `photo`: CV_32FC3 linear; the ball's silhouette at (cx, cy) radius r in
// continuous image coordinates (pixel centres at +½).
UnwrappedBall UnwrapMirrorBall(const cv::Mat& photo, double cx, double cy, double r, int width,
                               const MirrorBallOptions& options = {});

// Fills texels where `known` is 0 from the known ones (push–pull pyramid).
cv::Mat FillHoles(const cv::Mat& rgb, const cv::Mat& known);

// A mirror ball filling a `size`² image, as an orthographic camera at +Z sees it
// (4×4 samples per pixel, probe read bilinearly); outside the ball is black.
cv::Mat RenderMirrorBall(const LatLongProbe& probe, int size);

}  // namespace brdfshot
