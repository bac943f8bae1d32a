// The camera → probe rotation from a mirror ball photographed in the same frame
// as the sample: the ball, unwrapped, is the lighting seen from the camera's
// frame; the probe is the same lighting in its own frame. The rotation R that
// makes ball(d) ∝ probe(R d) for every direction d the ball saw is the one
// `calib --rotate` otherwise asks the user for.
//
// How: log radiance of both at low resolution (so exposure and white balance
// drop out as an offset, and the sun does not outweigh the sky), compared by
// the variance of their difference over the ball's measured directions,
// weighted by solid angle. A grid search over yaw (all), pitch and roll (±45°)
// finds the basin; coordinate descent with halving steps then refines it.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"
#include "util/rotation.h"

namespace brdfshot {

struct RotationFit {
  Rotation rotation;                    // camera → probe
  double yaw = 0, pitch = 0, roll = 0;  // degrees, Rotation::FromYawPitchRoll's convention
  double rms_log = 0;                   // RMS of the log-radiance difference at the optimum (after the offset)
};

// `ball`: the unwrapped mirror ball (camera frame); `measured`: CV_8U, non-zero
// where the ball saw the texel (UnwrappedBall::measured), or empty for all.
RotationFit EstimateRotation(const LatLongProbe& probe, const LatLongProbe& ball, const cv::Mat& measured);

}  // namespace brdfshot
