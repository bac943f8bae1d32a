#include "fit/basis_benchmark.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "fit/basis_reference.h"
#include "util/check.h"
#include "util/plots.h"
#include "util/progress.h"
#include "util/stats.h"

namespace brdfshot {
namespace {

// Bumped whenever the reference integrator changes, so stale caches re-render.
constexpr int kReferenceVersion = 3;

// Both tables at once: they share every number.
std::pair<std::string, std::string> Tables(const std::vector<BasisBenchmarkRow>& rows) {
  std::ostringstream md, csv;
  md << "| probe | sphere | samples | pixels | θo levels | build s | apply s | total s |";
  csv << "probe_width,sphere,samples,pixels,levels,build_s,apply_s,total_s";
  for (const auto& c : ReferenceClasses()) md << " " << c.name << " |", csv << "," << c.name;
  md << " worst | brute force s (est.) |\n|---|---|---|---|---|---|---|---|";
  csv << ",worst,brute_force_s\n";
  for (size_t i = 0; i < ReferenceClasses().size() + 2; ++i) md << "---|";
  md << "\n";
  char buf[256];
  for (const BasisBenchmarkRow& r : rows) {
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
  return {md.str(), csv.str()};
}

}  // namespace

BasisImages LoadOrRenderReference(const std::string& path, const PixelGeometry& g, const LatLongProbe& probe,
                                  const BasisDatabase& db, const std::vector<int>& mats, std::pair<int, int> samples,
                                  bool show_progress, double* seconds) {
  *seconds = 0;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    BasisImages r;
    try {
      r = BasisImages::Read(path);
    } catch (const Error& e) {  // a damaged cache is rendered anew, never trusted
      std::fprintf(stderr, "warning: %s; rendering the reference again\n", e.what());
    }
    if (r.header.is_object() && r.header.value("geometry_hash", uint64_t{0}) == g.Hash() &&
        r.header.value("probe_hash", uint64_t{0}) == probe.Hash() &&
        r.header.value("samples", std::vector<int>{}) == std::vector<int>{samples.first, samples.second} &&
        r.header.value("reference_version", 0) == kReferenceVersion &&
        r.Y[0].cols() == static_cast<Eigen::Index>(3 * mats.size())) {
      *seconds = r.header.value("seconds", 0.0);
      return r;
    }
  }
  Progress progress("reference " + std::filesystem::path(path).filename().string(), mats.size(), show_progress);
  Stopwatch sw;
  BasisImages r = RenderReferenceImages(g, probe, db, mats, samples.first, samples.second, &progress);
  *seconds = sw.Seconds();
  r.header["samples"] = {samples.first, samples.second};
  r.header["reference_version"] = kReferenceVersion;
  r.header["seconds"] = *seconds;
  r.Write(path);
  return r;
}

BasisBenchmark RunBasisBenchmark(const BasisBenchmarkOptions& o) {
  const LatLongProbe full = LatLongProbe::Read(o.probe);
  const BasisDatabase base = LoadDatabase(o.database);
  const std::vector<int> ref_mats = ReferenceMaterialIndices(base);
  if (ref_mats.empty()) throw Error("database '" + base.label + "' has none of the reference materials (MERL names)");
  std::vector<std::string> ref_class;
  for (int m : ref_mats) ref_class.push_back(ReferenceClassOf(base.materials[m]));
  const MatrixXfR Bref = MaterialColumns(base, ref_mats);

  BasisBenchmark result;
  result.database_label = base.label;
  std::vector<BasisBenchmarkRow>& rows = result.rows;
  for (int width : o.probe_widths) {
    const LatLongProbe probe = width < full.width() ? full.Resized(width) : full;
    for (int sphere : o.spheres) {
      const PixelGeometry g = OrthographicSphere(sphere, o.margin_deg);
      const int step = std::max(1, static_cast<int>(std::lround(std::sqrt(double(g.size()) / o.reference_pixels))));
      const PixelGeometry sub = Subsample(g, step);
      double t_ref = 0;
      const std::string ref_path = o.cache + "/reference_" + full.name() + "_" + std::to_string(width) + "_s" +
                                   std::to_string(sphere) + "_step" + std::to_string(step) + ".bsbi";
      const BasisImages ref =
          LoadOrRenderReference(ref_path, sub, probe, base, ref_mats, o.reference_samples, o.progress, &t_ref);
      // Brute force for all bases of the whole sphere, from its measured rate.
      const double brute = t_ref / (double(sub.size()) * ref_mats.size()) * g.size() * base.num_materials();
      for (const auto& [nt, np] : o.qualities) {
        RenderQuality q = o.base_quality;
        q.theta_samples = nt;
        q.phi_samples = np;
        q.probe_width = 0;  // the scene's probe as given: its size is the variable here
        std::vector<double> tb, ta;
        size_t nlev = 0;
        const int runs = std::max(1, o.repeats);
        for (int r = 0; r < runs; ++r) {
          Stopwatch sw;
          const TransportOperator t = TransportOperator::Build(g, probe, base.grid, q);
          tb.push_back(sw.Seconds());
          Stopwatch sa;
          const auto Y = t.Apply(base.B);
          ta.push_back(sa.Seconds());
          nlev = t.levels();
        }
        BasisBenchmarkRow row{
            sphere, width, std::to_string(nt) + "x" + std::to_string(np), g.size(), nlev, Median(tb), Median(ta), brute,
            {},     0};
        row.class_max =
            WorstErrorPerLabel(TransportOperator::Build(sub, probe, base.grid, q).Apply(Bref), ref.Y, ref_class);
        for (const auto& [cls, e] : row.class_max) row.worst = std::max(row.worst, e);
        rows.push_back(row);
        if (o.progress) {
          std::printf("probe %4d  sphere %3d  %-6s  build %6.3f s  apply %6.3f s  worst error %.4f\n", width, sphere,
                      row.quality.c_str(), row.build_s, row.apply_s, row.worst);
          std::fflush(stdout);
        }
      }
    }
  }

  return result;
}

std::string BasisBenchmarkMarkdown(const std::vector<BasisBenchmarkRow>& rows) { return Tables(rows).first; }
std::string BasisBenchmarkCsv(const std::vector<BasisBenchmarkRow>& rows) { return Tables(rows).second; }

cv::Mat BasisBenchmarkPlot(const BasisBenchmark& b, const BasisBenchmarkOptions& o) {
  const std::vector<BasisBenchmarkRow>& rows = b.rows;
  const std::vector<int>& spheres = o.spheres;
  const std::vector<int>& widths = o.probe_widths;
  std::string qualities;
  for (const auto& [nt, np] : o.qualities)
    qualities += (qualities.empty() ? "" : ",") + std::to_string(nt) + "x" + std::to_string(np);
  // Colour = sphere size, marker = probe width: nine series stay apart. Each
  // line runs through the qualities in the order given.
  std::vector<XYSeries> series;
  for (const BasisBenchmarkRow& r : rows) {
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
  return LogLogPlot(series, "basis images: time against error (" + b.database_label + ")",
                    "seconds (build + apply, all bases); points along a line: " + qualities,
                    "worst rel. RMSE over the reference materials", 0.01, "goal 1 %");
}

}  // namespace brdfshot
