// Where a light probe's 8-bit JPEG frames are clipped, for all channels at once.
//
// JPEG's chroma subsampling spreads a clipped highlight's colour over 2×2
// blocks (and their upsampling over one more pixel), and so lowers codes the
// sensor clipped: a white spot clipped in every channel, between green
// leaves, decodes as (255, 255, 200). That blue then reads as a valid and far
// too dark measurement — in a merge weighted by t², the longest frame's, so
// it wins (the sun through forest.exr's leaves merged with blue 100× too
// low), and in response recovery it ties code 200 to a huge exposure. So for
// a JPEG light probe (merge --probe) a frame does not count at a pixel when, within `reach` px of
// it, a pixel has two or more channels clipped (a highlight near white; one
// clipped channel is a saturated colour, whose other channels are sound);
// the shorter frames measure that pixel.
// Lossless 8-bit frames (PNG, TIFF) keep per-channel clipping: on them the
// rule only throws good samples away (bench-merge: median error 0.66 → 0.73 %);
// so does a sphere's photo, where it cost more than it saved (merge.cc).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace brdfshot {

// The code at and above which an 8-bit frame is clipped by default
// (MergeOptions::high = 0.98 of 255).
constexpr int kClippedCode8 = 249;

// The reach that covers JPEG's 4:2:0 blocks and their upsampling.
constexpr int kJpegClipReach = 2;

// One CV_8U mask per frame, 255 within `reach` px (Chebyshev) of a pixel
// with two or more channels ≥ `clipped_code`. Empty for 16-bit frames (RAW, linear:
// no chroma subsampling, channels clip on their own) and for reach < 0.
std::vector<cv::Mat> ClippedNearby(const std::vector<cv::Mat>& frames, int clipped_code, int reach);

// The same for one pixel of one 8-bit frame (false for reach < 0): for the
// samples of response recovery, which need no whole-frame masks.
bool IsClippedNearby(const cv::Mat& frame, int x, int y, int clipped_code, int reach);

}  // namespace brdfshot
