// The merge sidecar: what `merge` writes beside the linear EXR — the frames
// and their exposures, the camera, the response, how the merge ran — and what
// `calib` (scale from exposure metadata) and `normals` (focal length from
// EXIF) read. One writer (MergeSidecar::Write), one reader (MergeSidecar::Read).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "capture/response.h"

namespace brdfshot {

struct MergeSidecar {
  // One record per frame: "file", and what applies of "exposure",
  // "exif_exposure", "orientation", "shift" and, for RAW, "black", "white", "wb".
  nlohmann::json frames = nlohmann::json::array();
  std::string camera;     // EXIF make and model ("" when unknown)
  double focal_35mm = 0;  // EXIF FocalLengthIn35mmFilm, mm (0: unknown)
  ResponseCurve response;
  bool raw = false, aligned = false, half = false;
  double unreliable_fraction = 0;
  double chroma_pooled_fraction = 0;  // pixels whose colour came from their neighbours (MergeOptions)
  int clip_reach = 0;
  // Ghost detection (capture/ghosts.h): the reference frame's index, the share
  // of pixels taken from it alone, and the mask of them ("" when off).
  bool deghosted = false;
  int reference_frame = -1;
  double ghost_fraction = 0;
  std::string output, mask, ghosts, response_plot, command;

  // RAW: the white balance every frame shares; FileError naming `source`
  // when they differ or one is not positive. (1, 1, 1) for other brackets.
  cv::Vec3d WhiteBalance(const std::string& source) const;

  nlohmann::json ToJson() const;
  // FileError naming `source` for another format, no frames, a focal length
  // out of range or a missing field.
  static MergeSidecar FromJson(const nlohmann::json& j, const std::string& source);
  void Write(const std::string& path) const;  // atomic
  static MergeSidecar Read(const std::string& path);
};

}  // namespace brdfshot
