// A bracket as `merge` takes it: the frames of one exposure series read from
// files (8/16-bit images with EXIF or a times file, or camera RAW), checked to
// belong together and to have measured something, then merged to radiance.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "capture/align.h"
#include "capture/merge.h"
#include "capture/merge_sidecar.h"
#include "capture/response.h"

namespace brdfshot {

bool IsRawFile(const std::string& path);   // by extension: .nef, .cr2, .dng, …
bool IsJpegFile(const std::string& path);  // .jpg, .jpeg

// Files and folders → the frames' files: a folder contributes its images and
// RAW files in name order. FileError for a path that does not exist.
std::vector<std::string> ExpandBracketInputs(const std::vector<std::string>& paths);

struct Bracket {
  std::vector<std::string> files;
  std::vector<cv::Mat> frames;                       // RGB, 8- or 16-bit, EXIF orientation applied
  std::vector<double> exposure;                      // relative exposure t · ISO/100 / N² (or the times file's)
  nlohmann::json records = nlohmann::json::array();  // per frame, for the merge sidecar
  std::string camera;                                // the first frame's that says
  double focal_35mm = 0;                             // the first frame's that says (0: none)
  bool raw = false, jpeg = false;
};

struct BracketReadOptions {
  std::string times_path;            // overrides EXIF exposures
  bool white_balance_given = false;  // RAW: use `white_balance` instead of the camera's
  std::array<double, 3> white_balance{};
  bool progress = false;
};

// Reads and checks the frames: one kind (all RAW or none), decodable, 8/16-bit,
// of one size, each with an exposure (EXIF, or the times file; a single frame
// without one counts as exposure 1). FileError naming the frame otherwise.
Bracket ReadBracket(const std::vector<std::string>& files, const BracketReadOptions& opt);

// FileError naming the shortest frame when it is saturated everywhere, or the
// longest when it is black everywhere: a bracket that measured nothing, said in
// the photographer's terms.
void CheckBracketMeasured(const Bracket& b);

// The clipping reach the merge uses (capture/clipping.h): kJpegClipReach for
// a JPEG light probe, whose power sits in a few small clipped sources whose
// other channels JPEG lowers; none (−1) otherwise — on a sphere's photo the
// rule drops more sound samples than it saves.
int ClipReachFor(const Bracket& b, bool is_probe);

struct BracketMergeOptions {
  bool align = false;  // hand-held: frames aligned onto the middle one (capture/align.h)
  AlignModel align_model = AlignModel::kHomography;
  bool deghost = false;   // things that moved between frames taken from the middle frame (capture/ghosts.h)
  bool is_probe = false;  // ClipReachFor
  // Overrides ClipReachFor when ≥ −1 (−1: each channel clipped on its own;
  // N ≥ 0: a frame does not count within N px of a pixel it clips in two
  // channels). Below −1: ClipReachFor decides.
  int clip_reach = -2;
  const ResponseCurve* response = nullptr;  // reuse instead of recovering
};

// Wall time of MergeReadBracket's steps (the merge's own parts are in
// MergeResult), for `bench-merge --bracket` and `merge`'s summary.
struct MergeStageSeconds {
  double align = 0, response = 0, deghost = 0, merge = 0;
};

struct MergedBracket {
  MergeResult merge;
  MergeStageSeconds seconds;
  ResponseCurve response;
  MergeSidecar sidecar;         // filled but for the output paths and the command line
  std::vector<cv::Mat> frames;  // as merged (aligned when asked)
  cv::Mat ghosts;               // with deghost: CV_8U 255 where pixels came from the reference frame alone
};

// Align (when asked), check, recover or reuse the response, merge. FileError
// for a single 8-bit frame without a response, or a bracket that measured nothing.
MergedBracket MergeReadBracket(Bracket b, const BracketMergeOptions& opt);

// Where a merge goes: the linear EXR, the mask of unreliable pixels (PNG), the
// sidecar, and optionally the response curve (JSON) and its plot (8-bit
// brackets only).
struct MergeOutputs {
  std::string image, mask, sidecar;
  std::string ghosts;         // the ghost mask, when the merge detected ghosts
  std::string response_json;  // "" : not written
  std::string response_plot;  // "" : not drawn
  bool half = false;          // half-float EXR
  std::string command;        // recorded in the sidecar
};

// Writes every output atomically and returns the sidecar written. Error
// (before anything is written) when --half cannot hold the radiance.
MergeSidecar WriteMergeOutputs(const MergedBracket& m, const MergeOutputs& out);

}  // namespace brdfshot
