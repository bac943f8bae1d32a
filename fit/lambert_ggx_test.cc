#include "fit/lambert_ggx.h"

#include <gtest/gtest.h>

#include "calib/sun_probe.h"
#include "fit/standin.h"
#include "fit/transport.h"
#include "util/check.h"

namespace brdfshot {

namespace {
const MerlGrid kGrid{45, 45, 90};

// The weights on the lobe columns of kd / π + q [F0 (1 − s) + s] GGX(alphas[r]).
Eigen::MatrixXd ModelWeights(const LambertGgxLobes& lobes, int r, const double kd[3], const double f0[3], double q) {
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(lobes.columns(), 3);
  for (int c = 0; c < 3; ++c) w(0, c) = kd[c], w(1 + 2 * r, c) = q * f0[c], w(2 + 2 * r, c) = q;
  return w;
}

// A stand-in metal (GGX with Schlick's Fresnel) plus a stand-in Lambertian,
// tabulated by the stand-in database's own code.
Eigen::MatrixXd StandinTable(double alpha, const double kd[3], const double f0[3], double q) {
  StandinMaterial metal, matte;
  metal.family = "metal", metal.ks1 = q, metal.alpha1 = alpha;
  matte.family = "diffuse", matte.sigma = 0;
  for (int c = 0; c < 3; ++c) metal.f0[c] = f0[c], matte.kd[c] = kd[c];
  const MerlBrdf a = metal.ToMerl(kGrid), b = matte.ToMerl(kGrid);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kGrid.size()), 3);
  for (size_t i = 0; i < kGrid.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (a.raw(c, i) >= 0) out(static_cast<Eigen::Index>(i), c) = a.Value(c, i) + b.Value(c, i);
  return out;
}

LatLongProbe SunAndSky() {
  const Vec3 sun = Normalize(Vec3(0.5, 0.7, 0.6));
  return SunOverSkyProbe(sun, cv::Vec3f(1, 0.9, 0.8), cv::Vec3f(0.02f, 0.03f, 0.05f), 4.0, 128);
}
}  // namespace

TEST(LambertGgx, LobeColumnsAddUpToTheStandinMaterialsOwnFormula) {
  const LambertGgxLobes lobes;
  const MatrixXfR T = lobes.Tables(kGrid);
  const double kd[3] = {0.3, 0.2, 0.1}, f0[3] = {0.95, 0.64, 0.54};
  const int r = 4;
  const Eigen::MatrixXd want = StandinTable(lobes.alphas[r], kd, f0, 0.8);
  const Eigen::MatrixXd got = T.cast<double>() * ModelWeights(lobes, r, kd, f0, 0.8);
  double worst = 0;
  for (Eigen::Index i = 0; i < got.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(got(i, c) - want(i, c)) / std::max(1.0, std::abs(want(i, c))));
  EXPECT_LT(worst, 1e-5);
  EXPECT_GE(T.minCoeff(), 0.0f);
}

TEST(LambertGgx, AWhiteMirrorishLobeReflectsAConstantSkyAlmostWhole) {
  // GGX with Smith's height-correlated shadowing loses under 1 % of the
  // energy at α = 0.05 seen head-on (single scattering): a constant sky of
  // radiance 1 comes back at 0.99…1, read here to the 2 % the transport
  // reaches for a lobe this narrow on a half-resolution table.
  LambertGgxLobes lobes;
  lobes.alphas = {0.05};
  const PixelGeometry g = OrthographicSphere(48, 75);
  const LatLongProbe sky(cv::Mat(64, 128, CV_32FC3, cv::Scalar::all(1.0)));
  const TransportOperator t = TransportOperator::Build(g, sky, kGrid, RenderQuality{});
  const std::array<MatrixXfR, 3> L = t.Apply(lobes.Tables(kGrid));
  int checked = 0;
  for (size_t p = 0; p < g.size(); ++p) {
    if (Dot(g.normal[p], g.view[p]) < std::cos(30 * kPi / 180)) continue;
    const double white = L[1](static_cast<Eigen::Index>(p), 1) + L[1](static_cast<Eigen::Index>(p), 2);
    EXPECT_GT(white, 0.97) << "pixel " << p;
    EXPECT_LT(white, 1.02) << "pixel " << p;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(LambertGgx, FitRecoversTheParametersOfAStandinRenderedOnTheGrid) {
  const LambertGgxLobes lobes;
  const PixelGeometry g = OrthographicSphere(48, 80);
  const TransportOperator t = TransportOperator::Build(g, SunAndSky(), kGrid, RenderQuality{});
  const std::array<MatrixXfR, 3> L = t.Apply(lobes.Tables(kGrid));
  const double kd[3] = {0.5, 0.1, 0.05}, f0[3] = {0.04, 0.04, 0.04};
  const int r = 6;
  // The photo: the stand-in's table rendered through the same transport.
  const Eigen::MatrixXd table = StandinTable(lobes.alphas[r], kd, f0, 1.0);
  MatrixXfR tf = table.cast<float>();
  const std::array<MatrixXfR, 3> Y = t.Apply(tf);
  Eigen::MatrixXd y(static_cast<Eigen::Index>(g.size()), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = Y[c].col(c).cast<double>();
  const LambertGgxFit fit = FitLambertGgx(lobes, MakeLobeSystem(L, y));
  EXPECT_EQ(fit.alpha_index, r);
  EXPECT_LT(fit.relative_residual, 1e-4);
  EXPECT_NEAR(fit.specular_scale, 1.0, 1e-3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.diffuse_albedo[c], kd[c], 1e-3) << "channel " << c;
    EXPECT_NEAR(fit.SpecularF0()[c], f0[c], 2e-3) << "channel " << c;
  }
  // Its neighbours on the grid fit visibly worse: the search sees roughness.
  EXPECT_GT(fit.residual_by_alpha[r - 1], 10 * fit.relative_residual);
  EXPECT_GT(fit.residual_by_alpha[r + 1], 10 * fit.relative_residual);
}

TEST(LambertGgx, ABlackImageGivesZeroWeightsNotNaN) {
  const LambertGgxLobes lobes;
  const PixelGeometry g = OrthographicSphere(24, 80);
  const TransportOperator t = TransportOperator::Build(g, SunAndSky(), kGrid, RenderQuality{});
  const std::array<MatrixXfR, 3> L = t.Apply(lobes.Tables(kGrid));
  const LambertGgxFit fit =
      FitLambertGgx(lobes, MakeLobeSystem(L, Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(g.size()), 3)));
  EXPECT_TRUE(fit.weights.allFinite());
  EXPECT_EQ(fit.weights.norm(), 0.0);
  EXPECT_EQ(fit.relative_residual, 0.0);
}

TEST(LambertGgx, LobeDescriptionsRoundTripAndBadOnesNameTheFile) {
  LambertGgxLobes lobes;
  lobes.alphas = {0.1, 0.3};
  EXPECT_TRUE(LambertGgxLobes::FromJson(lobes.ToJson(), "x") == lobes);
  nlohmann::json bad = lobes.ToJson();
  bad["alphas"] = {0.1, 2.0};
  try {
    LambertGgxLobes::FromJson(bad, "scene.bsbi");
    FAIL() << "accepted α = 2";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.bsbi"), std::string::npos);
  }
  bad = lobes.ToJson();
  bad["model"] = "phong";
  EXPECT_THROW(LambertGgxLobes::FromJson(bad, "scene.bsbi"), Error);
}

}  // namespace brdfshot
