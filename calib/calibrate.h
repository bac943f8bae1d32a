// The calib stage: a light probe in the pipeline's lat-long frame and its
// relation to the camera — the layout converted (lat-long, angular map, mirror
// ball photo, or a generated sun), the camera → probe rotation (given, or
// estimated from a mirror-ball photo taken from the camera's position) and the
// radiometric scale photo units per probe unit (given, measured on a reference
// card in the photo, or from the two merges' exposure metadata).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "calib/calibration.h"
#include "calib/latlong_probe.h"
#include "calib/mirror_ball.h"
#include "calib/radiometric_scale.h"
#include "normals/circle_fit.h"
#include "util/rotation.h"
#include "util/vec3.h"

namespace brdfshot {

// Where a mirror ball is in its photo. A ball's rim reflects what lies right
// behind it, so against its own surroundings its silhouette can vanish: then
// the user marks the circle, as HDR tools ask for.
struct BallLocation {
  std::optional<Circle> circle;  // marked by the user; detected when absent
  double focal_px = 0;           // > 0: the ball is seen in perspective
  double focal_35mm = 0;         // instead of focal_px: the 35 mm-equivalent focal length
};

// One distant light, e.g. a photometric-stereo LED or the sun.
struct SunLight {
  Vec3 direction{0, 0, 1};        // towards the light, probe frame
  cv::Vec3d irradiance{1, 1, 1};  // at normal incidence
  double radius_deg = 1;
};

struct CalibrateOptions {
  // The lighting: the probe file in `layout` (latlong | angular | mirrorball), or `sun`.
  std::string probe_path;
  std::string layout = "latlong";
  std::optional<SunLight> sun;
  int width = 0;  // lat-long width written; 0: as given, 512 for converted layouts
  // Camera → probe, as given; replaced by the estimate when `rotation_from_ball` names a photo.
  Rotation camera_to_probe;
  std::array<double, 3> yaw_pitch_roll_deg{};
  std::string rotation_from_ball;
  // Photo radiance per probe radiance, as given; replaced by the measurement
  // when `card_photo` or `photo_merge` + `probe_merge` are set.
  cv::Vec3d scale{1, 1, 1};
  std::string card_photo;
  ReferenceCard card;
  std::string photo_merge, probe_merge;
  // The mirror ball (of --layout mirrorball or of rotation_from_ball).
  BallLocation ball_location;
  MirrorBallOptions ball;
};

struct CalibrateResult {
  LatLongProbe probe;                    // lat-long, probe frame
  Calibration calibration;               // Calibration::probe left for the caller to name
  std::optional<RadiometricScale> card;  // the card's measurement, when one was used
  std::vector<std::string> warnings;     // for the user: measurements to double-check
};

// Errors name the file: an unreadable probe or photo, an angular map that is
// not square, a ball that is not found (asking for its circle), a card region
// outside its photo, merge sidecars of different kinds.
CalibrateResult Calibrate(const CalibrateOptions& options);

// The focal length in pixels of a 35 mm-equivalent one (EXIF
// FocalLengthIn35mmFilm: the 36 mm side of full frame maps to the photo's
// longer side).
double FocalPxFrom35mm(double focal_35mm, cv::Size photo);

}  // namespace brdfshot
