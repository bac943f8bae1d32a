// Light probes in the layouts people shoot them in, resampled to the lat-long
// frame of the whole pipeline (latlong_probe.h).
//
//  * Angular map (Debevec's light-probe layout): a disc whose centre looks
//    along −Z, radius ∝ the angle from −Z, the rim is +Z:
//    r = acos(−d_z)/π, (u, v) = r (d_x, d_y)/|(d_x, d_y)|, u right, v up.
//  * A photographed mirror ball: calib/mirror_ball.h.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"

namespace brdfshot {

// `angular`: CV_32FC3, square. Output `width` × width/2.
LatLongProbe AngularMapToLatLong(const cv::Mat& angular, int width);
cv::Mat LatLongToAngularMap(const LatLongProbe& probe, int size);  // for round trips and pictures

// Fills texels where `known` is 0 from the known ones (push–pull pyramid).
cv::Mat FillHoles(const cv::Mat& rgb, const cv::Mat& known);

}  // namespace brdfshot
