// A probe for a scene lit by one distant source of known direction and
// intensity (a photometric-stereo dataset's LED, a point light far away): a
// small disc on a black lat-long map, its radiance set so the power it
// delivers — Σ L dω over the disc — is the given irradiance exactly.
#pragma once

#include <opencv2/core.hpp>

#include "calib/latlong_probe.h"
#include "util/vec3.h"

namespace brdfshot {

// `direction`: towards the light (need not be unit, must not be zero);
// `irradiance`: RGB, at normal incidence; `radius_deg`: the disc's angular
// radius (at least one texel is always lit). Error for a zero direction or
// a negative irradiance.
LatLongProbe SunProbe(const Vec3& direction, const cv::Vec3f& irradiance, double radius_deg = 1.0, int width = 512);

// The sun of SunProbe over a uniform sky: `sky_radiance` on every texel
// above the horizon (+y up), the sun's disc added on top. A small sun over a
// dim sky is the lighting that tests a BRDF's highlight and its falloff
// hardest — the case natural probes, with their broad light, say least about.
LatLongProbe SunOverSkyProbe(const Vec3& direction, const cv::Vec3f& irradiance, const cv::Vec3f& sky_radiance,
                             double radius_deg = 1.0, int width = 512);

}  // namespace brdfshot
