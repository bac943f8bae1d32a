// brdfshot bench-basis: speed against error of the basis images (a benchmark,
// not a test; fit/basis_benchmark.h).
#include <cstdio>
#include <sstream>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/basis_benchmark.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

std::pair<int, int> ParseSamples(const std::string& text) {
  int a = 0, b = 0;
  char x = 0;
  std::istringstream s(text);
  if (!(s >> a >> x >> b) || x != 'x' || a <= 0 || b <= 0 || a > 4096 || b > 8192)
    throw Error("bad sample setting '" + text + "': expected THETAxPHI, e.g. 32x48");
  return {a, b};
}

std::vector<int> ParseInts(const std::string& text, const std::string& what) {
  std::vector<int> v;
  for (const std::string& s : SplitList(text)) {
    try {
      v.push_back(std::stoi(s));
    } catch (const std::exception&) {
      throw Error("bad " + what + " '" + s + "' in '" + text + "'");
    }
    if (v.back() <= 0) throw Error("bad " + what + " '" + s + "': must be positive");
  }
  return v;
}

}  // namespace

int BenchBasisMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs base_quality;
  BasisBenchmarkOptions o;
  std::string spheres = "64,128,256", widths = "256,512,1024", qualities = "12x24,16x32,24x40,32x48,32x64",
              reference = "192x384", out = "bench_basis";
  o.cache = "brdfshot_cache";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&o.probe), "lat-long probe (default: <data>/envmaps/forest.exr)")
      ("spheres", po::value(&spheres)->default_value(spheres), "sphere diameters in pixels")
      ("probe-widths", po::value(&widths)->default_value(widths), "probe widths the scene is given at")
      ("qualities", po::value(&qualities)->default_value(qualities), "half-vector samples THETAxPHI to compare")
      ("reference-samples", po::value(&reference)->default_value(reference), "samples of the converged reference")
      ("reference-pixels", po::value(&o.reference_pixels)->default_value(o.reference_pixels), "about this many pixels carry the error")
      ("repeats", po::value(&o.repeats)->default_value(o.repeats), "timing runs per setting (the median is reported)")
      ("margin", po::value(&o.margin_deg)->default_value(o.margin_deg), "max angle between normal and view (deg)")
      ("cache", po::value(&o.cache)->default_value(o.cache), "folder for cached references (test data, not committed)")
      ("out,o", po::value(&out)->default_value(out), "output folder: table (markdown, CSV) and plot");
  // clang-format on
  db.Add(desc);
  base_quality.Add(desc);
  if (!ParseOptions("bench-basis", "[options]", desc, argc, argv)) return 0;
  o.spheres = ParseInts(spheres, "sphere size");
  o.probe_widths = ParseInts(widths, "probe width");
  for (const std::string& q : SplitList(qualities)) o.qualities.push_back(ParseSamples(q));
  o.reference_samples = ParseSamples(reference);
  if (o.probe.empty()) o.probe = DataPath("envmaps/forest.exr", db.data);
  if (o.probe.empty()) throw Error("no probe given and no data folder: pass --probe or set BRDFSHOT_DATA");
  o.base_quality = base_quality.q;
  o.database = db.ToOptions(true);
  o.progress = true;
  MakeOutputDir(out);
  MakeOutputDir(o.cache);
  const BasisBenchmark b = RunBasisBenchmark(o);
  const std::string md = BasisBenchmarkMarkdown(b.rows), csv = BasisBenchmarkCsv(b.rows);
  std::printf("\n%s", md.c_str());
  WriteFileAtomic(out + "/bench_basis.md", [&](std::ostream& s) { s << md; });
  WriteFileAtomic(out + "/bench_basis.csv", [&](std::ostream& s) { s << csv; });
  WritePng(out + "/bench_basis.png", BasisBenchmarkPlot(b, o));
  std::printf("wrote %s/bench_basis.{md,csv,png}\n", out.c_str());
  return 0;
}

}  // namespace brdfshot
