// Alignment of a hand-held bracket onto its middle frame (by exposure).
//
// Exposure changes every intensity, so frames are compared where that change
// does not matter: translation by median-threshold bitmaps (Ward's MTB, as
// OpenCV's AlignMTB implements it), which an exposure change leaves nearly
// unchanged; a homography (rotation, translation and perspective, what a
// hand-held camera turning about its lens does) by OpenCV's ECC, after the
// frame's codes are mapped onto the reference's by matching histograms (two
// exposures differ by a monotone map of codes; the enhanced correlation
// coefficient is invariant to what affine difference remains). Frames far apart in exposure share few well-exposed
// pixels, so each frame is aligned to its neighbour towards the middle one
// and the warps are chained; MTB's shift starts each ECC, and ECC runs on a
// pyramid (coarse, then at up to 2000 px) for speed at 12 MP. Two frames
// with signal in common on less than a fifth of the image (the longest of a
// bracket is mostly clipped) cannot tell a homography and keep MTB's shift,
// unless the little they share does not correlate under it (then refused).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace brdfshot {

enum class AlignModel { kTranslation, kHomography };

struct AlignOptions {
  AlignModel model = AlignModel::kHomography;
  int max_shift_px = 64;                 // bounds MTB's search (its pyramid depth is chosen from it)
  double min_overlap = 0.5;              // of the reference frame a warped frame must cover, else refused
  double min_correlation = 0.5;          // ECC's correlation coefficient below which a pair is refused
  std::vector<std::string> frame_names;  // for messages (the files); empty: "frame <index>"
};

struct AlignedBracket {
  std::vector<cv::Mat> frames;  // warped onto the reference frame
  // Per frame, reference pixel → the frame's pixel (3 × 3, double; identity
  // for the reference). Translation: [[1, 0, −dx], [0, 1, −dy], [0, 0, 1]].
  std::vector<cv::Matx33d> warps;
  std::vector<cv::Point> shifts;  // translation only: what was applied to each frame (reference: 0, 0)
  int reference = 0;              // the middle frame by exposure
};

// `frames`: 8- or 16-bit RGB, same size; `times`: their exposures (the
// reference and the chaining order follow them). Borders a warp uncovers are
// filled with the nearest edge pixel so they do not read as black. Error
// naming the two frames when a pair overlaps less than `min_overlap` or does
// not correlate (not the same scene, or moved too far to align).
AlignedBracket AlignBracket(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                            const AlignOptions& options = {});

}  // namespace brdfshot
