// A synthetic capture folder, as a photographer would bring it back:
// bracketed frames (JPEG through a response, or linear 16-bit, with EXIF) of a
// sphere of a known material under a light probe, bracketed frames of the probe
// itself with the same camera, optionally a mirror-ball photo, a capture.mk —
// and the truth (truth/: the radiance, the sphere, truth.json), so every stage
// after it can be measured.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "capture/synthetic_bracket.h"
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

struct SyntheticCaptureOptions {
  SphereShot shot;
  std::array<double, 3> yaw_pitch_roll_deg{};  // shot.camera_to_probe, as the user states it in capture.mk
  CameraModel camera;
  bool jpeg = true;  // else linear 16-bit PNG (camera.raw_bits)
  int jpeg_quality = 95;
  double stops = 2;            // bracket step
  int probe_shot_width = 512;  // the probe's own bracket: a lat-long panorama this wide
  int mirror_ball = 0;         // > 0: also ball.exr, a mirror ball this many px across
  RenderQuality quality;
  // For the record: the material's name and the options that render it, the probe's file, the command.
  std::string material, material_args, probe_path, command;
};

// truth/truth.json: what the capture was made of. One writer, one reader.
struct SyntheticCaptureTruth {
  std::string material, material_args, probe;
  std::array<double, 3> yaw_pitch_roll_deg{};
  Rotation camera_to_probe;
  SphereView sphere;
  std::vector<double> photo_times, probe_times;
  CameraModel camera;
  std::string render_quality, command;

  nlohmann::json ToJson() const;
  // FileError naming `source` for another format or a missing field.
  static SyntheticCaptureTruth FromJson(const nlohmann::json& j, const std::string& source);
  void Write(const std::string& path) const;  // atomic
  static SyntheticCaptureTruth Read(const std::string& path);
};

struct SyntheticCapture {
  SyntheticPhoto photo;
  std::vector<std::string> photo_frames, probe_frames;  // file names in photo/ and probe/
  cv::Size probe_shot;                                  // the probe bracket's size
};

// Writes the capture folder `dir` (frames of an earlier bracket in it are removed).
SyntheticCapture WriteSyntheticCapture(const MerlBrdf& brdf, const LatLongProbe& probe,
                                       const SyntheticCaptureOptions& options, const std::string& dir);

}  // namespace brdfshot
