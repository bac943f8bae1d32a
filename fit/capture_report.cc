#include "fit/capture_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "calib/calibration.h"
#include "capture/merge_sidecar.h"
#include "fit/photo_fit.h"
#include "util/plots.h"
#include "fit/synthetic_capture.h"
#include "normals/sphere_view.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_error.h"
#include "util/image_io.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}
std::string Sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", v);
  return buf;
}

}  // namespace

std::vector<std::pair<std::string, double>> StageTimes(const std::string& path) {
  std::vector<std::pair<std::string, double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    std::istringstream words(line.substr(tab + 1));
    std::string w, cmd, out, prev;
    words >> w >> cmd;
    while (words >> w) {
      // Every output a command names (render writes one per BRDF).
      if (prev == "-o" || prev == "--out") out += (out.empty() ? "" : ", ") + fs::path(w).filename().string();
      prev = w;
    }
    const std::string key = cmd + (out.empty() ? "" : " → " + out);
    const double t = std::atof(line.c_str());
    auto it = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == key; });
    if (it == rows.end())
      rows.push_back({key, t});
    else
      it->second = t;
  }
  return rows;
}

CaptureReport WriteCaptureReport(const CaptureReportOptions& o) {
  const fs::path r(o.results);
  if (!fs::is_directory(r)) throw FileError(o.results, "is not a results folder");
  const std::string out = o.out.empty() ? (r / "report.md").string() : o.out;
  const std::string title = o.title.empty() ? fs::absolute(r).lexically_normal().filename().string() : o.title;
  const fs::path pics = r / "report";
  fs::create_directories(pics);
  auto rel = [&](const fs::path& p) {
    return fs::relative(p, fs::path(out).parent_path().empty() ? "." : fs::path(out).parent_path()).string();
  };
  std::ostringstream md;
  CaptureReport report;
  md << "# brdfshot report: " << title << "\n\n";

  // The photo and the sphere found in it.
  const fs::path photo = r / "photo.exr";
  if (fs::exists(photo)) {
    const cv::Mat img = ReadHdrImage(photo.string());
    WritePngTonemapped((pics / "photo.png").string(), img, AutoExposure(img));
    md << "| merged photo | sphere found (rim points green, fit red) |\n|---|---|\n| ![photo]("
       << rel(pics / "photo.png") << ") | ![sphere](" << rel(r / "sphere.png") << ") |\n\n";
  }
  md << "## Capture\n\n";
  if (fs::exists(r / "photo.json")) {
    const MergeSidecar m = MergeSidecar::Read((r / "photo.json").string());
    md << "- photo: " << m.frames.size() << (m.frames.size() == 1 ? " frame" : " frames") << " merged ("
       << (m.raw ? "RAW" : m.response.kind) << " response), " << 100 * m.unreliable_fraction
       << " % of pixels unreliable\n";
  }
  if (fs::exists(r / "probe.json")) {
    const Calibration c = Calibration::Read((r / "probe.json").string());
    md << "- probe: " << c.source << " (" << c.layout << "), yaw/pitch/roll "
       << nlohmann::json(c.yaw_pitch_roll_deg).dump() << " deg, scale "
       << nlohmann::json{c.scale[0], c.scale[1], c.scale[2]}.dump() << "\n";
  }
  const fs::path truth_dir = o.capture.empty() ? fs::path() : fs::path(o.capture) / "truth";
  const bool synthetic = !o.capture.empty() && fs::exists(truth_dir / "truth.json");
  if (synthetic) {
    const SyntheticCaptureTruth t = SyntheticCaptureTruth::Read((truth_dir / "truth.json").string());
    md << "- synthetic capture: truth " << t.material << " under " << t.probe << "\n";
  }
  if (fs::exists(r / "sphere.json")) {
    const nlohmann::json j = ReadJsonFile((r / "sphere.json").string());
    const SphereView v = SphereView::FromJson(j, (r / "sphere.json").string());
    md << "\n## Sphere\n\n- centre (" << Fixed(v.circle.cx, 3) << ", " << Fixed(v.circle.cy, 3) << ") px, radius "
       << Fixed(v.circle.r, 3) << " px, "
       << (v.perspective ? "perspective, f " + Fixed(v.focal_px, 1) + " px" : std::string("orthographic")) << "\n";
    if (j.contains("fit"))
      md << "- rim fit: " << j["fit"].value("inliers", 0) << "/" << j["fit"].value("edge_points", 0)
         << " rim points, rms " << Fixed(j["fit"].value("rms_px", 0.0), 3) << " px, blur "
         << Fixed(j["fit"].value("blur_sigma_px", 0.0), 2) << " px\n";
    if (synthetic && fs::exists(truth_dir / "sphere.json")) {
      const SphereView t = SphereView::FromJson(ReadJsonFile((truth_dir / "sphere.json").string()),
                                                (truth_dir / "sphere.json").string());
      md << "- against the truth: centre off by "
         << Fixed(std::hypot(v.circle.cx - t.circle.cx, v.circle.cy - t.circle.cy), 3) << " px, radius by "
         << Fixed(v.circle.r - t.circle.r, 3) << " px\n";
    }
  }

  // The fit: class, residual per class, reconstruction.
  const auto BlendLine = [](const FitRecord& f) {
    if (f.parts.size() < 2) return std::string();
    std::string line = "\n- blended: ";
    for (size_t i = 0; i < f.parts.size(); ++i) {
      const LambdaChoice::Part& p = f.parts[i];
      line += (i ? " + " : "") + Fixed(p.weight, 2) + " × class " + std::to_string(p.cls) + " at λ = " + Sci(p.lambda);
    }
    return line + " (the class and every basis scored alike on the wedges)";
  };
  const fs::path fit_json = r / "fit" / "fit.json";
  if (fs::exists(fit_json)) {
    const FitRecord f = FitRecord::Read(fit_json.string());
    md << "\n## Fit\n\n- database: " << f.database << ", " << f.bases.size()
       << " bases\n- regularisation λ = " << f.lambda << " ("
       << (f.lambda_rule == "fixed" ? std::string("fixed by --lambda")
                                    : "chosen by " + f.lambda_rule + " on the photo's pixels")
       << "); predicted relit error " << Fixed(f.predicted_relit_error, 4)
       << (f.prior_sensitivity >= 0
               ? ", prior sensitivity " + Fixed(f.prior_sensitivity, 3) +
                     " (how much the sphere's images under eight suns move when λ moves a decade either way: large where the photo leaves it "
                     "to the prior)"
               : std::string())
       << (f.lambda_rule != "fixed" && f.condition_bound > 0 && f.relative_noise >= 0
               ? "\n- the photo's pixel noise " + Sci(f.relative_noise) + " of its RMS" +
                     (f.bound_noise >= 0 && f.bound_noise < f.relative_noise
                          ? " (what the fit of the largest candidate class leaves reads " + Sci(f.bound_noise) + ")"
                          : std::string()) +
                     ": λ searched within the condition bound " + Sci(f.condition_bound) +
                     " (a noisier photo is trusted less far)"
               : std::string())
       << "\n- chosen class **" << f.chosen_class << "**, relative residual " << f.relative_residual << BlendLine(f)
       << "\n- BRDF: `" << rel(r / "fit" / "brdf.binary") << "` (MERL format), weights `" << rel(fit_json) << "`\n";
    if (f.lambert_ggx) {
      const LambertGgxFit& g = *f.lambert_ggx;
      md << "- analytic baseline (Lambert + GGX on the same pixels, `lambert_ggx` in fit.json): relative residual "
         << Fixed(g.relative_residual, 4) << "; diffuse albedo " << Fixed(g.diffuse_albedo[0], 3) << ", "
         << Fixed(g.diffuse_albedo[1], 3) << ", " << Fixed(g.diffuse_albedo[2], 3) << "; specular F0 "
         << Fixed(g.SpecularF0()[0], 3) << ", " << Fixed(g.SpecularF0()[1], 3) << ", " << Fixed(g.SpecularF0()[2], 3)
         << " × " << Fixed(g.specular_scale, 3) << "; roughness " << Fixed(std::sqrt(g.alpha), 3) << " (GGX α "
         << g.alpha << ")\n";
    }
    md << "\n| class | bases | residual (Σ RGB) | condition (G) | solver |\n|---|---|---|---|---|\n";
    std::vector<std::vector<double>> bars;
    std::vector<std::string> groups;
    for (size_t k = 0; k < f.classes.size(); ++k) {
      const auto& c = f.classes[k];
      md << "| " << k << (static_cast<int>(k) == f.chosen_class ? " (chosen)" : "") << " | " << c.members << " | "
         << c.residual << " | " << c.condition << " | " << c.path << " |\n";
      bars.push_back({c.residual});
      groups.push_back("class " + std::to_string(k));
    }
    WritePng((pics / "residuals.png").string(),
             BarPlot(bars, groups, {"residual"}, "residual per class (lowest is chosen)"));
    md << "\n![residuals](" << rel(pics / "residuals.png")
       << ")\n\nphoto (left) and the fit in the photo's lighting (right):\n\n![photo vs fit]("
       << rel(r / "fit" / "photo_vs_fit.png") << ")\n";
  }

  // Relit under other probes: relit/<probe>_fit.exr, beside <probe>_truth.exr.
  if (fs::is_directory(r / "relit")) {
    md << "\n## Relit under other probes\n\n";
    std::vector<fs::path> fits;
    for (const auto& e : fs::directory_iterator(r / "relit")) {
      const std::string n = e.path().filename().string();
      if (n.size() > 8 && n.compare(n.size() - 8, 8, "_fit.exr") == 0) fits.push_back(e.path());
    }
    std::sort(fits.begin(), fits.end());
    for (const fs::path& fp : fits) {
      const std::string probe = fp.filename().string().substr(0, fp.filename().string().size() - 8);
      const cv::Mat fit = ReadHdrImage(fp.string());
      const fs::path tp = r / "relit" / (probe + "_truth.exr");
      cv::Mat shown = fit;
      std::string caption = "fit";
      if (fs::exists(tp)) {
        const cv::Mat truth = ReadHdrImage(tp.string());
        if (truth.size() != fit.size()) throw FileError(tp.string(), "size differs from " + fp.string());
        cv::hconcat(fit, truth, shown);
        const double err = CompareLinearImages(truth, fit).relative_rmse;
        caption = "fit (left), truth (right): relative RMSE **" + Fixed(err, 4) + "**";
        report.relit_error.push_back({probe, err});
        // The analytic baseline relit alike, when the relight step rendered it.
        const fs::path gp = r / "relit" / (probe + "_lambert_ggx.exr");
        if (fs::exists(gp)) {
          const cv::Mat ggx = ReadHdrImage(gp.string());
          if (ggx.size() != truth.size()) throw FileError(gp.string(), "size differs from " + tp.string());
          caption +=
              "; the Lambert + GGX baseline: relative RMSE " + Fixed(CompareLinearImages(truth, ggx).relative_rmse, 4);
        }
      }
      WritePngTonemapped((pics / ("relit_" + probe + ".png")).string(), shown, AutoExposure(shown));
      md << "- " << probe << ": " << caption << "\n\n  ![" << probe << "](" << rel(pics / ("relit_" + probe + ".png"))
         << ")\n\n";
    }
  }

  // Wall time of each stage, from the Makefile's BRDFSHOT_TIME_LOG.
  if (fs::exists(r / "times.tsv")) {
    double total = 0;
    md << "\n## Stage wall times\n\n| stage | seconds |\n|---|---|\n";
    for (const auto& [stage, t] : StageTimes((r / "times.tsv").string())) {
      md << "| " << stage << " | " << Fixed(t, 2) << " |\n";
      total += t;
    }
    md << "| **all** | **" << Fixed(total, 2) << "** |\n";
  }
  WriteFileAtomic(out, [&](std::ostream& s) { s << md.str(); });
  report.page = out;
  report.pictures = pics.string();
  return report;
}

}  // namespace brdfshot
