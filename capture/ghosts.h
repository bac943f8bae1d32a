// Ghosts: things that moved between the frames of a bracket (people, leaves,
// cars). Merged as they are, each frame puts its own copy of the moving thing
// into the result — a double image. A frame's pixel is a ghost where its
// radiance estimate disagrees with the reference frame's beyond their noise;
// the merge then does not count that frame there, so the pixel comes from the
// reference frame (and the frames that agree with it).
//
// The test needs both frames to measure the pixel: where the reference is
// clipped or black, a moving thing is not detected (shoot the reference
// frame, the middle exposure, so that the moving parts are well exposed).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "capture/merge.h"
#include "capture/response.h"

namespace brdfshot {

struct GhostOptions {
  double sigmas = 5;           // disagreement in standard deviations of the difference…
  double min_relative = 0.15;  // …and as a ratio (response error and misregistration stay below it)
  int grow_px = 2;             // a ghost region is grown by this many pixels (its soft edges)
};

// Per frame, CV_8U 255 where it disagrees with `reference`, or with its stand-in
// where the reference does not measure (never in the frame a pixel is taken from). `frames` as MergeBracket's; `noise` from EstimateNoise.
std::vector<cv::Mat> DetectGhosts(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                                  const ResponseCurve& response, int reference, const NoiseModel& noise,
                                  const GhostOptions& options = {});

// The union of the frames' ghost masks: the pixels taken from the reference.
cv::Mat GhostUnion(const std::vector<cv::Mat>& ghosts);

}  // namespace brdfshot
