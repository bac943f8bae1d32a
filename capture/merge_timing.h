// Where the time of a merge goes, on a bracket's own files: ours (ReadBracket
// and MergeReadBracket, as `brdfshot merge` runs them, images on huge pages:
// util/huge_pages.h) beside OpenCV's CalibrateDebevec + MergeDebevec as an
// OpenCV program runs them (its own allocator) and with our allocator, all
// reading the same files in the same run (`brdfshot bench-merge --bracket`). Ground truth is not needed: this is the
// speed half of the merge benchmark for real brackets; `merge-check` is the
// accuracy half.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "capture/bracket.h"

namespace brdfshot {

// Seconds per step, each the median over the repeats. OpenCV's merge has no
// noise model, pooling or alignment: those stay 0 for it.
struct MergeTiming {
  std::string method;
  double read = 0;      // decoding the files (ours: with EXIF, orientation and the JPEG completeness check)
  double response = 0;  // recovering the response curve
  double noise = 0;     // ours: the noise model estimated from the frames (part of `merge`)
  double pool = 0;      // ours: colour pooling of noisy pixels (part of `merge`)
  double merge = 0;     // the merge itself, with `noise` and `pool`
  double total = 0;     // read + response + merge, timed as one
};

struct BracketTimings {
  int frames = 0, repeats = 0;
  cv::Size size;
  // "brdfshot", "OpenCV Debevec" (OpenCV's allocator), "OpenCV Debevec,
  // huge-page images" (ours): the ratios are to the second.
  std::vector<MergeTiming> methods;
};

struct MergeTimingOptions {
  int repeats = 3;  // each method run this often, alternating; medians reported
  bool progress = false;
};

// Times both merges of the 8-bit bracket `files` (read.times_path as for
// `merge`). OpenCV is given the exposures our reader found (it reads no
// EXIF); that read is not timed for it. FileError for a file that cannot be
// read, Error for a bracket that is not 8-bit.
BracketTimings TimeBracketMerges(const std::vector<std::string>& files, const BracketReadOptions& read,
                                 const MergeTimingOptions& opt = {});

// A markdown table: what was timed (`source` names the frames), then a row
// per method with its steps and the ratio of its total to OpenCV's.
std::string MergeTimingTable(const BracketTimings& timings, const std::string& source);

}  // namespace brdfshot
