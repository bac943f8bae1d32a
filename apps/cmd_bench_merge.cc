// brdfshot bench-merge: HDR merging against ground truth, side by side with
// OpenCV in one run. Real HDR maps are the scenes; a known camera (response
// with a shoulder, shot and read noise, clipping, 8-bit rounding; or linear
// 12-bit RAW-like) makes the brackets; each method recovers its response from
// the frames and merges. Error is measured where the bracket could measure the
// truth at all, after a per-channel scale (responses are only known up to one).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <sstream>
#include <unistd.h>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "capture/clipping.h"
#include "capture/merge.h"
#include "capture/response.h"
#include "capture/synthetic_bracket.h"
#include "fit/loo_eval.h"  // Median
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

struct ErrorStats {
  double median = 0, p95 = 0, mean = 0;
  double bad_fraction = 0;  // non-finite or ≤ 0 where the truth was measurable
  // What a light probe is for: each channel's total power over the measurable
  // pixels, after the same scale, against the truth's (the worst channel). A
  // few wrong pixels (a sun) leave the median alone and move this.
  double power = 0;
};

// Where some frame measured the truth: not clipped in the shortest exposure,
// above the read noise in the longest.
cv::Mat MeasurableMask(const cv::Mat& truth, const std::vector<double>& times, const CameraModel& cam) {
  const auto [tmin, tmax] = std::minmax_element(times.begin(), times.end());
  cv::Mat m(truth.size(), CV_8UC3);
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x)
      for (int c = 0; c < 3; ++c) {
        const double e = truth.at<cv::Vec3f>(y, x)[c];
        m.at<cv::Vec3b>(y, x)[c] = e * *tmin < 0.9 && e * *tmax * cam.full_well > 20 * cam.read_noise ? 1 : 0;
      }
  return m;
}

ErrorStats Compare(const cv::Mat& merged, const cv::Mat& truth, const cv::Mat& measurable) {
  ErrorStats s;
  std::vector<double> ratio[3], rel;
  long bad = 0, n = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x)
      for (int c = 0; c < 3; ++c) {
        if (!measurable.at<cv::Vec3b>(y, x)[c]) continue;
        ++n;
        const double m = merged.at<cv::Vec3f>(y, x)[c], t = truth.at<cv::Vec3f>(y, x)[c];
        if (!std::isfinite(m) || m <= 0) {
          ++bad;
          continue;
        }
        ratio[c].push_back(t / m);
      }
  double scale[3], power_merged[3] = {0, 0, 0}, power_truth[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    std::vector<double> r = ratio[c];
    if (r.empty()) return s;
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    scale[c] = r[r.size() / 2];
  }
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x)
      for (int c = 0; c < 3; ++c) {
        if (!measurable.at<cv::Vec3b>(y, x)[c]) continue;
        const double m = merged.at<cv::Vec3f>(y, x)[c], t = truth.at<cv::Vec3f>(y, x)[c];
        rel.push_back(std::isfinite(m) && m > 0 ? std::abs(scale[c] * m / t - 1) : 1.0);
        if (std::isfinite(m)) power_merged[c] += scale[c] * m;
        power_truth[c] += t;
      }
  for (int c = 0; c < 3; ++c)
    if (power_truth[c] > 0) s.power = std::max(s.power, std::abs(power_merged[c] / power_truth[c] - 1));
  s.bad_fraction = n ? double(bad) / n : 0;
  if (rel.empty()) return s;
  double sum = 0;
  for (double r : rel) sum += r;
  s.mean = sum / rel.size();
  std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
  s.median = rel[rel.size() / 2];
  std::nth_element(rel.begin(), rel.begin() + rel.size() * 95 / 100, rel.end());
  s.p95 = rel[rel.size() * 95 / 100];
  return s;
}

struct Method {
  std::string key, name;
  bool raw;  // works on the RAW-like brackets (else 8-bit)
  std::function<cv::Mat(const std::vector<cv::Mat>& rgb, const std::vector<double>& times)> merge;
};

// The camera's own response as a ResponseCurve: ln of the signal each code
// stands for (inverted by bisection), to show what a perfect calibration gives.
ResponseCurve TrueResponse(const CameraModel& cam) {
  ResponseCurve r;
  r.kind = "debevec";
  for (int z = 0; z < 256; ++z) {
    const double target = std::max(z, 1) / 255.0;
    double lo = 0, hi = 1;
    for (int it = 0; it < 60; ++it) (cam.Response(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
    for (int c = 0; c < 3; ++c) r.g[c].push_back(std::log(std::max(1e-12, 0.5 * (lo + hi))));
  }
  return r;
}

// OpenCV's pipeline: a calibrator's response, then its merge (times as float).
template <typename Calibrate, typename Merge>
auto OpenCvMerge(Calibrate calibrate, Merge merge) {
  return [=](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
    const std::vector<float> tf(t.begin(), t.end());
    cv::Mat response, hdr;
    calibrate()->process(f, response, tf);
    merge()->process(f, hdr, tf, response);
    return hdr;
  };
}

// pfstools (Debian's pfstools 2.x) as its users run it: frames written to disk,
// an hdrgen script, `pfsinhdrgen | pfshdrcalibrate | pfsoutexr`. Its default
// calibration is Robertson's with a noise-optimal merge (Hanji et al. 2020).
// The time includes writing the PNGs and the pipes: that is its interface.
// Empty result if pfstools is not installed.
cv::Mat PfstoolsMerge(const std::vector<cv::Mat>& frames, const std::vector<double>& times) {
  namespace fs = std::filesystem;
  if (std::system("command -v pfshdrcalibrate >/dev/null 2>&1") != 0) return cv::Mat();
  const fs::path dir = fs::temp_directory_path() / ("brdfshot_pfs_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ostringstream script;
  for (size_t j = 0; j < frames.size(); ++j) {
    const std::string png = (dir / ("f" + std::to_string(j) + ".png")).string();
    cv::Mat bgr;
    cv::cvtColor(frames[j], bgr, cv::COLOR_RGB2BGR);
    cv::imwrite(png, bgr);
    script << png << " " << 1.0 / times[j] << " 1 100 0\n";  // 1/t, f-number, ISO
  }
  const std::string hdrgen = (dir / "bracket.hdrgen").string(), exr = (dir / "merged.exr").string();
  WriteFileAtomic(hdrgen, [&](std::ostream& o) { o << script.str(); });
  const std::string cmd = "pfsinhdrgen " + hdrgen + " | pfshdrcalibrate -c robertson 2>/dev/null | pfsoutexr " + exr;
  cv::Mat hdr;
  if (std::system(cmd.c_str()) == 0) hdr = ReadHdrImage(exr);
  fs::remove_all(dir);
  return hdr;
}

// `jpeg`: the 8-bit frames went through JPEG, and ours treats them as the
// merge command treats .jpg files (clipping for all channels and nearby).
std::vector<Method> Methods(const CameraModel& cam, bool jpeg) {
  const int reach = jpeg ? kJpegClipReach : -1;
  auto ours = [reach](MergeWeights w) {
    return [w, reach](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
      MergeOptions o;
      o.weights = w;
      o.clip_reach = reach;
      return MergeBracket(f, t, RecoverResponse(f, t, 3, 200000, reach), o).radiance;
    };
  };
  return {
      {"ours", "brdfshot: Debevec + Robertson-refined response, noise-aware weights (default)", false,
       ours(MergeWeights::kNoise)},
      {"ours-debevec", "brdfshot, Debevec response without the Robertson refinement", false,
       [](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
         return MergeBracket(f, t, RecoverResponseDebevec(f, t)).radiance;
       }},
      {"ours-true", "brdfshot merge with the camera's true response (calibration floor)", false,
       [cam, reach](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
         MergeOptions o;
         o.clip_reach = reach;
         return MergeBracket(f, t, TrueResponse(cam), o).radiance;
       }},
      {"ours-perchannel", "brdfshot, each channel clipped on its own (as for lossless frames)", false,
       [](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
         MergeOptions o;
         o.clip_reach = -1;
         return MergeBracket(f, t, RecoverResponse(f, t), o).radiance;
       }},
      {"ours-hat", "brdfshot, hat x t weights", false, ours(MergeWeights::kHat)},
      {"ours-flat", "brdfshot, flat-top x t weights", false, ours(MergeWeights::kFlat)},
      {"cv-debevec", "OpenCV CalibrateDebevec + MergeDebevec", false,
       OpenCvMerge([] { return cv::createCalibrateDebevec(); }, [] { return cv::createMergeDebevec(); })},
      {"cv-robertson", "OpenCV CalibrateRobertson + MergeRobertson", false,
       OpenCvMerge([] { return cv::createCalibrateRobertson(); }, [] { return cv::createMergeRobertson(); })},
      {"pfstools", "pfstools pfshdrcalibrate (Robertson, noise-optimal merge)", false, PfstoolsMerge},
      {"ours-raw", "brdfshot on RAW-like 12-bit frames (linear)", true,
       [](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
         return MergeBracket(f, t, ResponseCurve::Linear16()).radiance;
       }},
  };
}

}  // namespace

int BenchMergeMain(int argc, char** argv) {
  std::string probes_arg, data, size_arg = "4000x3000", out = "bench_merge",
                                methods_arg = "ours,ours-hat,ours-flat,cv-debevec,cv-robertson,pfstools,ours-raw";
  int frames = 9, jpeg_quality = 0;
  double stops = 1;
  CameraModel cam;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probes", po::value(&probes_arg), "HDR scenes (default: every <data>/envmaps/*.exr)")
      ("data", po::value(&data), "data folder (default: $BRDFSHOT_DATA, then ../shared)")
      ("size", po::value(&size_arg)->default_value(size_arg), "WIDTHxHEIGHT the scenes are resampled to (12 MP)")
      ("frames", po::value(&frames)->default_value(frames), "exposures per bracket")
      ("stops", po::value(&stops)->default_value(stops), "EV between exposures")
      ("read-noise", po::value(&cam.read_noise)->default_value(cam.read_noise), "camera read noise (electrons)")
      ("full-well", po::value(&cam.full_well)->default_value(cam.full_well), "camera full well (electrons)")
      ("jpeg", po::value(&jpeg_quality)->default_value(jpeg_quality),
       "pass the 8-bit frames through JPEG at this quality (OpenCV's 4:2:0), as a camera's JPEGs; 0: lossless")
      ("methods", po::value(&methods_arg)->default_value(methods_arg), "methods to run (cv-robertson takes minutes at 12 MP)")
      ("out,o", po::value(&out)->default_value(out), "output folder: table (markdown, CSV)");
  // clang-format on
  if (!ParseOptions("bench-merge", "[options]", desc, argc, argv)) return 0;
  const cv::Size size = ParseImageSize(size_arg, "--size", 16);
  const int width = size.width, height = size.height;
  if (frames < 2) throw Error("--frames must be at least 2");
  if (!(stops > 0)) throw Error("--stops must be positive");
  MakeOutputDir(out);
  const std::vector<std::string> probes = ResolveProbes(probes_arg, data);

  std::vector<Method> methods;
  for (const std::string& k : SplitList(methods_arg)) {
    bool found = false;
    for (const Method& m : Methods(cam, jpeg_quality > 0))
      if (m.key == k) methods.push_back(m), found = true;
    if (!found) throw Error("unknown method '" + k + "' in --methods");
  }
  std::map<std::string, std::vector<double>> times_s;
  std::map<std::string, std::vector<ErrorStats>> errors;
  std::ostringstream md, csv;
  md << "| scene | method | median rel. error | 95th pct | mean | power | unusable | time s "
        "|\n|---|---|---|---|---|---|---|---|\n";
  csv << "scene,method,median,p95,mean,power,unusable,seconds\n";
  char buf[512];
  for (const std::string& path : probes) {
    const std::string scene = std::filesystem::path(path).stem().string();
    cv::Mat truth;
    cv::resize(ReadHdrImage(path), truth, cv::Size(width, height), 0, 0, cv::INTER_LINEAR);
    const std::vector<double> t = BracketTimes(truth, frames, stops);
    std::map<bool, std::vector<cv::Mat>> brackets;
    CameraModel ldr = cam, raw = cam;
    ldr.raw_bits = 0;
    raw.raw_bits = 12;
    Stopwatch sim;
    brackets[false] = SimulateBracket(truth, t, ldr);
    if (jpeg_quality > 0)
      for (cv::Mat& f : brackets[false]) {
        std::vector<uint8_t> bytes;
        cv::Mat bgr;
        cv::cvtColor(f, bgr, cv::COLOR_RGB2BGR);
        cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality});
        cv::cvtColor(cv::imdecode(bytes, cv::IMREAD_COLOR), f, cv::COLOR_BGR2RGB);
      }
    brackets[true] = SimulateBracket(truth, t, raw);
    const cv::Mat measurable = MeasurableMask(truth, t, cam);
    std::printf("%s: %dx%d, %d frames %.0f EV apart, simulated in %.1f s\n", scene.c_str(), width, height, frames,
                stops, sim.Seconds());
    for (const Method& m : methods) {
      Stopwatch sw;
      const cv::Mat hdr = m.merge(brackets[m.raw], t);
      const double secs = sw.Seconds();
      if (hdr.empty()) {
        std::printf("  %-58s not available (not installed)\n", m.name.c_str());
        continue;
      }
      const ErrorStats e = Compare(hdr, truth, measurable);
      times_s[m.name].push_back(secs);
      errors[m.name].push_back(e);
      std::snprintf(buf, sizeof buf, "| %s | %s | %.4f | %.4f | %.4f | %.4f | %.4f | %.3f |\n", scene.c_str(),
                    m.name.c_str(), e.median, e.p95, e.mean, e.power, e.bad_fraction, secs);
      md << buf;
      std::printf("  %-58s median %.4f  p95 %.4f  power %.4f  %.3f s\n", m.name.c_str(), e.median, e.p95, e.power,
                  secs);
      std::fflush(stdout);
      std::snprintf(buf, sizeof buf, "%s,\"%s\",%.5f,%.5f,%.5f,%.5f,%.5f,%.4f\n", scene.c_str(), m.name.c_str(),
                    e.median, e.p95, e.mean, e.power, e.bad_fraction, secs);
      csv << buf;
    }
  }
  md << "\n| method | median of medians | median of 95th pct | worst power | median time s | time / OpenCV Debevec "
        "|\n|---|---|---|---|---|---|\n";
  const double t_cv = Median(times_s["OpenCV CalibrateDebevec + MergeDebevec"]);  // 0 if not run
  for (const Method& m : methods) {
    std::vector<double> med, p95;
    double power = 0;
    for (const ErrorStats& e : errors[m.name])
      med.push_back(e.median), p95.push_back(e.p95), power = std::max(power, e.power);
    const double tm = Median(times_s[m.name]);
    std::snprintf(buf, sizeof buf, "| %s | %.4f | %.4f | %.4f | %.3f | %.2f |\n", m.name.c_str(), Median(med),
                  Median(p95), power, tm, t_cv > 0 ? tm / t_cv : 0);
    md << buf;
  }
  std::printf("\n%s", md.str().c_str());
  WriteFileAtomic(out + "/bench_merge.md", [&](std::ostream& o) { o << md.str(); });
  WriteFileAtomic(out + "/bench_merge.csv", [&](std::ostream& o) { o << csv.str(); });
  std::printf("wrote %s/bench_merge.{md,csv}\n", out.c_str());
  return 0;
}

}  // namespace brdfshot
