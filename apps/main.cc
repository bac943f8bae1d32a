// brdfshot: one executable, subcommands registered in a table.
#include <cstdio>
#include <cstring>
#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <unistd.h>
#include <exception>
#include <iostream>
#include <set>
#include <string>

#include "apps/command.h"
#include "util/check.h"
#include "util/heap_reuse.h"
#include "util/huge_pages.h"

namespace brdfshot {
namespace po = boost::program_options;

const std::vector<Command>& Commands() {
  static const std::vector<Command> kCommands = {
      {"synth-capture",
       "a synthetic capture folder: bracketed JPEGs of a known material on a sphere, the probe's bracket, the truth",
       SynthCaptureMain},
      {"merge", "bracketed frames (LDR + EXIF/times, or RAW) to linear HDR EXR + mask + sidecar", MergeMain},
      {"merge-check", "how good a merge of a real bracket is: each frame predicted from the others, beside OpenCV",
       MergeCheckMain},
      {"calib", "light probe to lat-long (lat-long, angular map, mirror ball), rotation and scale to the camera",
       CalibMain},
      {"normals", "find the sphere in a photo to sub-pixel accuracy: sphere file + overlay", NormalsMain},
      {"remap", "photo + sphere + calibration -> observation file (radiance, normal, view in the probe frame)",
       RemapMain},
      {"synth-db", "write the analytic stand-in materials as MERL .binary files", SynthDbMain},
      {"nbrdf-db", "write MERL's materials from their neural fits as MERL .binary files", NbrdfDbMain},
      {"render", "render one BRDF on a sphere under a probe (EXR + PNG)", RenderMain},
      {"basis", "basis images of a scene (every basis BRDF under the probe), cached", BasisMain},
      {"cluster", "class model of the database: SVD + GMM, MDS picture (paper sec. 3)", ClusterMain},
      {"fit", "fit a photo: class-wise regularised solve, BRDF + previews", FitMain},
      {"report",
       "one capture's results as markdown + pictures: photo, sphere, class and residuals, relit vs truth, stage times",
       ReportMain},
      {"compare", "relative RMSE of one linear image against a reference", CompareMain},
      {"score", "a fit's relit error on a photo it was not fitted to (the same object under another light)", ScoreMain},
      {"bench-merge", "HDR merge against ground truth, beside OpenCV's Debevec and Robertson", BenchMergeMain, true},
      {"bench-detect", "sphere detection vs known truth, beside OpenCV HoughCircles alone (error and time)",
       BenchDetectMain, true},
      {"bench-basis", "basis images: speed against error vs a cached converged reference", BenchBasisMain, true},
      {"eval", "the fit on unseen lighting and materials, against its baselines (evaluation sets a and b)", EvalMain,
       true},
  };
  return kCommands;
}

std::string CommandLine(int argc, char** argv) {
  std::string line = "brdfshot";
  for (int i = 0; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

bool ParseOptions(const std::string& command, const std::string& usage, po::options_description& desc, int argc,
                  char** argv, po::positional_options_description* positional, std::vector<std::string>* given) {
  // clang-format off
  desc.add_options()("help,h", "show this help");
  // clang-format on
  // Two options of one name (a command's own and a shared group's) make every
  // use of that name "ambiguous" at run time: a programming error, caught here.
  std::set<std::string> names;
  for (const auto& o : desc.options())
    BRDFSHOT_CHECK(names.insert(o->long_name()).second,
                   "brdfshot " + command + " registers --" + o->long_name() + " twice");
  po::variables_map vm;
  try {
    po::command_line_parser parser(argc, argv);
    parser.options(desc);
    if (positional) parser.positional(*positional);
    const po::parsed_options parsed = parser.run();
    if (given)
      for (const po::option& o : parsed.options) given->push_back(o.string_key);
    po::store(parsed, vm);
    if (vm.count("help")) {
      std::cout << "usage: brdfshot " << command << " " << usage << "\n\n" << desc << "\n";
      return false;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw Error("brdfshot " + command + ": " + e.what() + " (see --help)");
  }
  return true;
}

}  // namespace brdfshot

static void PrintUsage() {
  std::printf(
      "brdfshot — BRDF from one photo of a sphere under known lighting\n\n"
      "usage: brdfshot <command> [options]   (brdfshot <command> --help)\n\ncommands:\n");
  for (const auto& c : brdfshot::Commands())
    if (!c.developer_tool) std::printf("  %-14s %s\n", c.name, c.summary);
  std::printf("\ndeveloper tools (benchmarks and the evaluation, docs/benchmarks.md):\n");
  for (const auto& c : brdfshot::Commands())
    if (c.developer_tool) std::printf("  %-14s %s\n", c.name, c.summary);
}

// With BRDFSHOT_TIME_LOG set, each successful command appends one line
// "seconds<TAB>command line" to that file: a Makefile run gives the wall time
// of every stage without a `time` binary (the report's stage table reads it).
// One write(2) of one short line in append mode, so parallel makes interleave
// whole lines.
static void LogStageTime(int argc, char** argv, double seconds) {
  const char* log = std::getenv("BRDFSHOT_TIME_LOG");
  if (!log || !*log) return;
  const std::string line = std::to_string(seconds) + "\t" + brdfshot::CommandLine(argc - 1, argv + 1) + "\n";
  const int fd = ::open(log, O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd < 0) return;                              // timing is a convenience: never fail a stage over it
  if (::write(fd, line.data(), line.size()) < 0) { /* same */
  }
  ::close(fd);
}

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  for (const auto& c : brdfshot::Commands()) {
    if (std::strcmp(argv[1], c.name) != 0) continue;
    cv::Mat::setDefaultAllocator(brdfshot::HugePageMatAllocator());  // util/huge_pages.h: why
    brdfshot::KeepFreedHeapMemory();                                 // util/heap_reuse.h: why
    try {
      const auto start = std::chrono::steady_clock::now();
      const int rc = c.run(argc - 1, argv + 1);
      LogStageTime(argc, argv, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      return rc;
    } catch (const brdfshot::Error& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "internal error: %s\n", e.what());
      return 3;
    }
  }
  std::fprintf(stderr, "error: unknown command '%s'\n\n", argv[1]);
  PrintUsage();
  return 2;
}
