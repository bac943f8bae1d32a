// A synthetic photo of a known material: a unit sphere seen by a perspective
// camera under a light probe, with the environment behind it, anti-aliased at
// the rim and blurred by the lens. The scene radiance `synth-capture` brackets
// through a camera model; the truth every stage is measured against.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"
#include "fit/merl_brdf.h"
#include "fit/transport.h"
#include "normals/sphere_view.h"
#include "util/rotation.h"

namespace brdfshot {

struct SphereShot {
  int width = 640, height = 480;
  double focal_px = 900;            // about a 50 mm lens on a 36 mm-wide sensor at 640 px
  double radius_px = 110;           // apparent radius of the sphere
  cv::Point2d centre_px{350, 230};  // where the sphere's centre appears
  Rotation camera_to_probe;
  double blur_sigma = 0.6;  // lens blur, px
  int rim_supersample = 4;  // per axis, for pixels the rim crosses
};

struct SyntheticPhoto {
  cv::Mat radiance;  // CV_32FC3, probe units
  SphereView view;   // the true camera and sphere
};

// The sphere is rendered with the basis-image operator at `quality`
// (fit/transport.h); the background is the probe seen along each pixel's ray.
SyntheticPhoto RenderSphereShot(const MerlBrdf& brdf, const LatLongProbe& probe, const SphereShot& shot,
                                const RenderQuality& quality);

// The SphereView `shot` describes (perspective, principal point at the centre).
SphereView ShotView(const SphereShot& shot);

}  // namespace brdfshot
