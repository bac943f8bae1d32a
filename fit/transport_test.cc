#include "fit/transport.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>

#include "fit/database.h"
#include "fit/standin.h"
#include "util/data_paths.h"

namespace brdfshot {

namespace {
MerlBrdf Lambert(const MerlGrid& grid, double albedo) {
  MerlBrdf m(grid);
  for (size_t idx = 0; idx < grid.size(); ++idx)
    if (grid.Measurable(idx))
      for (int c = 0; c < 3; ++c) m.set_raw(c, idx, albedo / kPi / kMerlScale[c]);
  return m;
}
LatLongProbe Constant(int w, float v) { return LatLongProbe(cv::Mat(w / 2, w, CV_32FC3, cv::Scalar::all(v))); }
}  // namespace

TEST(Transport, LambertianUnderAConstantProbeIsAlbedoTimesRadiance) {
  const MerlGrid grid{45, 45, 90};
  const PixelGeometry g = OrthographicSphere(32, 75);
  const TransportOperator t = TransportOperator::Build(g, Constant(64, 2.0f), grid, RenderQuality{});
  const Eigen::MatrixXd y = t.Render(Lambert(grid, 0.6));
  for (Eigen::Index p = 0; p < y.rows(); ++p)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(y(p, c), 0.6 * 2.0, 0.01 * 1.2) << "pixel " << p;
}

TEST(Transport, SingleBrightTexelFollowsTheCosineLaw) {
  cv::Mat img(32, 64, CV_32FC3, cv::Scalar::all(0));
  const int tc = 4, tr = 12;  // in front of the camera, upper left
  img.at<cv::Vec3f>(tr, tc) = cv::Vec3f(1000, 1000, 1000);
  const LatLongProbe probe(img);
  const Vec3 d = probe.DirectionAt(tc + 0.5, tr + 0.5);
  const double energy = 1000 * probe.TexelSolidAngle(tr);
  const MerlGrid grid{45, 45, 90};
  const PixelGeometry g = OrthographicSphere(48, 75);
  RenderQuality q;
  q.theta_samples = 32;
  q.phi_samples = 64;
  const Eigen::MatrixXd y = TransportOperator::Build(g, probe, grid, q).Render(Lambert(grid, 1.0));
  int checked = 0;
  for (size_t p = 0; p < g.size(); ++p) {
    const double cos_i = Dot(g.normal[p], d);
    // Near the terminator the prefilter footprint straddles the horizon and the
    // blurred texel loses part of its energy below it: the law is checked where
    // the light is at least 30° above the pixel's horizon.
    if (cos_i < 0.5) continue;
    const double want = energy * cos_i / kPi;
    EXPECT_NEAR(y(p, 1), want, 0.05 * want) << "cos=" << cos_i;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(Transport, NearMirrorMetalReflectsTheProbe) {
  // A smooth probe so the comparison does not depend on the lobe's exact width.
  cv::Mat img(128, 256, CV_32FC3);
  LatLongProbe tmp(img.clone());
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 256; ++c) {
      const Vec3 d = tmp.DirectionAt(c + 0.5, r + 0.5);
      img.at<cv::Vec3f>(r, c) = cv::Vec3f(1 + 0.5 * d.x, 1 + 0.4 * d.y, 1 - 0.3 * d.z);
    }
  const LatLongProbe probe(img);
  StandinMaterial metal;
  metal.family = "metal";
  metal.ks1 = 1.0;
  metal.alpha1 = 0.01;
  metal.f0[0] = metal.f0[1] = metal.f0[2] = 0.95;
  const MerlGrid grid = MerlGrid::Full();
  const PixelGeometry g = OrthographicSphere(32, 50);
  const Eigen::MatrixXd y = TransportOperator::Build(g, probe, grid, RenderQuality{}).Render(metal.ToMerl(grid));
  const PrefilteredProbe lookup(probe);
  for (size_t p = 0; p < g.size(); ++p) {
    const Vec3 r = Reflect(g.view[p], g.normal[p]);
    const double f = FresnelSchlick(0.95, Dot(g.view[p], g.normal[p]));
    const cv::Vec3f L = lookup.LookupLevel(r, 0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(y(p, c), f * L[c], 0.04 * f * L[c]) << "pixel " << p;
  }
}

TEST(Transport, RenderingAWeightVectorEqualsYTimesW) {
  const std::string tsv = DataPath("standin/materials.tsv");
  if (tsv.empty() || !std::filesystem::exists(tsv)) GTEST_SKIP() << "no stand-in";
  DatabaseOptions opt;
  opt.kind = "standin";
  opt.grid = MerlGrid{30, 30, 60};
  opt.max_materials = 6;
  const BasisDatabase db = LoadDatabase(opt);
  cv::Mat img(32, 64, CV_32FC3);
  cv::randu(img, 0, 4);
  const PixelGeometry g = OrthographicSphere(24, 80);
  const TransportOperator t = TransportOperator::Build(g, LatLongProbe(img), db.grid, RenderQuality{});
  const auto Y = t.Apply(db.B);
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(db.num_bases(), 3);
  for (int i = 0; i < db.num_bases(); ++i)
    for (int c = 0; c < 3; ++c) w(i, c) = 0.05 * ((i * 7 + c * 3) % 5);
  const Eigen::MatrixXd direct = t.Render(CombineBases(db, w));
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd via_y = Y[c].cast<double>() * w.col(c);
    EXPECT_LT((via_y - direct.col(c)).norm(), 1e-5 * direct.col(c).norm()) << "channel " << c;
  }
}

// Several BRDFs rendered in one pass: each image is what a render of that
// BRDF alone gives (to float rounding), and a Lambertian one under a constant
// probe is its albedo times the radiance; a BRDF on another grid is refused.
TEST(Transport, RenderingSeveralBrdfsAtOnceGivesEachItsOwnImage) {
  const MerlGrid grid{45, 45, 90};
  const PixelGeometry g = OrthographicSphere(32, 75);
  cv::Mat img(32, 64, CV_32FC3);
  cv::randu(img, 0.5, 3);
  StandinMaterial metal;
  metal.family = "metal";
  metal.ks1 = 1.0;
  metal.alpha1 = 0.05;
  metal.f0[0] = 0.9, metal.f0[1] = 0.6, metal.f0[2] = 0.3;
  const MerlBrdf a = Lambert(grid, 0.6), b = metal.ToMerl(grid), c = Lambert(grid, 0.2);
  for (const bool constant : {true, false}) {
    const TransportOperator t =
        TransportOperator::Build(g, constant ? Constant(64, 2.0f) : LatLongProbe(img.clone()), grid, RenderQuality{});
    const std::vector<Eigen::MatrixXd> all = t.RenderAll({&a, &b, &c});
    ASSERT_EQ(all.size(), 3u);
    const MerlBrdf* brdfs[] = {&a, &b, &c};
    for (int i = 0; i < 3; ++i) {
      const Eigen::MatrixXd alone = t.Render(*brdfs[i]);
      ASSERT_EQ(all[i].rows(), alone.rows());
      EXPECT_LT((all[i] - alone).norm(), 1e-6 * alone.norm()) << "BRDF " << i << (constant ? ", constant probe" : "");
    }
    if (constant)
      for (Eigen::Index p = 0; p < all[0].rows(); ++p)
        for (int ch = 0; ch < 3; ++ch) {
          EXPECT_NEAR(all[0](p, ch), 0.6 * 2.0, 0.01 * 1.2) << "pixel " << p;
          EXPECT_NEAR(all[2](p, ch), 0.2 * 2.0, 0.01 * 0.4) << "pixel " << p;
        }
  }
  const MerlBrdf other = Lambert(MerlGrid{30, 30, 60}, 0.5);
  const TransportOperator t = TransportOperator::Build(g, Constant(64, 1.0f), grid, RenderQuality{});
  EXPECT_THROW(t.RenderAll({&a, &other}), std::logic_error);
}

// Sharing the table reads is only a reordering of the work: each operator's
// images are those it renders alone, for different pixels, probes and suns.
TEST(Transport, ApplyingSeveralOperatorsAtOnceGivesEachItsOwnImages) {
  const MerlGrid grid{30, 30, 60};
  MatrixXfR B(grid.size(), 4);
  for (Eigen::Index r = 0; r < B.rows(); ++r)
    for (Eigen::Index c = 0; c < B.cols(); ++c) B(r, c) = static_cast<float>(((r * 13 + c * 7) % 29) / 29.0);
  cv::Mat noisy(32, 64, CV_32FC3);
  cv::randu(noisy, 0, 4);
  cv::Mat sun(32, 64, CV_32FC3, cv::Scalar::all(0.1));
  sun.at<cv::Vec3f>(9, 20) = cv::Vec3f(5000, 4000, 3000);  // split off as a directional light
  const TransportOperator a = TransportOperator::Build(OrthographicSphere(24, 80), LatLongProbe(noisy), grid, {});
  const TransportOperator b = TransportOperator::Build(OrthographicSphere(17, 60), LatLongProbe(sun), grid, {});
  ASSERT_TRUE(a.lights().empty());
  ASSERT_FALSE(b.lights().empty());
  const auto both = TransportOperator::ApplyToEach({&a, &b, &a}, B);
  ASSERT_EQ(both.size(), 3u);
  const std::array<MatrixXfR, 3> alone[3] = {a.Apply(B), b.Apply(B), a.Apply(B)};
  for (int o = 0; o < 3; ++o)
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(both[o][c].rows(), alone[o][c].rows());
      EXPECT_GT(alone[o][c].norm(), 0);
      EXPECT_LE((both[o][c] - alone[o][c]).cwiseAbs().maxCoeff(), 1e-6f * alone[o][c].cwiseAbs().maxCoeff())
          << "operator " << o << " channel " << c;
    }
}

// Several tables at once share the lighting per sample: each table's images
// are those it gets alone, whatever the other tables' widths, suns included.
TEST(Transport, ApplyingSeveralTablesAtOnceGivesEachItsOwnImages) {
  const MerlGrid grid{30, 30, 60};
  MatrixXfR B1(grid.size(), 5), B2(grid.size(), 2);
  for (Eigen::Index r = 0; r < B1.rows(); ++r) {
    for (Eigen::Index c = 0; c < B1.cols(); ++c) B1(r, c) = static_cast<float>(((r * 13 + c * 7) % 29) / 29.0);
    for (Eigen::Index c = 0; c < B2.cols(); ++c) B2(r, c) = static_cast<float>(((r * 5 + c * 11) % 17) / 3.0);
  }
  cv::Mat noisy(32, 64, CV_32FC3);
  cv::randu(noisy, 0, 4);
  cv::Mat sun(32, 64, CV_32FC3, cv::Scalar::all(0.1));
  sun.at<cv::Vec3f>(9, 20) = cv::Vec3f(5000, 4000, 3000);
  const TransportOperator a = TransportOperator::Build(OrthographicSphere(24, 80), LatLongProbe(noisy), grid, {});
  const TransportOperator b = TransportOperator::Build(OrthographicSphere(17, 60), LatLongProbe(sun), grid, {});
  ASSERT_FALSE(b.lights().empty());
  // The third table is a block of columns: its rows are strided.
  const auto all = TransportOperator::ApplyAll({&a, &b}, {MapOf(B1), MapOf(B2), MapOf(B1.middleCols(1, 3))});
  ASSERT_EQ(all.size(), 2u);
  const TransportOperator* ops[2] = {&a, &b};
  for (int o = 0; o < 2; ++o) {
    ASSERT_EQ(all[o].size(), 3u);
    const std::array<MatrixXfR, 3> alone[3] = {ops[o]->Apply(B1), ops[o]->Apply(B2), ops[o]->Apply(B1.middleCols(1, 3))};
    for (int t = 0; t < 3; ++t)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(all[o][t][c].rows(), alone[t][c].rows());
        ASSERT_EQ(all[o][t][c].cols(), alone[t][c].cols());
        EXPECT_GT(alone[t][c].norm(), 0);
        EXPECT_LE((all[o][t][c] - alone[t][c]).cwiseAbs().maxCoeff(), 1e-6f * alone[t][c].cwiseAbs().maxCoeff())
            << "operator " << o << " table " << t << " channel " << c;
      }
  }
  const MatrixXfR other_grid = MatrixXfR::Ones(7, 2);
  EXPECT_THROW(TransportOperator::ApplyAll({&a}, {MapOf(B1), MapOf(other_grid)}), std::logic_error);
}

TEST(Transport, OperatorsWithDifferentSamplingAreNotAppliedTogether) {
  const MerlGrid grid{30, 30, 60};
  const PixelGeometry g = OrthographicSphere(16, 80);
  RenderQuality finer;
  finer.theta_samples = 40;
  const TransportOperator a = TransportOperator::Build(g, Constant(64, 1.0f), grid, {});
  const TransportOperator b = TransportOperator::Build(g, Constant(64, 1.0f), grid, finer);
  RenderQuality other_probe_width;
  other_probe_width.probe_width = 32;  // the lighting's resolution is each operator's own
  const TransportOperator c = TransportOperator::Build(g, Constant(64, 1.0f), grid, other_probe_width);
  EXPECT_FALSE(a.SharesTableReadsWith(b));
  EXPECT_TRUE(a.SharesTableReadsWith(c));
  EXPECT_THROW(TransportOperator::ApplyToEach({&a, &b}, MatrixXfR::Ones(grid.size(), 2)), std::logic_error);
}

}  // namespace brdfshot

namespace brdfshot {

// Against an independent brute force: the analytic stand-in BRDF itself (not
// its table) integrated densely over the unfiltered demo probe. The operator
// sees only the 90×90×180 table, so this bounds quadrature + tabulation error
// together, one material per family.
TEST(Transport, MatchesADenseAnalyticReferenceForEveryFamily) {
  const std::string tsv = AssetPath("standin/materials.tsv");
  const std::string exr = AssetPath("envmaps/studio_256.exr");
  if (tsv.empty() || exr.empty()) GTEST_SKIP() << "samples/assets not found";
  const LatLongProbe probe = LatLongProbe::Read(exr);
  const PixelGeometry g = OrthographicSphere(24, 75);
  const TransportOperator t = TransportOperator::Build(g, probe, MerlGrid::Full(), RenderQuality{});
  std::map<std::string, bool> seen;
  for (const StandinMaterial& m : ReadStandinTable(tsv)) {
    if (seen[m.family]) continue;
    seen[m.family] = true;
    const Eigen::MatrixXd y = t.Render(m.ToMerl(MerlGrid::Full()));
    const Eigen::MatrixXd ref = RenderReference(
        g, probe, [&](const Vec3& wi, const Vec3& wo) { return m.Eval(wi, wo); }, 128, 256);
    const double err = (y - ref).norm() / ref.norm();
    std::printf("%-8s %-20s relative RMSE %.4f\n", m.family.c_str(), m.name.c_str(), err);
    EXPECT_LT(err, 0.03) << m.name;
  }
  EXPECT_EQ(seen.size(), 4u);
}

}  // namespace brdfshot

namespace brdfshot {
// A sun spread over a 2×2 texel block of a 1024-wide probe, each texel below
// the light share: counted on the 512-wide grid it is one light carrying the
// block's whole power at its centroid, and power is conserved.
TEST(ExtractLights, ASunSplitOverTexelsIsOneLightAtItsCentroid) {
  cv::Mat rgb(512, 1024, CV_32FC3, cv::Scalar::all(1));
  const int r0 = 200, c0 = 600;  // an even block: one cell of the 512 grid
  for (int r = r0; r < r0 + 2; ++r)
    for (int c = c0; c < c0 + 2; ++c) rgb.at<cv::Vec3f>(r, c) = cv::Vec3f(660, 440, 220);
  const LatLongProbe full(rgb);
  auto power = [](const LatLongProbe& p) {
    cv::Vec3d e(0, 0, 0);
    for (int r = 0; r < p.height(); ++r)
      for (int c = 0; c < p.width(); ++c) e += cv::Vec3d(p.Texel(c, r)) * p.TexelSolidAngle(r);
    return e;
  };
  const cv::Vec3d total = power(full);
  const double texel_share = 1320 * full.TexelSolidAngle(r0) / (total[0] + total[1] + total[2]);
  ASSERT_LT(texel_share, 0.002);  // per texel the sun would stay in the quadrature
  ASSERT_GT(4 * texel_share, 0.002);

  LatLongProbe per_texel = full;
  EXPECT_TRUE(ExtractLights(&per_texel, 64, 0.002, 0).empty());

  LatLongProbe rest = full;
  const std::vector<DirectionalLight> lights = ExtractLights(&rest, 64, 0.002, 512);
  ASSERT_EQ(lights.size(), 1u);
  // Centroid of four equal texels: the shared corner, up to the rows' solid-angle difference.
  const Vec3 corner = full.DirectionAt(c0 + 1, r0 + 1);
  EXPECT_LT(std::acos(std::min(1.0, Dot(lights[0].direction, corner))) * 180 / kPi, 0.01);
  const cv::Vec3d after = power(rest);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c] + lights[0].power[c], total[c], 1e-6 * total[c]);
  EXPECT_EQ(rest.Texel(c0, r0), cv::Vec3f(0, 0, 0));
}
}  // namespace brdfshot
