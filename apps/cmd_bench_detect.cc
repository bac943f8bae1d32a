// brdfshot bench-detect: sphere detection against known truth, beside OpenCV's
// HoughCircles alone, in one run (normals/detect_benchmark.h).
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "normals/detect_benchmark.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

int BenchDetectMain(int argc, char** argv) {
  DetectBenchmarkOptions o;
  std::string sizes = "640x480,4000x3000";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("sizes", po::value(&sizes)->default_value(sizes), "image sizes WxH, comma-separated (4000x3000 = 12 MP)")
      ("seeds", po::value(&o.seeds)->default_value(o.seeds), "scenes per size and camera")
      ("noise", po::value(&o.noise)->default_value(o.noise), "additive Gaussian noise (image values ~0.05 … 1)")
      ("blur", po::value(&o.blur)->default_value(o.blur), "optical blur sigma, px (the same at every size: a sharp lens blurs ~1 px whatever the sensor)")
      ("clutter", po::value(&o.clutter)->default_value(o.clutter), "background shapes (rectangles, discs, rings)")
      ("verbose,v", po::bool_switch(&o.verbose), "print every scene's truth and detection")
      ("dump", po::value(&o.dump), "write every scene as a tone-mapped PNG into this folder")
      ("focal", po::value(&o.focal_factor)->default_value(o.focal_factor), "perspective focal length, in image widths");
  // clang-format on
  if (!ParseOptions("bench-detect", "[options]", desc, argc, argv)) return 0;
  if (o.seeds < 1) throw Error("--seeds must be at least 1");
  o.sizes.clear();
  for (const std::string& s : SplitList(sizes)) o.sizes.push_back(ParseImageSize(s, "--sizes", 64));
  o.progress = true;
  std::printf("%s", DetectBenchmarkTable(RunDetectBenchmark(o)).c_str());
  return 0;
}

}  // namespace brdfshot
