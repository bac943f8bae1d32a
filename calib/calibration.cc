#include "calib/calibration.h"

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {

namespace {
constexpr const char* kCalibrationFormat = "brdfshot-calib-1";
}  // namespace

nlohmann::json Calibration::ToJson() const {
  nlohmann::json j = provenance.is_object() ? provenance : nlohmann::json::object();
  j["format"] = kCalibrationFormat;
  j["source"] = source;
  j["layout"] = layout;
  j["probe"] = probe;
  j["width"] = width;
  j["rotation_camera_to_probe"] = camera_to_probe.m;
  j["yaw_pitch_roll_deg"] = yaw_pitch_roll_deg;
  j["scale"] = {scale[0], scale[1], scale[2]};
  return j;
}

Calibration Calibration::FromJson(const nlohmann::json& j, const std::string& source_name) {
  Calibration c;
  try {
    if (!HasFormat(j, kCalibrationFormat))
      throw FileError(source_name, "not a brdfshot calibration (format " + std::string(kCalibrationFormat) + ")");
    c.source = j.value("source", "");
    c.layout = j.value("layout", "");
    c.probe = j.value("probe", "");
    c.width = j.value("width", 0);
    c.camera_to_probe.m = j.at("rotation_camera_to_probe").get<decltype(c.camera_to_probe.m)>();
    if (j.contains("yaw_pitch_roll_deg"))
      c.yaw_pitch_roll_deg = j.at("yaw_pitch_roll_deg").get<std::array<double, 3>>();
    // One number for all channels, or R,G,B.
    const nlohmann::json& js = j.at("scale");
    for (int k = 0; k < 3; ++k) c.scale[k] = js.is_array() ? js.at(k).get<double>() : js.get<double>();
    for (const char* key : {"sun", "ball", "rotation_from_ball", "scale_from_card", "scale_from_merges"})
      if (j.contains(key)) c.provenance[key] = j.at(key);
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source_name, std::string("incomplete calibration: ") + e.what());
  }
  if (c.camera_to_probe.OrthonormalityError() > 1e-6) throw FileError(source_name, "rotation is not orthonormal");
  if (!(c.scale[0] > 0 && c.scale[1] > 0 && c.scale[2] > 0)) throw FileError(source_name, "scale must be positive");
  return c;
}

void Calibration::Write(const std::string& path) const {
  const std::string text = ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& s) { s << text << "\n"; });
}

Calibration Calibration::Read(const std::string& path) { return FromJson(ReadJsonFile(path), path); }

}  // namespace brdfshot
