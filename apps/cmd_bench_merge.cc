// brdfshot bench-merge: HDR merging against ground truth, side by side with
// OpenCV in one run (capture/merge_benchmark.h); with --bracket, the time of
// both merges of a bracket's own files (capture/merge_timing.h).
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "capture/bracket.h"
#include "capture/merge_benchmark.h"
#include "capture/merge_timing.h"
#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

int BenchMergeMain(int argc, char** argv) {
  MergeBenchmarkOptions o;
  std::vector<std::string> bracket;
  BracketReadOptions read;
  MergeTimingOptions timing;
  std::string probes_arg, data, size_arg = "4000x3000", out = "bench_merge",
                                methods_arg = "ours,ours-hat,ours-flat,cv-debevec,cv-robertson,pfstools,ours-raw";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("bracket", po::value(&bracket)->multitoken(),
       "time ours against OpenCV's Debevec merge on these 8-bit frames (files or a folder; no ground truth needed) "
       "instead of the synthetic benchmark")
      ("times", po::value(&read.times_path), "with --bracket: exposure times file (overrides EXIF)")
      ("repeats", po::value(&timing.repeats)->default_value(timing.repeats), "with --bracket: runs per method (medians)")
      ("probes", po::value(&probes_arg), "HDR scenes (default: every <data>/envmaps/*.exr)")
      ("data", po::value(&data), "data folder (default: $BRDFSHOT_DATA, then ../shared)")
      ("size", po::value(&size_arg)->default_value(size_arg), "WIDTHxHEIGHT the scenes are resampled to (12 MP)")
      ("frames", po::value(&o.frames)->default_value(o.frames), "exposures per bracket")
      ("stops", po::value(&o.stops)->default_value(o.stops), "EV between exposures")
      ("read-noise", po::value(&o.camera.read_noise)->default_value(o.camera.read_noise), "camera read noise (electrons)")
      ("full-well", po::value(&o.camera.full_well)->default_value(o.camera.full_well), "camera full well (electrons)")
      ("jpeg", po::value(&o.jpeg_quality)->default_value(o.jpeg_quality),
       "pass the 8-bit frames through JPEG at this quality (OpenCV's 4:2:0), as a camera's JPEGs; 0: lossless")
      ("exposure-shift", po::value(&o.exposure_shift_ev)->default_value(0), "shift every exposure by this many EV (e.g. -3: shadows below the longest frame's floor, as in a night bracket)")
      ("methods", po::value(&methods_arg)->default_value(methods_arg), "methods to run (cv-robertson takes minutes at 12 MP)")
      ("out,o", po::value(&out)->default_value(out), "output folder: table (markdown, CSV)");
  // clang-format on
  if (!ParseOptions("bench-merge", "[options]", desc, argc, argv)) return 0;
  if (!bracket.empty()) {
    const std::vector<std::string> files = ExpandBracketInputs(bracket);
    timing.progress = true;
    const std::string table = MergeTimingTable(TimeBracketMerges(files, read, timing),
                                               files.size() > 1 ? files[0] + " … " + files.back() : files[0]);
    std::printf("\n%s", table.c_str());
    MakeOutputDir(out);
    WriteFileAtomic(out + "/bench_merge_bracket.md", [&](std::ostream& s) { s << table; });
    std::printf("wrote %s/bench_merge_bracket.md\n", out.c_str());
    return 0;
  }
  o.size = ParseImageSize(size_arg, "--size", 16);
  if (o.frames < 2) throw Error("--frames must be at least 2");
  if (!(o.stops > 0)) throw Error("--stops must be positive");
  o.methods = SplitList(methods_arg);
  o.scenes = ResolveProbes(probes_arg, data);
  o.progress = true;
  MakeOutputDir(out);
  const MergeBenchmarkTables t = RunMergeBenchmark(o);
  std::printf("\n%s", t.markdown.c_str());
  WriteFileAtomic(out + "/bench_merge.md", [&](std::ostream& s) { s << t.markdown; });
  WriteFileAtomic(out + "/bench_merge.csv", [&](std::ostream& s) { s << t.csv; });
  std::printf("wrote %s/bench_merge.{md,csv}\n", out.c_str());
  return 0;
}

}  // namespace brdfshot
