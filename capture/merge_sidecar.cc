#include "capture/merge_sidecar.h"

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {

namespace {
constexpr const char* kMergeFormat = "brdfshot-merge-1";
}  // namespace

cv::Vec3d MergeSidecar::WhiteBalance(const std::string& source) const {
  cv::Vec3d wb(1, 1, 1);
  if (!raw) return wb;
  try {
    const nlohmann::json& first = frames.at(0).at("wb");
    for (int c = 0; c < 3; ++c) wb[c] = first.at(c);
    for (const nlohmann::json& f : frames)
      for (int c = 0; c < 3; ++c)
        if (f.at("wb").at(c).get<double>() != wb[c])
          throw FileError(source, "frames of one bracket with different white balance");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("incomplete merge sidecar: ") + e.what());
  }
  if (!(wb[0] > 0 && wb[1] > 0 && wb[2] > 0)) throw FileError(source, "white balance must be positive");
  return wb;
}

nlohmann::json MergeSidecar::ToJson() const {
  return {{"format", kMergeFormat},
          {"frames", frames},
          {"camera", camera},
          {"focal_35mm", focal_35mm},
          {"response", response.ToJson()},
          {"raw", raw},
          {"aligned", aligned},
          {"unreliable_fraction", unreliable_fraction},
          {"chroma_pooled_fraction", chroma_pooled_fraction},
          {"clip_reach", clip_reach},
          {"deghosted", deghosted},
          {"reference_frame", reference_frame},
          {"ghost_fraction", ghost_fraction},
          {"output", output},
          {"mask", mask},
          {"ghosts", ghosts},
          {"half", half},
          {"response_plot", response_plot},
          {"command", command}};
}

MergeSidecar MergeSidecar::FromJson(const nlohmann::json& j, const std::string& source) {
  MergeSidecar m;
  try {
    if (!HasFormat(j, kMergeFormat)) throw FileError(source, "not a brdfshot merge sidecar");
    m.raw = j.at("raw");
    m.camera = j.value("camera", "");
    m.frames = j.at("frames");
    if (!m.frames.is_array() || m.frames.empty()) throw FileError(source, "lists no frames");
    if (j.contains("focal_35mm")) {
      const nlohmann::json& f = j.at("focal_35mm");
      if (!f.is_number() || !(f.get<double>() >= 0 && f.get<double>() < 1e4))
        throw FileError(source, "focal_35mm must be a focal length in mm (0: unknown)");
      m.focal_35mm = f.get<double>();
    }
    m.response = ResponseCurve::FromJson(j.at("response"), source);
    m.aligned = j.value("aligned", false);
    m.half = j.value("half", false);
    m.unreliable_fraction = j.value("unreliable_fraction", 0.0);
    m.chroma_pooled_fraction = j.value("chroma_pooled_fraction", 0.0);
    m.clip_reach = j.value("clip_reach", 0);
    m.deghosted = j.value("deghosted", false);
    m.reference_frame = j.value("reference_frame", -1);
    m.ghost_fraction = j.value("ghost_fraction", 0.0);
    m.output = j.value("output", "");
    m.mask = j.value("mask", "");
    m.ghosts = j.value("ghosts", "");
    m.response_plot = j.value("response_plot", "");
    m.command = j.value("command", "");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("incomplete merge sidecar: ") + e.what());
  }
  return m;
}

void MergeSidecar::Write(const std::string& path) const {
  const std::string text = ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& o) { o << text << "\n"; });
}

MergeSidecar MergeSidecar::Read(const std::string& path) { return FromJson(ReadJsonFile(path), path); }

}  // namespace brdfshot
