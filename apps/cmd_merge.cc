// brdfshot merge: a bracketed series (LDR with EXIF or a times file, or RAW) to
// one linear-radiance EXR, a mask of pixels no frame measured well, and a JSON
// sidecar recording exposures, camera, response and the command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "apps/command.h"
#include "apps/common_options.h"
#include "capture/bracket.h"
#include "fit/plots.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

// The recovered curve as people draw it: relative exposure (log) against code,
// one line per channel, over the codes the frames actually contain (a code no
// pixel shows is only extrapolated by the smoothness term, and would stretch
// the axis without telling anything). A kink shows at a glance.
cv::Mat ResponsePlot(const ResponseCurve& r, const std::vector<cv::Mat>& frames) {
  // Which codes occur, from a grid of ~250 000 pixels per frame: the plot
  // needs no more, and a 12 MP bracket would otherwise cost half a merge.
  std::vector<std::array<long, 3>> count(r.levels, {0, 0, 0});
  const int step = std::max(1, static_cast<int>(std::sqrt(frames[0].total() / 250000.0)));
  long counted = 0;
  for (const cv::Mat& f : frames)
    for (int y = 0; y < f.rows; y += step)
      for (int x = 0; x < f.cols; x += step, ++counted)
        for (int c = 0; c < 3; ++c) ++count[f.at<cv::Vec3b>(y, x)[c]][c];
  const long min_count = std::max<long>(10, counted / 100000);
  std::vector<XYSeries> series;
  const char* names[3] = {"R", "G", "B"};
  const cv::Scalar bgr[3] = {{40, 40, 220}, {40, 160, 40}, {220, 80, 40}};
  for (int c = 0; c < 3; ++c) {
    XYSeries s{names[c], {}, {}, bgr[c]};
    for (int z = 1; z + 1 < r.levels; ++z)
      if (count[z][c] >= min_count) s.x.push_back(z), s.y.push_back(r.Linear(c, z));
    series.push_back(s);
  }
  return LogLogPlot(series, "response curve (" + r.kind + "), codes seen in the frames", "pixel code",
                    "relative exposure");
}

}  // namespace

int MergeMain(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::string times_path, response_in, response_out, out = "merged.exr", mask_out, sidecar;
  bool align = false, half = false, probe = false;
  std::string wb_arg, plot_out;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("input", po::value(&inputs)->multitoken(), "frames: files or a folder (positional)")
      ("times", po::value(&times_path), "exposure times file, one per frame in input order (overrides EXIF)")
      ("response", po::value(&response_in), "reuse a response curve (JSON) instead of recovering one")
      ("save-response", po::value(&response_out), "write the recovered response curve (JSON)")
      ("align", po::bool_switch(&align), "align hand-held frames by translation (median threshold bitmaps)")
      ("wb", po::value(&wb_arg), "RAW white balance R,G,B multipliers (default: the camera's)")
      ("mask", po::value(&mask_out), "mask PNG of unreliable pixels (default: <out>_mask.png)")
      ("sidecar", po::value(&sidecar), "JSON sidecar (default: <out>.json)")
      ("plot-response", po::value(&plot_out), "PNG plot of the response curve (default: <out>_response.png for 8-bit frames)")
      ("half", po::bool_switch(&half), "write half-float EXR (half the size; values above 65504 saturate)")
      ("probe", po::bool_switch(&probe),
       "the bracket is a light probe: with JPEG frames, a frame does not count near a highlight clipped in two "
       "channels (JPEG lowers the third; a small sun's power comes out far too low otherwise)")
      ("out,o", po::value(&out)->default_value(out), "merged linear radiance (.exr)");
  // clang-format on
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!ParseOptions("merge", "FRAME... | FOLDER [options]", desc, argc, argv, &pos)) return 0;
  const std::string stem = (fs::path(out).parent_path() / fs::path(out).stem()).string();
  if (mask_out.empty()) mask_out = stem + "_mask.png";
  if (sidecar.empty()) sidecar = stem + ".json";
  if (plot_out.empty()) plot_out = stem + "_response.png";
  BracketReadOptions read;
  read.times_path = times_path;
  read.progress = true;
  if (!wb_arg.empty()) {
    const std::vector<double> v = ParseNumberList(wb_arg, 3, "--wb", "R,G,B");
    read.white_balance_given = true;
    std::copy(v.begin(), v.end(), read.white_balance.begin());
  }
  BracketMergeOptions merge;
  merge.align = align;
  merge.is_probe = probe;
  ResponseCurve given;
  if (!response_in.empty())
    given = ResponseCurve::FromJson(ReadJsonFile(response_in), response_in), merge.response = &given;

  Stopwatch sw;
  const MergedBracket m = MergeReadBracket(ReadBracket(ExpandBracketInputs(inputs), read), merge);
  if (!response_out.empty())
    WriteFileAtomic(response_out, [&](std::ostream& o) { o << m.response.ToJson().dump(1) << "\n"; });
  double max_radiance = 0;
  cv::minMaxLoc(m.merge.radiance.reshape(1), nullptr, &max_radiance);
  if (half && max_radiance > 65504)
    throw Error("--half: the merged radiance reaches " + std::to_string(max_radiance) +
                ", beyond half float's 65504; drop --half or rescale the times");
  WriteExr(out, m.merge.radiance, half ? ExrPixel::kHalf : ExrPixel::kFloat);
  const bool plotted = m.frames[0].depth() == CV_8U;
  if (plotted) WritePng(plot_out, ResponsePlot(m.response, m.frames));
  WriteFileAtomicByName(mask_out, [&](const std::string& tmp) {
    if (!cv::imwrite(tmp, m.merge.mask)) throw FileError(tmp, "cannot write mask");
  });
  MergeSidecar side = m.sidecar;
  side.output = out;
  side.mask = mask_out;
  side.half = half;
  side.response_plot = plotted ? plot_out : "";
  side.command = CommandLine(argc, argv);
  side.Write(sidecar);
  std::printf("merged %zu frames (%dx%d, %s) in %.2f s: %.2f %% of pixels unreliable\nwrote %s, %s, %s\n",
              m.frames.size(), m.frames[0].cols, m.frames[0].rows, side.raw ? "RAW" : m.response.kind.c_str(),
              sw.Seconds(), 100 * m.merge.unreliable_fraction, out.c_str(), mask_out.c_str(), sidecar.c_str());
  return 0;
}

}  // namespace brdfshot
