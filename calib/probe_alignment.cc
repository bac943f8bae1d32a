#include "calib/probe_alignment.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/check.h"

namespace brdfshot {

namespace {

// Log luminance of a probe resized to `width`, floored at 1e-3 of its mean so
// black texels do not dominate.
LatLongProbe LogProbe(const LatLongProbe& p, int width) {
  const LatLongProbe small = p.Resized(width);
  cv::Mat grey;
  cv::cvtColor(small.rgb(), grey, cv::COLOR_RGB2GRAY);
  const double floor = std::max(1e-3 * cv::mean(grey)[0], 1e-12);
  cv::Mat lg;
  cv::max(grey, floor, grey);
  cv::log(grey, lg);
  cv::Mat rgb;
  cv::merge(std::vector<cv::Mat>{lg, lg, lg}, rgb);
  return LatLongProbe(rgb);
}

struct Sample {
  Vec3 dir;
  double value, weight;
};

std::vector<Sample> BallSamples(const LatLongProbe& log_ball, const cv::Mat& measured) {
  cv::Mat mask;
  if (!measured.empty()) cv::resize(measured, mask, log_ball.rgb().size(), 0, 0, cv::INTER_NEAREST);
  std::vector<Sample> out;
  for (int r = 0; r < log_ball.height(); ++r)
    for (int c = 0; c < log_ball.width(); ++c) {
      if (!mask.empty() && !mask.at<uint8_t>(r, c)) continue;
      out.push_back({log_ball.DirectionAt(c + 0.5, r + 0.5), log_ball.Texel(c, r)[0], log_ball.TexelSolidAngle(r)});
    }
  return out;
}

// Weighted variance of ball − probe∘R: the offset (exposure) drops out.
double Cost(const std::vector<Sample>& s, const LatLongProbe& log_probe, const Rotation& R) {
  double sw = 0, sd = 0, sdd = 0;
  for (const Sample& x : s) {
    const double d = x.value - log_probe.Bilinear(R(x.dir))[0];
    sw += x.weight;
    sd += x.weight * d;
    sdd += x.weight * d * d;
  }
  const double mean = sd / sw;
  return std::max(0.0, sdd / sw - mean * mean);
}

}  // namespace

RotationFit EstimateRotation(const LatLongProbe& probe, const LatLongProbe& ball, const cv::Mat& measured) {
  BRDFSHOT_CHECK(probe.width() > 0 && ball.width() > 0);
  RotationFit best;
  double best_cost = INFINITY;
  // Coarse: 64 × 32, yaw every 10°, pitch and roll every 15° within ±45°.
  {
    const LatLongProbe lp = LogProbe(probe, 64), lb = LogProbe(ball, 64);
    const std::vector<Sample> s = BallSamples(lb, measured);
    if (s.size() < 50) throw Error("mirror ball: too few measured directions to estimate a rotation");
    for (double yaw = -180; yaw < 180; yaw += 10)
      for (double pitch = -45; pitch <= 45; pitch += 15)
        for (double roll = -45; roll <= 45; roll += 15) {
          const double c = Cost(s, lp, Rotation::FromYawPitchRoll(yaw, pitch, roll));
          if (c < best_cost) best_cost = c, best.yaw = yaw, best.pitch = pitch, best.roll = roll;
        }
  }
  // Fine: coordinate descent at increasing resolution, step halving to 0.02°.
  double step = 8;
  for (int width : {128, 256}) {
    const LatLongProbe lp = LogProbe(probe, std::min(width, probe.width()));
    const LatLongProbe lb = LogProbe(ball, std::min(width, ball.width()));
    const std::vector<Sample> s = BallSamples(lb, measured);
    best_cost = Cost(s, lp, Rotation::FromYawPitchRoll(best.yaw, best.pitch, best.roll));
    const double last = width == 128 ? 0.5 : 0.02;
    for (; step >= last; step *= 0.5) {
      bool moved = true;
      for (int it = 0; moved && it < 50; ++it) {
        moved = false;
        for (double* a : {&best.yaw, &best.pitch, &best.roll})
          for (double sign : {-1.0, 1.0}) {
            const double keep = *a;
            *a += sign * step;
            const double c = Cost(s, lp, Rotation::FromYawPitchRoll(best.yaw, best.pitch, best.roll));
            if (c < best_cost) {
              best_cost = c;
              moved = true;
            } else {
              *a = keep;
            }
          }
      }
    }
    step = 1;
  }
  best.rotation = Rotation::FromYawPitchRoll(best.yaw, best.pitch, best.roll);
  best.rms_log = std::sqrt(best_cost);
  return best;
}

}  // namespace brdfshot
