// brdfshot bench-detect: sphere detection against known truth, beside OpenCV's
// HoughCircles alone, in one run. Scenes are normals/synthetic_sphere renders
// (cluttered background, optical blur, sensor noise; orthographic or
// perspective) with random centre and radius per seed, at each image size.
//
// "Hough alone" is cv::HoughCircles (HOUGH_GRADIENT_ALT) on the full-resolution
// 8-bit log luminance, scored by its strongest circle — what a user gets from
// OpenCV without our coarse ranking and sub-pixel stages. Errors: centre
// distance and |radius difference| in pixels (perspective: of the silhouette
// cone's axis and half-angle, times the focal length); medians and maxima over
// the seeds; times are medians.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <random>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/loo_eval.h"  // Median
#include "normals/sphere_detect.h"
#include "normals/synthetic_sphere.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// HoughCircles alone, full resolution; {0,0,0} when it finds nothing.
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

struct Scores {
  std::vector<double> centre, radius, seconds;
  int misses = 0;
};

}  // namespace

int BenchDetectMain(int argc, char** argv) {
  std::string sizes_arg = "640x480,4000x3000";
  int seeds = 8;
  double noise = 0.01, blur = 1.2;
  int clutter = 30;
  bool verbose = false;
  std::string dump;
  double focal_factor = 1.4;  // perspective focal length, in image widths
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("sizes", po::value(&sizes_arg)->default_value(sizes_arg), "image sizes WxH, comma-separated (4000x3000 = 12 MP)")
      ("seeds", po::value(&seeds)->default_value(seeds), "scenes per size and camera")
      ("noise", po::value(&noise)->default_value(noise), "additive Gaussian noise (image values ~0.05 … 1)")
      ("blur", po::value(&blur)->default_value(blur), "optical blur sigma, px (the same at every size: a sharp lens blurs ~1 px whatever the sensor)")
      ("clutter", po::value(&clutter)->default_value(clutter), "background shapes (rectangles, discs, rings)")
      ("verbose,v", po::bool_switch(&verbose), "print every scene's truth and detection")
      ("dump", po::value(&dump), "write every scene as a tone-mapped PNG into this folder")
      ("focal", po::value(&focal_factor)->default_value(focal_factor), "perspective focal length, in image widths");
  // clang-format on
  if (!ParseOptions("bench-detect", "[options]", desc, argc, argv)) return 0;
  if (seeds < 1) throw Error("--seeds must be at least 1");
  std::vector<cv::Size> sizes;
  for (const std::string& s : SplitList(sizes_arg)) sizes.push_back(ParseImageSize(s, "--sizes", 64));

  std::printf(
      "| size | camera | method | centre err median / max (px) | radius err median / max (px) | misses | time median "
      "|\n"
      "|---|---|---|---|---|---|---|\n");
  for (const cv::Size& size : sizes) {
    for (const bool perspective : {false, true}) {
      Scores ours, hough;
      Progress progress("bench-detect " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                            (perspective ? " perspective" : " orthographic"),
                        seeds, true);
      for (int seed = 1; seed <= seeds; ++seed) {
        std::mt19937 rng(1000 * seed + perspective);
        std::uniform_real_distribution<double> u(0, 1);
        const double side = std::min(size.width, size.height);
        SyntheticSphereScene s;
        s.width = size.width;
        s.height = size.height;
        s.seed = seed;
        s.noise = noise;
        s.clutter = clutter;
        s.blur_sigma = blur;
        Circle truth;
        double focal = 0;
        if (perspective) {
          focal = s.focal_px = focal_factor * size.width;
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
        if (!dump.empty()) {
          std::filesystem::create_directories(dump);
          WritePngTonemapped(dump + "/" + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                 (perspective ? "_persp_" : "_ortho_") + std::to_string(seed) + ".png",
                             img);
        }
        const cv::Point2d principal(size.width / 2.0, size.height / 2.0);
        const SphereCone cone = perspective ? TrueCone(s) : SphereCone{};
        if (perspective) truth = ApparentCircle(cone, focal, principal);

        SphereDetectOptions o;
        o.focal_px = focal;
        auto t0 = std::chrono::steady_clock::now();
        try {
          const SphereDetection d = DetectSphere(img, o);
          ours.seconds.push_back(Seconds(t0));
          if (verbose)
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
          if (verbose)
            std::fprintf(stderr, "seed %d: truth (%.1f, %.1f, r %.1f), ours: %s\n", seed, truth.cx, truth.cy, truth.r,
                         e.what());
          ++ours.misses;
        }
        t0 = std::chrono::steady_clock::now();
        const Circle h = HoughAlone(img, o.min_radius * side, o.max_radius * side);
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
        std::printf("| %dx%d | %s | %s | %.3f / %.3f | %.3f / %.3f | %d/%d | %.0f ms |\n", size.width, size.height,
                    perspective ? "perspective" : "orthographic", name, Median(sc->centre), mx(sc->centre),
                    Median(sc->radius), mx(sc->radius), sc->misses, seeds, 1000 * Median(sc->seconds));
      }
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace brdfshot
