// brdfshot bench-basis: speed against error of the basis images (a benchmark,
// not a test). For each probe size, sphere size and quality setting it times
// building the operator and rendering all bases on the whole sphere (median of
// --repeats), and measures the relative RMSE of the reference materials' images
// against a converged reference on a pixel subset. References are cached.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/basis_reference.h"
#include "fit/loo_eval.h"
#include "util/plots.h"
#include "fit/transport.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

// Bumped whenever the reference integrator changes, so stale caches re-render.
constexpr int kReferenceVersion = 3;

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

// The cached reference if its header matches this scene, else renders and caches it.
BasisImages LoadOrRenderReference(const std::string& path, const PixelGeometry& g, const LatLongProbe& probe,
                                  const BasisDatabase& db, const std::vector<int>& mats, std::pair<int, int> samples,
                                  double* seconds) {
  *seconds = 0;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    BasisImages r = BasisImages::Read(path);
    if (r.header.value("geometry_hash", uint64_t{0}) == g.Hash() &&
        r.header.value("probe_hash", uint64_t{0}) == probe.Hash() &&
        r.header.value("samples", std::vector<int>{}) == std::vector<int>{samples.first, samples.second} &&
        r.header.value("reference_version", 0) == kReferenceVersion &&
        r.Y[0].cols() == static_cast<Eigen::Index>(3 * mats.size())) {
      *seconds = r.header.value("seconds", 0.0);
      return r;
    }
  }
  Progress progress("reference " + std::filesystem::path(path).filename().string(), mats.size(), true);
  Stopwatch sw;
  BasisImages r = RenderReferenceImages(g, probe, db, mats, samples.first, samples.second, &progress);
  *seconds = sw.Seconds();
  r.header["samples"] = {samples.first, samples.second};
  r.header["reference_version"] = kReferenceVersion;
  r.header["seconds"] = *seconds;
  r.Write(path);
  return r;
}

struct Row {
  int sphere, probe_width;
  std::string quality;
  size_t pixels, levels;
  double build_s, apply_s, brute_s;
  std::map<std::string, double> class_max;  // worst basis of each class
  double worst = 0;
};

}  // namespace

int BenchBasisMain(int argc, char** argv) {
  DatabaseArgs db;
  std::string probe_path, spheres_arg = "64,128,256", probes_arg = "256,512,1024",
                          qualities_arg = "12x24,16x32,24x40,32x48,32x64", ref_arg = "192x384",
                          cache = "brdfshot_cache", out = "bench_basis";
  int ref_pixels = 700, repeats = 3;
  QualityArgs base_quality;
  double margin = 80;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path), "lat-long probe (default: <data>/envmaps/forest.exr)")
      ("spheres", po::value(&spheres_arg)->default_value(spheres_arg), "sphere diameters in pixels")
      ("probe-widths", po::value(&probes_arg)->default_value(probes_arg), "probe widths the scene is given at")
      ("qualities", po::value(&qualities_arg)->default_value(qualities_arg), "half-vector samples THETAxPHI to compare")
      ("reference-samples", po::value(&ref_arg)->default_value(ref_arg), "samples of the converged reference")
      ("reference-pixels", po::value(&ref_pixels)->default_value(ref_pixels), "about this many pixels carry the error")
      ("repeats", po::value(&repeats)->default_value(repeats), "timing runs per setting (the median is reported)")
      ("margin", po::value(&margin)->default_value(margin), "max angle between normal and view (deg)")
      ("cache", po::value(&cache)->default_value(cache), "folder for cached references (test data, not committed)")
      ("out,o", po::value(&out)->default_value(out), "output folder: table (markdown, CSV) and plot");
  // clang-format on
  db.Add(desc);
  base_quality.Add(desc);
  if (!ParseOptions("bench-basis", "[options]", desc, argc, argv)) return 0;
  const std::vector<int> spheres = ParseInts(spheres_arg, "sphere size");
  const std::vector<int> widths = ParseInts(probes_arg, "probe width");
  std::vector<std::pair<int, int>> qualities;
  for (const std::string& q : SplitList(qualities_arg)) qualities.push_back(ParseSamples(q));
  const std::pair<int, int> ref_samples = ParseSamples(ref_arg);
  if (probe_path.empty()) probe_path = DataPath("envmaps/forest.exr", db.data);
  if (probe_path.empty()) throw Error("no probe given and no data folder: pass --probe or set BRDFSHOT_DATA");
  MakeOutputDir(out);
  MakeOutputDir(cache);

  const LatLongProbe full = LatLongProbe::Read(probe_path);
  const BasisDatabase base = LoadDatabase(db.ToOptions(true));
  const std::vector<int> ref_mats = ReferenceMaterialIndices(base);
  if (ref_mats.empty()) throw Error("database '" + base.label + "' has none of the reference materials (MERL names)");
  std::vector<std::string> ref_class;
  for (int m : ref_mats) ref_class.push_back(ReferenceClassOf(base.materials[m]));
  const MatrixXfR Bref = MaterialColumns(base, ref_mats);

  std::vector<Row> rows;
  for (int width : widths) {
    const LatLongProbe probe = width < full.width() ? full.Resized(width) : full;
    for (int sphere : spheres) {
      const PixelGeometry g = OrthographicSphere(sphere, margin);
      const int step = std::max(1, static_cast<int>(std::lround(std::sqrt(double(g.size()) / ref_pixels))));
      const PixelGeometry sub = Subsample(g, step);
      double t_ref = 0;
      const std::string ref_path = cache + "/reference_" + full.name() + "_" + std::to_string(width) + "_s" +
                                   std::to_string(sphere) + "_step" + std::to_string(step) + ".bsbi";
      const BasisImages ref = LoadOrRenderReference(ref_path, sub, probe, base, ref_mats, ref_samples, &t_ref);
      // Brute force for all bases of the whole sphere, from its measured rate.
      const double brute = t_ref / (double(sub.size()) * ref_mats.size()) * g.size() * base.num_materials();
      for (const auto& [nt, np] : qualities) {
        RenderQuality q = base_quality.q;
        q.theta_samples = nt;
        q.phi_samples = np;
        q.probe_width = 0;  // the scene's probe as given: its size is the variable here
        std::vector<double> tb, ta;
        size_t nlev = 0;
        const int runs = std::max(1, repeats);
        for (int r = 0; r < runs; ++r) {
          Stopwatch sw;
          const TransportOperator t = TransportOperator::Build(g, probe, base.grid, q);
          tb.push_back(sw.Seconds());
          Stopwatch sa;
          const auto Y = t.Apply(base.B);
          ta.push_back(sa.Seconds());
          nlev = t.levels();
        }
        Row row{
            sphere, width, std::to_string(nt) + "x" + std::to_string(np), g.size(), nlev, Median(tb), Median(ta), brute,
            {},     0};
        row.class_max =
            WorstErrorPerLabel(TransportOperator::Build(sub, probe, base.grid, q).Apply(Bref), ref.Y, ref_class);
        for (const auto& [cls, e] : row.class_max) row.worst = std::max(row.worst, e);
        rows.push_back(row);
        std::printf("probe %4d  sphere %3d  %-6s  build %6.3f s  apply %6.3f s  worst error %.4f\n", width, sphere,
                    row.quality.c_str(), row.build_s, row.apply_s, row.worst);
        std::fflush(stdout);
      }
    }
  }

  std::ostringstream md, csv;
  md << "| probe | sphere | samples | pixels | θo levels | build s | apply s | total s |";
  csv << "probe_width,sphere,samples,pixels,levels,build_s,apply_s,total_s";
  for (const auto& c : ReferenceClasses()) md << " " << c.name << " |", csv << "," << c.name;
  md << " worst | brute force s (est.) |\n|---|---|---|---|---|---|---|---|";
  csv << ",worst,brute_force_s\n";
  for (size_t i = 0; i < ReferenceClasses().size() + 2; ++i) md << "---|";
  md << "\n";
  char buf[256];
  for (const Row& r : rows) {
    std::snprintf(buf, sizeof buf, "| %d | %d | %s | %zu | %zu | %.3f | %.3f | %.3f |", r.probe_width, r.sphere,
                  r.quality.c_str(), r.pixels, r.levels, r.build_s, r.apply_s, r.build_s + r.apply_s);
    md << buf;
    std::snprintf(buf, sizeof buf, "%d,%d,%s,%zu,%zu,%.4f,%.4f,%.4f", r.probe_width, r.sphere, r.quality.c_str(),
                  r.pixels, r.levels, r.build_s, r.apply_s, r.build_s + r.apply_s);
    csv << buf;
    for (const auto& c : ReferenceClasses()) {
      const auto it = r.class_max.find(c.name);
      const double e = it == r.class_max.end() ? -1 : it->second;
      std::snprintf(buf, sizeof buf, " %.4f |", e), md << buf;
      std::snprintf(buf, sizeof buf, ",%.5f", e), csv << buf;
    }
    std::snprintf(buf, sizeof buf, " %.4f | %.0f |\n", r.worst, r.brute_s), md << buf;
    std::snprintf(buf, sizeof buf, ",%.5f,%.1f\n", r.worst, r.brute_s), csv << buf;
  }
  std::printf("\n%s", md.str().c_str());
  WriteFileAtomic(out + "/bench_basis.md", [&](std::ostream& o) { o << md.str(); });
  WriteFileAtomic(out + "/bench_basis.csv", [&](std::ostream& o) { o << csv.str(); });
  // Colour = sphere size, marker = probe width: nine series stay apart. Each
  // line runs through the qualities in the order given.
  std::vector<XYSeries> series;
  for (const Row& r : rows) {
    const std::string name = "probe " + std::to_string(r.probe_width) + ", sphere " + std::to_string(r.sphere) + " px";
    if (series.empty() || series.back().name != name) {
      XYSeries s{name, {}, {}};
      s.color = ClassColor(static_cast<int>(std::find(spheres.begin(), spheres.end(), r.sphere) - spheres.begin()));
      s.marker = static_cast<int>(std::find(widths.begin(), widths.end(), r.probe_width) - widths.begin()) % 3;
      series.push_back(s);
    }
    series.back().x.push_back(r.build_s + r.apply_s);
    series.back().y.push_back(std::max(r.worst, 1e-6));
  }
  WritePng(out + "/bench_basis.png",
           LogLogPlot(series, "basis images: time against error (" + base.label + ")",
                      "seconds (build + apply, all bases); points along a line: " + qualities_arg,
                      "worst rel. RMSE over the reference materials", 0.01, "goal 1 %"));
  std::printf("wrote %s/bench_basis.{md,csv,png}\n", out.c_str());
  return 0;
}

}  // namespace brdfshot
