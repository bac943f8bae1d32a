#include "normals/detect_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <random>

#include "normals/sphere_detect.h"
#include "normals/synthetic_sphere.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"
#include "util/stats.h"

namespace brdfshot {

namespace {

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Scores {
  std::vector<double> centre, radius, seconds;
  int misses = 0;
};

}  // namespace

Circle HoughAlone(const cv::Mat& rgb, double min_r, double max_r) {
  const cv::Mat ll = LogLuminance(rgb);
  cv::Mat u8;  // the log range stretched over 0…255 (HoughCircles takes 8-bit)
  cv::normalize(ll, u8, 0, 255, cv::NORM_MINMAX, CV_8U);
  std::vector<cv::Vec3f> found;
  cv::HoughCircles(u8, found, cv::HOUGH_GRADIENT_ALT, 1.5, min_r, 300, 0.8, static_cast<int>(min_r),
                   static_cast<int>(max_r));
  if (found.empty()) return {};
  // OpenCV's centres are in pixel-index coordinates; ours put pixel centres at +½.
  return {found[0][0] + 0.5, found[0][1] + 0.5, found[0][2]};
}

std::vector<DetectBenchmarkRow> RunDetectBenchmark(const DetectBenchmarkOptions& o) {
  std::vector<DetectBenchmarkRow> rows;
  for (const cv::Size& size : o.sizes) {
    for (const bool perspective : {false, true}) {
      Scores ours, hough;
      Progress progress("bench-detect " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                            (perspective ? " perspective" : " orthographic"),
                        o.seeds, o.progress);
      for (int seed = 1; seed <= o.seeds; ++seed) {
        std::mt19937 rng(1000 * seed + perspective);
        std::uniform_real_distribution<double> u(0, 1);
        const double side = std::min(size.width, size.height);
        SyntheticSphereScene s;
        s.width = size.width;
        s.height = size.height;
        s.seed = seed;
        s.noise = o.noise;
        s.clutter = o.clutter;
        s.blur_sigma = o.blur;
        Circle truth;
        double focal = 0;
        if (perspective) {
          focal = s.focal_px = o.focal_factor * size.width;
          const double r_px = side * (0.15 + 0.15 * u(rng));
          const double z = -s.focal_px / r_px;  // unit sphere: apparent radius ≈ f / |z|
          const double fx = (u(rng) - 0.5) * 0.5 * size.width / s.focal_px;
          const double fy = (u(rng) - 0.5) * 0.5 * size.height / s.focal_px;
          s.centre = Vec3(fx * -z, fy * -z, z);
        } else {
          s.circle.r = side * (0.15 + 0.15 * u(rng));
          s.circle.cx = size.width / 2.0 + (u(rng) - 0.5) * (size.width - 2.4 * s.circle.r);
          s.circle.cy = size.height / 2.0 + (u(rng) - 0.5) * (size.height - 2.4 * s.circle.r);
          truth = s.circle;
        }
        const cv::Mat img = RenderSyntheticSphere(s);
        if (!o.dump.empty()) {
          std::filesystem::create_directories(o.dump);
          WritePngTonemapped(o.dump + "/" + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                 (perspective ? "_persp_" : "_ortho_") + std::to_string(seed) + ".png",
                             img);
        }
        const cv::Point2d principal(size.width / 2.0, size.height / 2.0);
        const SphereCone cone = perspective ? TrueCone(s) : SphereCone{};
        if (perspective) truth = ApparentCircle(cone, focal, principal);

        SphereDetectOptions detect;
        detect.focal_px = focal;
        auto t0 = std::chrono::steady_clock::now();
        try {
          const SphereDetection d = DetectSphere(img, detect);
          ours.seconds.push_back(Seconds(t0));
          if (o.verbose)
            std::fprintf(stderr,
                         "seed %d: truth (%.1f, %.1f, r %.1f), ours (%.1f, %.1f, r %.1f) rms %.2f px %d/%d inliers, "
                         "centre off %.3f px, radius off %+.3f px, blur %.2f px\n",
                         seed, truth.cx, truth.cy, truth.r, d.circle.cx, d.circle.cy, d.circle.r, d.quality.rms_px,
                         d.quality.inliers, d.quality.points,
                         std::hypot(d.circle.cx - truth.cx, d.circle.cy - truth.cy), d.circle.r - truth.r,
                         d.blur_sigma);
          if (perspective) {
            ours.centre.push_back(Length(Cross(d.cone.centre_dir, cone.centre_dir)) * focal);
            ours.radius.push_back(std::abs(d.cone.half_angle - cone.half_angle) * focal);
          } else {
            ours.centre.push_back(std::hypot(d.circle.cx - truth.cx, d.circle.cy - truth.cy));
            ours.radius.push_back(std::abs(d.circle.r - truth.r));
          }
        } catch (const Error& e) {
          if (o.verbose)
            std::fprintf(stderr, "seed %d: truth (%.1f, %.1f, r %.1f), ours: %s\n", seed, truth.cx, truth.cy, truth.r,
                         e.what());
          ++ours.misses;
        }
        t0 = std::chrono::steady_clock::now();
        const Circle h = HoughAlone(img, detect.min_radius * side, detect.max_radius * side);
        hough.seconds.push_back(Seconds(t0));
        if (h.r > 0) {
          hough.centre.push_back(std::hypot(h.cx - truth.cx, h.cy - truth.cy));
          hough.radius.push_back(std::abs(h.r - truth.r));
        } else {
          ++hough.misses;
        }
        progress.Step();
      }
      for (const auto& [name, sc] :
           {std::pair<const char*, const Scores*>{"ours", &ours}, {"HoughCircles alone", &hough}}) {
        auto mx = [](const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); };
        rows.push_back({size, perspective, name, Median(sc->centre), mx(sc->centre), Median(sc->radius), mx(sc->radius),
                        sc->misses, o.seeds, Median(sc->seconds)});
      }
    }
  }
  return rows;
}

std::string DetectBenchmarkTable(const std::vector<DetectBenchmarkRow>& rows) {
  std::string t =
      "| size | camera | method | centre err median / max (px) | radius err median / max (px) | misses | time median "
      "|\n|---|---|---|---|---|---|---|\n";
  char buf[512];
  for (const DetectBenchmarkRow& r : rows) {
    std::snprintf(buf, sizeof buf, "| %dx%d | %s | %s | %.3f / %.3f | %.3f / %.3f | %d/%d | %.0f ms |\n", r.size.width,
                  r.size.height, r.perspective ? "perspective" : "orthographic", r.method.c_str(), r.centre_median,
                  r.centre_max, r.radius_median, r.radius_max, r.misses, r.scenes, 1000 * r.seconds_median);
    t += buf;
  }
  return t;
}

}  // namespace brdfshot
