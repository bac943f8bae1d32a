// How good a merge of a real bracket is, without ground truth.
//
// Leave one frame out: merge the bracket without frame k, predict frame k's
// codes from the merged radiance through the method's own response and k's
// exposure, and compare with the codes frame k really holds where it shows
// mid-tones (codes 32 … 223 in every channel: a real frame's darkest codes
// are its black level and noise, its brightest near clipping). A merge that
// is right everywhere predicts every frame to within its noise; wrong
// weights, a wrong response or misregistration show as error. The chroma
// error compares the rg chromaticity of the prediction with the frame's own
// (through the same response), so colour noise counts apart from brightness.
//
// Chroma speckle: isolated pixels of random saturated hue in the shadows,
// where every frame is noisy — the share of the darkest pixels whose
// chromaticity is far from their neighbourhood's median.
#pragma once

#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace brdfshot {

// A merge and the response it used: lin[c][z], the linear value of code z in
// channel c (monotone; the units of `radiance` × exposure).
struct MergeAndResponse {
  cv::Mat radiance;  // CV_32FC3
  std::array<std::vector<double>, 3> lin;
};
using BracketMerger =
    std::function<MergeAndResponse(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times)>;

// Our merge (RecoverResponse, MergeBracket with its defaults) and OpenCV's
// (CalibrateDebevec + MergeDebevec), for 8-bit RGB frames. `clip_reach`: as
// MergeOptions' (−1: each channel clipped on its own, the default for frames
// that are not a JPEG light probe's).
MergeAndResponse OurMerge(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times, int clip_reach = -1);
MergeAndResponse OpenCvDebevecMerge(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times);

struct LeftOutFrame {
  int frame = 0;  // index in the bracket
  double time = 0;
  long pixels = 0;                     // mid-tones in every channel (codes 32 … 223)
  std::array<double, 3> code_error{};  // median |predicted − real| code, per channel
  double chroma_error = 0;             // median distance of rg chromaticities
};

// Every frame but the shortest and the longest left out in turn (those two
// fix the range the others are predicted within). Needs ≥ 3 frames.
std::vector<LeftOutFrame> LeaveOneFrameOut(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times,
                                           const BracketMerger& merge);

// The share of pixels darker than the `dark_quantile` of luminance whose rg
// chromaticity lies more than `distance` from the median chromaticity of their
// window × window neighbourhood. `radiance`: CV_32FC3 RGB.
double ChromaSpeckle(const cv::Mat& radiance, double dark_quantile = 0.2, double distance = 0.15, int window = 5);

// A real bracket checked both ways, ours against OpenCV's Debevec merge: every
// inner frame left out in turn, and the shadow speckle of each full merge.
struct MergeCheck {
  std::vector<LeftOutFrame> ours, opencv;
  double ours_speckle = 0, opencv_speckle = 0;
  double ours_seconds = 0, opencv_seconds = 0;  // the full merges
};

// 8-bit RGB frames only (a merge of RAW frames has no response to check).
// `clip_reach`: our merge's (OurMerge).
MergeCheck CheckMerges(const std::vector<cv::Mat>& rgb8, const std::vector<double>& times, int clip_reach = -1);

// The check as a markdown table: a row per left-out frame and method, then
// the medians over frames and the speckle.
std::string MergeCheckTable(const MergeCheck& check);

}  // namespace brdfshot
