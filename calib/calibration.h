// The calibration sidecar: what `calib` writes beside the lat-long probe and
// `remap` reads — how the camera's frame and radiance map onto the probe's.
// One writer (Calibration::Write), one reader (Calibration::Read).
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "util/rotation.h"

namespace brdfshot {

struct Calibration {
  std::string source;  // the probe as given (a file, or "sun x,y,z")
  std::string layout;  // latlong | angular | mirrorball | sun
  std::string probe;   // the lat-long EXR written
  int width = 0;       // its width in texels
  Rotation camera_to_probe;
  std::array<double, 3> yaw_pitch_roll_deg{};
  cv::Vec3d scale{1, 1, 1};  // photo radiance / probe radiance, per channel
  // How the probe, rotation and scale were obtained, kept for the record
  // (keys "sun", "ball", "rotation_from_ball", "scale_from_card",
  // "scale_from_merges"): an object, written as top-level keys.
  nlohmann::json provenance = nlohmann::json::object();

  nlohmann::json ToJson() const;
  // FileError naming `source_name` for a sidecar of another format, a
  // rotation that is not orthonormal or a scale that is not positive.
  static Calibration FromJson(const nlohmann::json& j, const std::string& source_name);
  void Write(const std::string& path) const;  // atomic
  static Calibration Read(const std::string& path);
};

}  // namespace brdfshot
