// brdfshot merge: a bracketed series (LDR with EXIF or a times file, or RAW) to
// one linear-radiance EXR, a mask of pixels no frame measured well, and a JSON
// sidecar recording exposures, camera, response and the command line
// (capture/bracket.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "apps/common_options.h"
#include "capture/bracket.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

// The command line as typed; the options of each step follow from it.
struct MergeArgs {
  std::vector<std::string> inputs;
  std::string times, response_in, wb, out = "merged.exr";
  bool align = false, probe = false, deghost = false;
  int clip_reach = -2;
  std::string align_model = "homography";
  MergeOutputs outputs;

  void Add(po::options_description& desc) {
    // clang-format off
    desc.add_options()
        ("input", po::value(&inputs)->multitoken(), "frames: files or a folder (positional)")
        ("times", po::value(&times), "exposure times file, one per frame in input order (overrides EXIF)")
        ("response", po::value(&response_in), "reuse a response curve (JSON) instead of recovering one")
        ("save-response", po::value(&outputs.response_json), "write the recovered response curve (JSON)")
        ("align", po::bool_switch(&align), "align hand-held frames onto the middle one (rotation, shift and perspective; capture/align.h)")
        ("deghost", po::bool_switch(&deghost), "things that moved between frames (people, leaves) taken from the middle frame alone (where it is clipped or black, from the nearest frame that measures them); their mask goes to <out>_ghosts.png")
        ("align-model", po::value(&align_model)->default_value(align_model), "with --align: homography, or translation (median threshold bitmaps only)")
        ("wb", po::value(&wb), "RAW white balance R,G,B multipliers (default: the camera's)")
        ("mask", po::value(&outputs.mask), "mask PNG of unreliable pixels (default: <out>_mask.png)")
        ("sidecar", po::value(&outputs.sidecar), "JSON sidecar (default: <out>.json)")
        ("plot-response", po::value(&outputs.response_plot), "PNG plot of the response curve (default: <out>_response.png for 8-bit frames)")
        ("half", po::bool_switch(&outputs.half), "write half-float EXR (half the size; values above 65504 saturate)")
        ("probe", po::bool_switch(&probe),
         "the bracket is a light probe: with JPEG frames, a frame does not count near a highlight clipped in two "
         "channels (JPEG lowers the third; a small sun's power comes out far too low otherwise)")
        ("clip-reach", po::value(&clip_reach),
         "a frame does not count within N px of a pixel it clips in two channels (0: that pixel alone; -1: each "
         "channel clipped on its own). Default: 2 for JPEG light probes (--probe), -1 otherwise; `merge-check "
         "--clip-reach` tells which predicts a real bracket's frames better")
        ("out,o", po::value(&out)->default_value(out), "merged linear radiance (.exr)");
    // clang-format on
  }

  BracketReadOptions ReadOptions() const {
    BracketReadOptions read;
    read.times_path = times;
    read.progress = true;
    if (!wb.empty()) {
      const std::vector<double> v = ParseNumberList(wb, 3, "--wb", "R,G,B");
      read.white_balance_given = true;
      std::copy(v.begin(), v.end(), read.white_balance.begin());
    }
    return read;
  }

  MergeOutputs Outputs(const std::string& command) const {
    const std::string stem = (fs::path(out).parent_path() / fs::path(out).stem()).string();
    MergeOutputs o = outputs;
    o.image = out;
    if (o.mask.empty()) o.mask = stem + "_mask.png";
    if (o.sidecar.empty()) o.sidecar = stem + ".json";
    if (o.response_plot.empty()) o.response_plot = stem + "_response.png";
    o.ghosts = stem + "_ghosts.png";
    o.command = command;
    return o;
  }
};

}  // namespace

int MergeMain(int argc, char** argv) {
  MergeArgs args;
  po::options_description desc("options");
  args.Add(desc);
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!ParseOptions("merge", "FRAME... | FOLDER [options]", desc, argc, argv, &pos)) return 0;
  const MergeOutputs outputs = args.Outputs(CommandLine(argc, argv));
  BracketMergeOptions merge;
  merge.align = args.align;
  if (args.align_model != "homography" && args.align_model != "translation")
    throw Error("unknown --align-model '" + args.align_model + "': homography or translation");
  merge.align_model = args.align_model == "homography" ? AlignModel::kHomography : AlignModel::kTranslation;
  merge.is_probe = args.probe;
  merge.deghost = args.deghost;
  if ((args.clip_reach < -1 && args.clip_reach != -2) || args.clip_reach > 64)  // -2: not given
    throw Error("--clip-reach must be -1 … 64");
  merge.clip_reach = args.clip_reach;
  ResponseCurve given;
  if (!args.response_in.empty())
    given = ResponseCurve::FromJson(ReadJsonFile(args.response_in), args.response_in), merge.response = &given;

  Stopwatch sw;
  const MergedBracket m = MergeReadBracket(ReadBracket(ExpandBracketInputs(args.inputs), args.ReadOptions()), merge);
  const MergeSidecar side = WriteMergeOutputs(m, outputs);
  std::printf(
      "merged %zu frames (%dx%d, %s) in %.2f s: %.2f %% of pixels unreliable, %.2f %% too noisy for their own "
      "colour (taken from their neighbours)",
      m.frames.size(), m.frames[0].cols, m.frames[0].rows, side.raw ? "RAW" : m.response.kind.c_str(), sw.Seconds(),
      100 * m.merge.unreliable_fraction, 100 * m.merge.chroma_pooled_fraction);
  if (side.deghosted)
    std::printf(", %.2f %% moved between frames (taken from %s alone)", 100 * side.ghost_fraction,
                side.frames[side.reference_frame].value("file", "the middle frame").c_str());
  std::printf("\ntime: response %.2f s, merge %.2f s (noise model %.2f s, colour pooling %.2f s)", m.seconds.response,
              m.seconds.merge, m.merge.noise_seconds, m.merge.pool_seconds);
  if (args.align) std::printf(", alignment %.2f s", m.seconds.align);
  if (side.deghosted) std::printf(", ghost detection %.2f s", m.seconds.deghost);
  std::printf("\nwrote %s, %s, %s%s%s\n", outputs.image.c_str(), outputs.mask.c_str(), outputs.sidecar.c_str(),
              side.ghosts.empty() ? "" : ", ", side.ghosts.c_str());
  return 0;
}

}  // namespace brdfshot
