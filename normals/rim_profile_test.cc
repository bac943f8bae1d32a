#include "normals/rim_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

namespace brdfshot {
namespace {

// A rim profile built from its definition, independently of the model: the
// step at s0 between `inside(depth)` and a flat background, convolved with a
// Gaussian of `sigma` by direct quadrature, sampled at r0 + i·step.
std::vector<float> BlurredRim(const std::function<double(double)>& inside, double background, double s0, double sigma,
                              double r0, double step, int n) {
  std::vector<float> p(n);
  const double dt = 1.0 / 512;
  for (int i = 0; i < n; ++i) {
    const double s = r0 + i * step;
    double sum = 0, weight = 0;
    for (double t = s - 7 * sigma + dt / 2; t < s + 7 * sigma; t += dt) {
      const double g = std::exp(-0.5 * (s - t) * (s - t) / (sigma * sigma));
      sum += g * (t < s0 ? inside(s0 - t) : background);
      weight += g;
    }
    p[i] = static_cast<float>(sum / weight);
  }
  return p;
}

struct RimCase {
  const char* name;
  std::function<double(double)> inside;
};

// A matte interior (√depth, the model's own shape), a flat one, and a sheen
// (felt, velvet: brightest at grazing, 1/√ of depth softened at the rim —
// the shape pink felt's rim has in synth-capture's photos).
std::vector<RimCase> Cases() {
  return {{"flat", [](double) { return 0.2; }},
          {"matte", [](double d) { return 0.1 + 0.05 * std::sqrt(d); }},
          {"sheen", [](double d) { return 0.1 + 0.15 / std::sqrt(d + 0.5); }}};
}

TEST(RimProfile, BlurVoteIsTheTrueBlurForMatteFlatAndSheenInteriors) {
  const double s0 = 50.3, r0 = 40, step = 0.25;
  const int n = 81;
  for (double sigma : {0.875, 1.5}) {
    for (const RimCase& c : Cases()) {
      const std::vector<float> p = BlurredRim(c.inside, 0.5, s0, sigma, r0, step, n);
      const std::vector<const float*> profiles{p.data()};
      // Without the curved-interior term the sheen's curve voted σ + ⅛ px.
      EXPECT_NEAR(EstimateRimBlur(profiles, n, r0, step, {50.0}), sigma, 1.0 / 32) << c.name << " σ " << sigma;
    }
  }
}

TEST(RimProfile, EdgeOfMatteAndFlatRimsWithinAHundredthOfAPixel) {
  const double s0 = 50.3, r0 = 40, step = 0.25;
  const int n = 81;
  for (double sigma : {0.875, 1.5}) {
    for (const RimCase& c : Cases()) {
      if (std::string(c.name) == "sheen") continue;
      const std::vector<float> p = BlurredRim(c.inside, 0.5, s0, sigma, r0, step, n);
      double rss;
      EXPECT_NEAR(RimProfileModel(sigma).Fit(p.data(), n, r0, step, 50.0, &rss), s0, 0.01) << c.name;
    }
  }
}

TEST(RimProfile, CurvedInteriorFitsItsOwnShapeExactly) {
  // a + c√d + e·d inside, a line outside: the five-term model's own family,
  // so its residual is quadrature error only and its edge is the true one;
  // the four-term model misses the e·d term.
  const double s0 = 50.3, r0 = 40, step = 0.25, sigma = 1.0;
  const int n = 81;
  const std::vector<float> p =
      BlurredRim([](double d) { return 0.1 + 0.05 * std::sqrt(d) + 0.02 * d; }, 0.5, s0, sigma, r0, step, n);
  double rss5, rss4;
  EXPECT_NEAR(RimProfileModel(sigma, true).Fit(p.data(), n, r0, step, 50.0, &rss5), s0, 0.005);
  RimProfileModel(sigma).Fit(p.data(), n, r0, step, 50.0, &rss4);
  EXPECT_LT(rss5, 1e-3 * rss4);
}

TEST(RimProfile, WindowLeavingTheProfileIsNaN) {
  const std::vector<float> p(20, 1.0f);
  double rss = 0;
  EXPECT_TRUE(std::isnan(RimProfileModel(1.0).Fit(p.data(), 20, 0, 0.25, 1.0, &rss)));
  EXPECT_TRUE(std::isnan(rss));
}

}  // namespace
}  // namespace brdfshot
