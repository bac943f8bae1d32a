#include "capture/merge_benchmark.h"

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

#include "capture/clipping.h"
#include "capture/merge.h"
#include "capture/merge_quality.h"
#include "capture/response.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/huge_pages.h"
#include "util/image_io.h"
#include "util/progress.h"
#include "util/stats.h"

namespace brdfshot {

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

MergeErrorStats CompareToTruth(const cv::Mat& merged, const cv::Mat& truth, const cv::Mat& measurable) {
  MergeErrorStats s;
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
  std::vector<std::pair<double, double>> chroma;  // (truth luminance, distance)
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const cv::Vec3b ok = measurable.at<cv::Vec3b>(y, x);
      if (!ok[0] || !ok[1] || !ok[2]) continue;
      const cv::Vec3f m = merged.at<cv::Vec3f>(y, x), t = truth.at<cv::Vec3f>(y, x);
      const double ms = scale[0] * m[0] + scale[1] * m[1] + scale[2] * m[2], ts = t[0] + t[1] + t[2];
      if (!(ms > 0) || !std::isfinite(ms) || !(ts > 0)) continue;
      const double d = std::hypot(scale[0] * m[0] / ms - t[0] / ts, scale[1] * m[1] / ms - t[1] / ts);
      chroma.push_back({0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2], d});
    }
  if (!chroma.empty()) {
    std::sort(chroma.begin(), chroma.end());
    std::vector<double> all, dark;
    for (size_t i = 0; i < chroma.size(); ++i) {
      all.push_back(chroma[i].second);
      if (i < (chroma.size() + 4) / 5) dark.push_back(chroma[i].second);
    }
    s.chroma = Median(all);
    s.shadow_chroma = Median(dark);
  }
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

namespace {

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

}  // namespace

std::vector<MergeMethod> MergeMethods(const CameraModel& cam, bool jpeg) {
  const int reach = jpeg ? kJpegClipReach : -1;
  auto ours = [reach](MergeWeights w, bool pool_noisy_chroma = true) {
    return [w, reach, pool_noisy_chroma](const std::vector<cv::Mat>& f, const std::vector<double>& t) {
      MergeOptions o;
      o.weights = w;
      o.clip_reach = reach;
      o.pool_noisy_chroma = pool_noisy_chroma;
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
      {"ours-nopool", "brdfshot, every channel as merged (no colour pooling in noisy shadows)", false,
       ours(MergeWeights::kNoise, false)},
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

MergeBenchmarkTables RunMergeBenchmark(const MergeBenchmarkOptions& o) {
  std::vector<MergeMethod> methods;
  for (const std::string& k : o.methods) {
    bool found = false;
    for (const MergeMethod& m : MergeMethods(o.camera, o.jpeg_quality > 0))
      if (m.key == k) methods.push_back(m), found = true;
    if (!found) throw Error("unknown method '" + k + "' in --methods");
  }
  std::map<std::string, std::vector<double>> times_s;
  std::map<std::string, std::vector<MergeErrorStats>> errors;
  std::ostringstream md, csv;
  md << "| scene | method | median rel. error | 95th pct | mean | power | unusable | chroma | shadow chroma | "
        "shadow speckle | time s |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  csv << "scene,method,median,p95,mean,power,unusable,chroma,shadow_chroma,speckle,seconds\n";
  char buf[512];
  for (const std::string& path : o.scenes) {
    const std::string scene = std::filesystem::path(path).stem().string();
    cv::Mat truth;
    cv::resize(ReadHdrImage(path), truth, o.size, 0, 0, cv::INTER_LINEAR);
    std::vector<double> t = BracketTimes(truth, o.frames, o.stops);
    for (double& ti : t) ti *= std::exp2(o.exposure_shift_ev);
    std::map<bool, std::vector<cv::Mat>> brackets;
    CameraModel ldr = o.camera, raw = o.camera;
    ldr.raw_bits = 0;
    raw.raw_bits = 12;
    Stopwatch sim;
    brackets[false] = SimulateBracket(truth, t, ldr);
    if (o.jpeg_quality > 0)
      for (cv::Mat& f : brackets[false]) {
        std::vector<uint8_t> bytes;
        cv::Mat bgr;
        cv::cvtColor(f, bgr, cv::COLOR_RGB2BGR);
        cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality});
        cv::cvtColor(cv::imdecode(bytes, cv::IMREAD_COLOR), f, cv::COLOR_BGR2RGB);
      }
    brackets[true] = SimulateBracket(truth, t, raw);
    const cv::Mat measurable = MeasurableMask(truth, t, o.camera);
    // The scene's own hue changes in its shadows, as the speckle measure sees them: the floor.
    const double scene_speckle = ChromaSpeckle(truth);
    std::snprintf(buf, sizeof buf, "| %s | (the scene itself) | | | | | | | | %.4f | |\n", scene.c_str(),
                  scene_speckle);
    md << buf;
    if (o.progress)
      std::printf("%s: %dx%d, %d frames %.0f EV apart, simulated in %.1f s; the scene's own shadow speckle %.4f\n",
                  scene.c_str(), o.size.width, o.size.height, o.frames, o.stops, sim.Seconds(), scene_speckle);
    for (const MergeMethod& m : methods) {
      // Each as its own program runs it: ours on huge pages (`brdfshot`
      // installs them), the others on OpenCV's allocator.
      const bool ours = m.key.rfind("ours", 0) == 0;
      const ScopedMatAllocator allocator(ours ? HugePageMatAllocator() : cv::Mat::getStdAllocator());
      Stopwatch sw;
      const cv::Mat hdr = m.merge(brackets[m.raw], t);
      const double secs = sw.Seconds();
      if (hdr.empty()) {
        if (o.progress) std::printf("  %-58s not available (not installed)\n", m.name.c_str());
        continue;
      }
      MergeErrorStats e = CompareToTruth(hdr, truth, measurable);
      e.speckle = ChromaSpeckle(hdr);
      times_s[m.name].push_back(secs);
      errors[m.name].push_back(e);
      std::snprintf(buf, sizeof buf, "| %s | %s | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.3f |\n",
                    scene.c_str(), m.name.c_str(), e.median, e.p95, e.mean, e.power, e.bad_fraction, e.chroma,
                    e.shadow_chroma, e.speckle, secs);
      md << buf;
      if (o.progress) {
        std::printf("  %-58s median %.4f  p95 %.4f  power %.4f  shadow chroma %.4f  speckle %.4f  %.3f s\n",
                    m.name.c_str(), e.median, e.p95, e.power, e.shadow_chroma, e.speckle, secs);
        std::fflush(stdout);
      }
      std::snprintf(buf, sizeof buf, "%s,\"%s\",%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f\n", scene.c_str(),
                    m.name.c_str(), e.median, e.p95, e.mean, e.power, e.bad_fraction, e.chroma, e.shadow_chroma,
                    e.speckle, secs);
      csv << buf;
    }
  }
  md << "\n| method | median of medians | median of 95th pct | worst power | median shadow chroma | worst shadow "
        "speckle | median time s | time / OpenCV Debevec |\n|---|---|---|---|---|---|---|---|\n";
  const double t_cv = Median(times_s["OpenCV CalibrateDebevec + MergeDebevec"]);  // 0 if not run
  for (const MergeMethod& m : methods) {
    std::vector<double> med, p95, shadow;
    double power = 0, speckle = 0;
    for (const MergeErrorStats& e : errors[m.name]) {
      med.push_back(e.median), p95.push_back(e.p95), shadow.push_back(e.shadow_chroma);
      power = std::max(power, e.power), speckle = std::max(speckle, e.speckle);
    }
    const double tm = Median(times_s[m.name]);
    std::snprintf(buf, sizeof buf, "| %s | %.4f | %.4f | %.4f | %.4f | %.4f | %.3f | %.2f |\n", m.name.c_str(),
                  Median(med), Median(p95), power, Median(shadow), speckle, tm, t_cv > 0 ? tm / t_cv : 0);
    md << buf;
  }
  return {md.str(), csv.str()};
}

}  // namespace brdfshot
