#include "normals/sphere_detect.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "normals/rim_profile.h"
#include "util/check.h"

namespace brdfshot {
namespace {

// Rec. 709 luminance weights, for linear RGB.
constexpr float kLuminance[3] = {0.2126f, 0.7152f, 0.0722f};

cv::Mat Luminance(const cv::Mat& rgb) {
  cv::Mat lum;
  cv::transform(rgb, lum, cv::Matx13f(kLuminance[0], kLuminance[1], kLuminance[2]));
  return lum;
}

}  // namespace

cv::Mat LogLuminance(const cv::Mat& rgb) {
  BRDFSHOT_CHECK(rgb.channels() == 3 || rgb.channels() == 1);
  cv::Mat f;
  rgb.convertTo(f, CV_32F);
  cv::Mat lum = f.channels() == 3 ? Luminance(f) : f;
  // 99th percentile from a subsample: the floor needs no more precision.
  std::vector<float> s;
  const int step = std::max(1, static_cast<int>(std::sqrt(lum.total() / 20000.0)));
  for (int y = 0; y < lum.rows; y += step)
    for (int x = 0; x < lum.cols; x += step) s.push_back(lum.at<float>(y, x));
  std::nth_element(s.begin(), s.begin() + s.size() * 99 / 100, s.end());
  const float floor = std::max(1e-12f, 0.01f * s[s.size() * 99 / 100]);
  cv::max(lum, floor, lum);
  cv::log(lum, lum);
  return lum;
}

namespace {
// Rays whose rim-model misfit exceeds this many times the median are dropped.
constexpr double kMaxRimMisfit = 4.0;
// A linear rim fit this rough (rms, px; the test is ≤ 1 px) may be pulled by a
// terminator: the log-edge fit is tried too. Sharp rims fit to 0.1–0.4 px.
constexpr double kMarginalRimRms = 0.6;

// Each row (a ray's RGB profile) projected on w ∝ ℓ ⊙ Δ, Δ its colour step
// at the steepest point, ℓ the luminance weights, |w|₁ = 1. Across a grey
// step w is ±ℓ, so the result is the luminance (up to sign) as before; across
// a step in colour at equal luminance — a red ball against green leaves,
// where the luminance profile has no rim at all — it keeps the contrast
// (w·Δ = Σ ℓ_c Δ_c² > 0). The ℓ weighting stands in for each channel's
// noise (green, twice sampled on a Bayer sensor, is the cleanest): weighting
// the channels equally made DiLiGenT's grey ball's normals worse.
cv::Mat ColourStepProjection(const cv::Mat& rgb) {
  const int n = rgb.cols;
  cv::Mat out(rgb.rows, n, CV_32F);
  for (int k = 0; k < rgb.rows; ++k) {
    const cv::Vec3f* p = rgb.ptr<cv::Vec3f>(k);
    // The steepest point by the ℓ-weighted colour difference.
    int best = -1;
    double best_d = 0;
    for (int i = 1; i + 1 < n; ++i) {
      const cv::Vec3f d = p[i + 1] - p[i - 1];
      double d2 = 0;
      for (int c = 0; c < 3; ++c) d2 += kLuminance[c] * d[c] * d[c];
      if (d2 > best_d) best_d = d2, best = i;
    }
    cv::Vec3f w(kLuminance[0], kLuminance[1], kLuminance[2]);
    if (best >= 0) {
      // The step across ±1 px (4 samples each side) of it.
      const cv::Vec3f step = p[std::min(n - 1, best + 4)] - p[std::max(0, best - 4)];
      const cv::Vec3f lw(kLuminance[0] * step[0], kLuminance[1] * step[1], kLuminance[2] * step[2]);
      const float l1 = std::abs(lw[0]) + std::abs(lw[1]) + std::abs(lw[2]);
      if (l1 > 0) w = lw / l1;
    }
    float* q = out.ptr<float>(k);
    for (int i = 0; i < n; ++i) q[i] = w.dot(p[i]);
  }
  return out;
}

}  // namespace

std::vector<cv::Point2d> RadialEdgePoints(const cv::Mat& image, const cv::Point2d& centre, double r_lo, double r_hi,
                                          int rays, double* rim_blur, bool log_pick, bool colour) {
  BRDFSHOT_CHECK((image.type() == CV_32F || image.type() == CV_32FC3) && rays > 0 && r_hi > r_lo && r_lo >= 0);
  const double step = 0.25;  // pixels along the ray
  const int n = static_cast<int>((r_hi - r_lo) / step) + 1;
  // One remap for all rays: rows are rays, columns radii. remap's pixel centres
  // sit at integer coordinates, ours at +½.
  cv::Mat mapx(rays, n, CV_32F), mapy(rays, n, CV_32F);
  for (int k = 0; k < rays; ++k) {
    const double a = 2 * kPi * (k + 0.5) / rays, ca = std::cos(a), sa = std::sin(a);
    for (int i = 0; i < n; ++i) {
      const double r = r_lo + i * step;
      mapx.at<float>(k, i) = static_cast<float>(centre.x + r * ca - 0.5);
      mapy.at<float>(k, i) = static_cast<float>(centre.y + r * sa - 0.5);
    }
  }
  cv::Mat prof;
  cv::remap(image, prof, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  // Smooth along the ray over about a pixel: bilinear samples at ¼ px are
  // piecewise linear, and their raw differences would lock onto pixel edges.
  cv::GaussianBlur(prof, prof, cv::Size(9, 1), 2.0, 0, cv::BORDER_REPLICATE);
  // One channel per ray from the samples only (a 12 MP photo is never
  // converted whole): luminance, or with `colour` for linear picks the
  // projection that shows this ray's rim best (ColourStepProjection).
  if (prof.channels() == 3) prof = colour && !log_pick ? ColourStepProjection(prof) : Luminance(prof);
  std::vector<double> strength(rays, 0.0), where(rays, -1.0);
  // Log picks: the samples floored at 1 % of their 99th percentile, as
  // LogLuminance does, so a black background's noise makes no edges.
  float log_floor = 0;
  if (log_pick) {
    std::vector<float> all(prof.begin<float>(), prof.end<float>());
    std::nth_element(all.begin(), all.begin() + all.size() * 99 / 100, all.end());
    log_floor = std::max(1e-12f, 0.01f * all[all.size() * 99 / 100]);
  }
  std::vector<double> log_p(log_pick ? n : 0);
  for (int k = 0; k < rays; ++k) {
    // A ray whose band leaves the picture sees the border, not the rim.
    const float ex = mapx.at<float>(k, n - 1), ey = mapy.at<float>(k, n - 1);
    if (ex < 0 || ey < 0 || ex > image.cols - 1 || ey > image.rows - 1) continue;
    const float* p = prof.ptr<float>(k);
    int best = -1;
    double best_d = 0;
    if (log_pick) {
      for (int i = 0; i < n; ++i) log_p[i] = std::log(std::max(p[i], log_floor));
      double best_log = 0;
      for (int i = 2; i + 2 < n; ++i) {
        const double d = std::abs(log_p[i + 1] - log_p[i - 1]);
        if (d > best_log) best_log = d, best = i;
      }
      if (best >= 0) best_d = std::abs(p[best + 1] - p[best - 1]);  // strength stays linear
    } else {
      for (int i = 2; i + 2 < n; ++i) {
        const double d = std::abs(p[i + 1] - p[i - 1]);
        if (d > best_d) best_d = d, best = i;
      }
    }
    if (best < 3 || best > n - 4) continue;  // at the band's end: not a peak
    const double dm = std::abs(p[best] - p[best - 2]), dp = std::abs(p[best + 2] - p[best]);
    const double denom = dm - 2 * best_d + dp;
    const double off = denom < 0 ? 0.5 * (dm - dp) / denom : 0.0;
    strength[k] = best_d;
    where[k] = r_lo + (best + std::clamp(off, -0.5, 0.5)) * step;
  }
  std::vector<double> s;
  for (double v : strength)
    if (v > 0) s.push_back(v);
  std::vector<cv::Point2d> pts;
  if (s.empty()) return pts;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  const double min_strength = 0.25 * s[s.size() / 2];
  if (rim_blur) {
    // The rim model on every ray strong enough, its blur estimated from a
    // spread of them.
    std::vector<const float*> sample;
    std::vector<double> guesses;
    for (int k = 0; k < rays; k += std::max(1, rays / 32))
      if (where[k] >= 0 && strength[k] >= min_strength)
        sample.push_back(prof.ptr<float>(k)), guesses.push_back(where[k]);
    *rim_blur = EstimateRimBlur(sample, n, r_lo, step, guesses);
    const RimProfileModel model(*rim_blur);
    std::vector<double> misfit(rays, -1.0);
    for (int k = 0; k < rays; ++k)
      if (where[k] >= 0 && strength[k] >= min_strength) {
        double rss;
        const double r = model.Fit(prof.ptr<float>(k), n, r_lo, step, where[k], &rss);
        where[k] = std::isfinite(r) ? r : -1;
        misfit[k] = rss / (strength[k] * strength[k]);
      }
    // A ray whose profile the rim model fits much worse than the typical ray
    // crosses something else near the rim (clutter behind the sphere, a
    // highlight): its edge is biased, not just noisy, so it is dropped.
    std::vector<double> m;
    for (int k = 0; k < rays; ++k)
      if (where[k] >= 0 && misfit[k] >= 0) m.push_back(misfit[k]);
    if (!m.empty()) {
      std::nth_element(m.begin(), m.begin() + m.size() / 2, m.end());
      const double limit = kMaxRimMisfit * m[m.size() / 2];
      for (int k = 0; k < rays; ++k)
        if (misfit[k] > limit) where[k] = -1;
    }
  }
  for (int k = 0; k < rays; ++k) {
    if (where[k] < 0 || strength[k] < min_strength) continue;
    const double a = 2 * kPi * (k + 0.5) / rays;
    pts.emplace_back(centre.x + where[k] * std::cos(a), centre.y + where[k] * std::sin(a));
  }
  return pts;
}

std::vector<Circle> HoughCandidates(const cv::Mat& rgb, const SphereDetectOptions& o) {
  // Reduce first (an area average of linear radiance is the physically right
  // downsampling) and take the log of the small copy only: a 12 MP photo is
  // never converted whole.
  cv::Mat f, small;
  if (rgb.depth() == CV_32F) {
    f = rgb;
  } else {
    rgb.convertTo(f, CV_32F);
  }
  // An integer factor: OpenCV's area resampling has a fast path for it (a
  // 12 MP photo reduces in ~10 ms instead of ~400).
  const int factor = std::max(1, (std::max(rgb.cols, rgb.rows) + o.coarse_max_side - 1) / o.coarse_max_side);
  if (factor > 1) {
    cv::resize(f, small, cv::Size(rgb.cols / factor, rgb.rows / factor), 0, 0, cv::INTER_AREA);
  } else {
    small = f;
  }
  const double scale0 = double(small.cols) / rgb.cols;
  // Log luminance, and with colour_rims the colour ratios log(R/G) and
  // log(B/G), where a sphere against a background of the same luminance but
  // another colour (a red ball before green leaves) still has its whole rim.
  // Hough on luminance alone put such a ball's circle 27 px off.
  std::vector<cv::Mat> views{LogLuminance(small)};
  if (o.colour_rims && small.channels() == 3) {
    std::vector<cv::Mat> c;
    cv::split(small, c);
    // The channels floored where the luminance is (its floor is its minimum).
    const float floor = static_cast<float>(std::exp(*std::min_element(views[0].begin<float>(), views[0].end<float>())));
    for (cv::Mat& m : c) {
      cv::max(m, floor, m);
      cv::log(m, m);
    }
    views.push_back(c[0] - c[1]);
    views.push_back(c[2] - c[1]);
  }
  std::vector<Circle> out;
  for (cv::Mat& view : views) {
    // Two scales: at the coarser one a large, blurred rim is still a sharp
    // circle to the gradient voting (a 224 px ball at σ = 2 px is missed at 512).
    for (int level = 0; level < 2; ++level) {
      if (level) cv::resize(view, view, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
      const double scale = scale0 * (level ? 0.5 : 1.0);
      cv::Mat u8;  // the log range stretched over 0…255 (HoughCircles takes 8-bit)
      cv::normalize(view, u8, 0, 255, cv::NORM_MINMAX, CV_8U);
      const int side = std::min(u8.cols, u8.rows);
      std::vector<cv::Vec3f> found;
      // Gradient-alt: param2 is how perfect a circle must be (1 = perfect).
      cv::HoughCircles(u8, found, cv::HOUGH_GRADIENT_ALT, 1.5, side * o.min_radius, 60, 0.6,
                       std::max(3, static_cast<int>(side * o.min_radius)), static_cast<int>(side * o.max_radius));
      // HoughCircles reports centres with pixel centres at integers.
      for (const cv::Vec3f& c : found) out.push_back({(c[0] + 0.5) / scale, (c[1] + 0.5) / scale, c[2] / scale});
    }
  }
  return out;
}

namespace {

// A Hough circle and the fraction of radial rays that find a strong edge
// near its rim (measured at full resolution).
struct RankedCircle {
  Circle circle;
  double support = 0;
};

// Candidates whose rim is at least half closed, the best first. A sphere is
// usually the largest closed rim in the picture: they are ranked by the rim's
// supported length, not its fraction (a small disc is as round).
std::vector<RankedCircle> RankByRimSupport(const cv::Mat& lin, const std::vector<Circle>& cands, bool log_pick,
                                           bool colour, double* best_support) {
  std::vector<RankedCircle> out;
  *best_support = 0;
  for (size_t i = 0; i < std::min<size_t>(cands.size(), 40); ++i) {
    Circle c = cands[i];
    const double band = std::max(4.0, 0.06 * c.r);
    const std::vector<cv::Point2d> pts = RadialEdgePoints(lin, {c.cx, c.cy}, std::max(0.0, c.r - 2 * band),
                                                          c.r + 2 * band, 90, nullptr, log_pick, colour);
    // Hough's circle can be a band's width off (the coarser scale's are):
    // the rim is counted around a robust fit to the edges it found, when that
    // fit stays near the candidate.
    try {
      const Circle fit = FitCircleRobust(pts);
      if (std::hypot(fit.cx - c.cx, fit.cy - c.cy) + std::abs(fit.r - c.r) < 2 * band) c = fit;
    } catch (const Error&) {
      // Too few or collinear edge points: counted around Hough's circle.
    }
    int near = 0;
    for (const auto& p : pts) near += std::abs(std::hypot(p.x - c.cx, p.y - c.cy) - c.r) < band;
    const double support = near / 90.0;
    *best_support = std::max(*best_support, support);
    if (support >= 0.5) out.push_back({c, support});
  }
  std::stable_sort(out.begin(), out.end(), [](const RankedCircle& a, const RankedCircle& b) {
    return a.support * a.circle.r > b.support * b.circle.r;
  });
  return out;
}

// The sub-pixel stage from a coarse circle; fills `det` (circle, cone,
// quality, blur, edge points). Returns whether the rim fits well enough to be
// a sphere's.
bool RefineRim(const cv::Mat& lin, const Circle& coarse, const SphereDetectOptions& o, SphereDetection* det) {
  det->coarse = coarse;
  det->principal = o.principal.x >= 0 ? o.principal : cv::Point2d(lin.cols / 2.0, lin.rows / 2.0);
  det->focal_px = o.focal_px;
  det->perspective = o.focal_px > 0;
  Circle c = coarse;
  // Three passes, each in a narrower band around the last fit: wide enough
  // first for a coarse circle 10 % off, narrow last so clutter stays out, and
  // the rim model (rim_profile.h) only in the last.
  for (int pass = 0; pass < 3; ++pass) {
    // Under perspective the rim is an ellipse; around the apparent circle it
    // strays by up to r (1 − cos θ_c), θ_c the centre's angle off axis.
    const double ellipse = det->perspective && pass ? c.r * (1 + det->cone.centre_dir.z) : 0.0;
    const double band = pass == 0   ? std::max(8.0, 0.12 * c.r)
                        : pass == 1 ? std::max(6.0, 0.03 * c.r) + ellipse
                                    : 14.0 + ellipse;
    det->edge_points = RadialEdgePoints(lin, {c.cx, c.cy}, std::max(0.0, c.r - band), c.r + band, o.rays,
                                        pass == 2 ? &det->blur_sigma : nullptr, o.log_edges, o.colour_rims);
    if (det->perspective) {
      det->cone = FitConeRobust(det->edge_points, o.focal_px, det->principal, &det->quality);
      c = ApparentCircle(det->cone, o.focal_px, det->principal);
    } else {
      c = FitCircleRobust(det->edge_points, &det->quality);
    }
  }
  det->circle = c;
  // A sphere's rim fits its circle to a fraction of a pixel along most rays;
  // a circle found in clutter or a probe does not.
  return det->quality.rms_px <= 1.0 && det->quality.inliers >= 0.3 * o.rays;
}

// Whether the disc is shaded like a matte sphere in soft light: its
// luminance, averaged over cells (so sensor noise does not count), varies
// (p90/p10 of the cells beyond `kMinShadingRatio`; a flat disc of paint does
// not) and follows a smooth function of the normal: second-order spherical
// harmonics leave under `kMaxShadingResidual` of the mean (0.4–0.5 % on the
// test's matte balls; 4.6 % on a disc half covered by a rectangle, 8–20 % on
// rings around other clutter, measured in bench-detect's scenes). Not
// recognised this way: a mirror ball (its interior is a picture of the room)
// and a glossy ball with a sharp highlight. Those do not make a photo
// ambiguous; the best-supported rim is measured.
constexpr double kMinShadingRatio = 1.3;
constexpr double kMaxShadingResidual = 0.02;

bool ShadedLikeASphere(const cv::Mat& lin, const Circle& c) {
  const int grid = 9;
  const double half = 0.8 * c.r, cell = 2 * half / grid;
  if (cell < 2) return false;  // too small to judge its shading
  std::vector<double> rows, values;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double x = c.cx - half + (i + 0.5) * cell, y = c.cy - half + (j + 0.5) * cell;
      const double nx = (x - c.cx) / c.r, ny = (y - c.cy) / c.r, q = 1 - nx * nx - ny * ny;
      if (q < 1 - 0.8 * 0.8) continue;
      const int x0 = static_cast<int>(x - cell / 2), y0 = static_cast<int>(y - cell / 2);
      const int side = static_cast<int>(cell);
      if (x0 < 0 || y0 < 0 || x0 + side > lin.cols || y0 + side > lin.rows) continue;
      // At most 16 × 16 pixels of the cell: noise averages down as well, and
      // a 12 MP sphere's cells are not read whole for every candidate.
      const int stride = std::max(1, side / 16);
      double sum = 0;
      int count = 0;
      for (int v = y0; v < y0 + side; v += stride)
        for (int u = x0; u < x0 + side; u += stride) {
          const cv::Vec3f& p = lin.at<cv::Vec3f>(v, u);
          sum += p[0] + p[1] + p[2];
          ++count;
        }
      const double nz = std::sqrt(q);
      rows.insert(rows.end(), {1, nx, ny, nz, nx * ny, ny * nz, nx * nz, nx * nx - ny * ny, 3 * nz * nz - 1});
      values.push_back(sum / count);
    }
  const int n = static_cast<int>(values.size());
  if (n < 20) return false;
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  const double p10 = sorted[n / 10], p90 = sorted[n * 9 / 10];
  if (!(p10 > 0) || p90 < kMinShadingRatio * p10) return false;
  const cv::Mat A(n, 9, CV_64F, rows.data()), b(n, 1, CV_64F, values.data());
  cv::Mat coef;
  cv::solve(A, b, coef, cv::DECOMP_SVD);
  const cv::Mat res = A * coef - b;
  const double mean = cv::mean(b)[0];
  return std::sqrt(res.dot(res) / n) < kMaxShadingResidual * mean;
}

// One detection with the given edge picks (DetectSphere runs it once or twice).
// One pass of the detector with one edge rule: the sphere, or why there is
// none. The fallbacks below try another rule on `no_sphere`; an ambiguous
// photo (two spheres) is final whatever the rule.
struct DetectionAttempt {
  std::optional<SphereDetection> sphere;
  std::string no_sphere;  // why none was found ("" when found or ambiguous)
  std::string ambiguous;  // "two spheres found ..." ("" otherwise)
};

DetectionAttempt NoSphere(std::string why) { return {std::nullopt, std::move(why), ""}; }

DetectionAttempt DetectSphereOnce(const cv::Mat& rgb_in, const SphereDetectOptions& o) {
  if (rgb_in.channels() != 3) throw Error("sphere detection wants an RGB image");
  cv::Mat lin;
  if (rgb_in.depth() == CV_32F) {
    lin = rgb_in;
  } else {
    rgb_in.convertTo(lin, CV_32F);
  }
  const std::vector<Circle> cands = HoughCandidates(lin, o);
  // Rim profiles are sampled from the linear image: blur is linear there, so a
  // blurred step's steepest point is the step. In log it shifts towards the
  // darker side by a fraction of the blur (0.3–0.5 px measured here).
  double best_support = 0;
  std::vector<RankedCircle> ranked = RankByRimSupport(lin, cands, o.log_edges, o.colour_rims, &best_support);
  const bool picked = o.near.x >= 0;
  if (picked) {
    // The user's point chooses among the spheres: only circles around it.
    ranked.erase(std::remove_if(ranked.begin(), ranked.end(),
                                [&](const RankedCircle& rc) {
                                  return std::hypot(o.near.x - rc.circle.cx, o.near.y - rc.circle.cy) > rc.circle.r;
                                }),
                 ranked.end());
  }
  if (ranked.empty())
    return NoSphere("no sphere found (" + std::to_string(cands.size()) + " circle candidates" +
                    (picked ? ", none around the given point" : "") + ", best rim support " +
                    std::to_string(static_cast<int>(100 * best_support)) + " %, need 50 %)");
  // The sub-pixel stage on a candidate; false when its rim fails the test or
  // has too few edge points for a circle at all.
  auto refine = [&](const Circle& coarse, SphereDetection* d) {
    try {
      return RefineRim(lin, coarse, o, d);
    } catch (const Error&) {
      return false;
    }
  };
  SphereDetection det;
  bool found = refine(ranked[0].circle, &det);
  const SphereDetection best_rim = det;
  // The best-supported rim is the sphere when it passes and is shaded like
  // one. Otherwise (a large clutter ring outranks the sphere, passes or not)
  // a lower-ranked candidate shaded like a sphere whose rim passes wins.
  if (!found || !ShadedLikeASphere(lin, det.circle)) {
    int tried = 0;
    for (size_t i = 1; i < ranked.size() && tried < 3; ++i) {
      if (!ShadedLikeASphere(lin, ranked[i].circle)) continue;
      ++tried;
      SphereDetection d;
      if (refine(ranked[i].circle, &d)) {
        det = d, found = true;
        break;
      }
    }
  }
  if (!found)
    return NoSphere("no sphere found: the best circle's rim fits to " + std::to_string(best_rim.quality.rms_px) +
                    " px rms over " + std::to_string(best_rim.quality.inliers) + " of " + std::to_string(o.rays) +
                    " rays (need ≤ 1 px over 30 %)" +
                    (best_rim.perspective ? "" : "; if the sphere is seen in perspective, give the focal length"));
  if (picked) return {det, "", ""};
  // A second sphere beside the first (two samples in one shot, a grey ball
  // next to the sample): measuring either silently could fit the wrong
  // material, so the user must say which. A second candidate counts when it
  // lies apart from the first, is shaded like a lit sphere (not a flat disc or
  // a ring around other things) and passes the same rim test.
  const Circle& first = det.circle;
  int tried = 0;
  for (size_t i = 0; i < ranked.size() && tried < 3; ++i) {
    const Circle& c = ranked[i].circle;
    if (std::hypot(c.cx - first.cx, c.cy - first.cy) < first.r + 0.8 * c.r) continue;
    if (!ShadedLikeASphere(lin, c)) continue;
    ++tried;
    SphereDetection other;
    if (!refine(c, &other)) continue;
    char msg[320];
    std::snprintf(msg, sizeof msg,
                  "two spheres found, centred at (%.1f, %.1f) r %.1f px and (%.1f, %.1f) r %.1f px: say which to "
                  "measure with a point inside it (normals --near X,Y) or crop the photo",
                  first.cx, first.cy, first.r, other.circle.cx, other.circle.cy, other.circle.r);
    return {std::nullopt, "", msg};
  }
  return {det, "", ""};
}

}  // namespace

namespace {

DetectionAttempt DetectWithLogFallback(const cv::Mat& rgb, const SphereDetectOptions& o) {
  if (o.log_edges) return DetectSphereOnce(rgb, o);
  // A rim partly in attached shadow (a ball lit from the side, as in
  // photometric stereo): there the steepest linear step is the terminator
  // inside the ball, not the silhouette, while in log luminance the
  // silhouette's step is the steeper. Log edges lie 0.3–0.5 px towards the
  // darker side, so they are the fallback, not the default: tried when the
  // linear picks find no sphere or fit it only marginally, and kept when their
  // rim fits better.
  SphereDetectOptions log_options = o;
  log_options.log_edges = true;
  auto with_log_edges = [&]() {
    DetectionAttempt a = DetectSphereOnce(rgb, log_options);
    if (a.sphere) a.sphere->rim_in_shadow = true;
    return a;
  };
  const DetectionAttempt linear = DetectSphereOnce(rgb, o);
  if (!linear.ambiguous.empty()) return linear;
  if (!linear.sphere) {
    DetectionAttempt log = with_log_edges();
    return log.sphere || !log.ambiguous.empty() ? log : linear;  // no sphere either way: the linear pass says why
  }
  if (linear.sphere->quality.rms_px <= kMarginalRimRms) return linear;
  const DetectionAttempt log = with_log_edges();  // only a better fit replaces the linear one
  return log.sphere && log.sphere->quality.rms_px < linear.sphere->quality.rms_px ? log : linear;
}

}  // namespace

SphereDetection DetectSphere(const cv::Mat& rgb, const SphereDetectOptions& o) {
  if (rgb.channels() != 3) throw Error("sphere detection wants an RGB image");
  DetectionAttempt a = DetectWithLogFallback(rgb, o);
  // Rims in colour: a fallback. The extra Hough views and candidates cost
  // ~40 ms a photo, luminance finds every sphere in bench-detect's scenes,
  // and a JPEG's colour is at half its resolution (4:2:0): profiles
  // projected on their colour step put the default capture's rim 0.19 px
  // inside, against 0.08 px in luminance.
  if (!a.sphere && a.ambiguous.empty() && !o.colour_rims) {
    SphereDetectOptions colour = o;
    colour.colour_rims = true;
    DetectionAttempt c = DetectWithLogFallback(rgb, colour);
    if (c.sphere || !c.ambiguous.empty()) a = c;
  }
  if (!a.ambiguous.empty()) throw Error(a.ambiguous);
  if (!a.sphere) throw NoSphereFound(a.no_sphere);
  return *a.sphere;
}

}  // namespace brdfshot
