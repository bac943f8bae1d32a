#include "fit/quality_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "fit/basis_reference.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

// The repository's own demo assets (always present): 16 analytic materials,
// 4 per family, and a 256-wide studio probe.
struct DemoScene {
  BasisDatabase db;
  LatLongProbe probe;
  PixelGeometry sphere = OrthographicSphere(40, 78);
};

bool LoadDemo(DemoScene* s) {
  const std::string tsv = AssetPath("standin/materials.tsv");
  const std::string exr = AssetPath("envmaps/studio_256.exr");
  if (tsv.empty() || exr.empty()) return false;
  DatabaseOptions opt;
  opt.kind = "standin";
  opt.data_root = std::filesystem::path(tsv).parent_path().parent_path().string();
  opt.grid = MerlGrid{45, 45, 90};
  s->db = LoadDatabase(opt);
  s->probe = LatLongProbe::Read(exr);
  return true;
}

QualitySearchOptions FastOptions(double target) {
  QualitySearchOptions o;
  o.target = target;
  o.pixels = 120;
  o.reference_theta = 96;
  o.reference_phi = 192;
  return o;
}

TEST(QualitySearch, TestMaterialsCoverEveryStandinFamilyOnce) {
  BasisDatabase db;
  db.materials = {"d1", "d2", "p1", "m1", "m2", "x1"};
  db.families = {"diffuse", "diffuse", "plastic", "metal", "metal", "paint"};
  const auto t = ErrorTestMaterials(db);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0].index, 0);
  EXPECT_EQ(t[1].index, 2);
  EXPECT_EQ(t[2].index, 3);
  EXPECT_EQ(t[3].index, 5);
  EXPECT_EQ(t[3].label, "paint");
}

TEST(QualitySearch, MerlDatabasesUseTheNamedReferenceMaterials) {
  BasisDatabase db;
  db.materials = {"alum-bronze", "chrome", "pvc", "blue-fabric"};
  const auto t = ErrorTestMaterials(db);
  ASSERT_EQ(t.size(), 3u);  // in ReferenceClasses order: diffuse, plastic, metal
  EXPECT_EQ(db.materials[t[0].index], "blue-fabric");
  EXPECT_EQ(t[0].label, "diffuse");
  EXPECT_EQ(db.materials[t[1].index], "pvc");
  EXPECT_EQ(db.materials[t[2].index], "chrome");
  EXPECT_EQ(t[2].label, "metal");
}

TEST(QualitySearch, LadderGoesToTheFullProbeOnlyWhenTheDefaultResamplesIt) {
  RenderQuality base;
  base.probe_width = 512;
  for (const RenderQuality& q : QualityLadder(base, 256)) EXPECT_EQ(q.probe_width, 512);
  for (const RenderQuality& q : QualityLadder(RenderQuality{}, 1024)) EXPECT_EQ(q.probe_width, 0);  // the default
  const auto wide = QualityLadder(base, 1024);
  EXPECT_EQ(wide.front().probe_width, 512);
  EXPECT_EQ(wide.back().probe_width, 0);
  // Cheap to fine: the resampled probe's settings first, and within one probe
  // width the sample counts never decrease.
  for (size_t i = 1; i < wide.size(); ++i) {
    EXPECT_FALSE(wide[i - 1].probe_width == 0 && wide[i].probe_width != 0) << i;
    if (wide[i].probe_width == wide[i - 1].probe_width) {
      EXPECT_GE(wide[i].theta_samples * wide[i].phi_samples, wide[i - 1].theta_samples * wide[i - 1].phi_samples);
    }
  }
}

TEST(QualitySearch, BadTargetsAreRefused) {
  DemoScene s;
  if (!LoadDemo(&s)) GTEST_SKIP() << "samples/assets not found";
  for (double t : {0.0, -0.01, std::nan("")})
    EXPECT_THROW(ChooseQuality(s.sphere, s.probe, s.db, RenderQuality{}, FastOptions(t), nullptr), Error);
}

// A loose target is met by the cheapest setting; an unreachable one walks the
// whole ladder, says so, and keeps the setting with the least error.
TEST(QualitySearch, StopsAtTheFirstSettingWithinTargetElseKeepsTheBest) {
  DemoScene s;
  if (!LoadDemo(&s)) GTEST_SKIP() << "samples/assets not found";
  const QualityChoice loose = ChooseQuality(s.sphere, s.probe, s.db, RenderQuality{}, FastOptions(0.5), nullptr);
  EXPECT_TRUE(loose.reached);
  ASSERT_EQ(loose.trials.size(), 1u);
  EXPECT_EQ(loose.quality.theta_samples, 16);
  EXPECT_EQ(loose.trials[0].label_error.size(), 4u);  // one per family

  const QualityChoice tight = ChooseQuality(s.sphere, s.probe, s.db, RenderQuality{}, FastOptions(1e-7), nullptr);
  EXPECT_FALSE(tight.reached);
  for (const auto& t : tight.trials)
    std::printf("%2dx%-2d probe %d: worst %.4f\n", t.quality.theta_samples, t.quality.phi_samples,
                t.quality.probe_width, t.worst);
  EXPECT_EQ(tight.trials.size(), QualityLadder(RenderQuality{}, s.probe.width()).size());
  double best = 1e9;
  for (const auto& t : tight.trials) best = std::min(best, t.worst);
  bool chosen_is_best = false;
  for (const auto& t : tight.trials)
    if (t.worst == best && t.quality.Describe() == tight.quality.Describe()) chosen_is_best = true;
  EXPECT_TRUE(chosen_is_best);
  EXPECT_GT(tight.pixels, 60u);
  EXPECT_LT(tight.pixels, 250u);
}

// The subset's estimate must hold for the pixels it did not see: render the
// chosen setting on a disjoint pixel set and compare with its own reference.
TEST(QualitySearch, TheChosenSettingMeetsTheTargetOnPixelsItWasNotChosenOn) {
  DemoScene s;
  if (!LoadDemo(&s)) GTEST_SKIP() << "samples/assets not found";
  const double target = 0.022;
  const QualityChoice c = ChooseQuality(s.sphere, s.probe, s.db, RenderQuality{}, FastOptions(target), nullptr);
  ASSERT_TRUE(c.reached) << "the studio probe is easy: some setting must reach 2.2 %";
  // On this coarse 45 × 45 × 90 table the cheapest setting is ~2.6 % off: the
  // search must have walked past it.
  EXPECT_GE(c.trials.size(), 2u);
  // Pixels off the search's grid (it keeps x, y divisible by its step, here 3).
  PixelGeometry other;
  other.width = s.sphere.width;
  other.height = s.sphere.height;
  for (size_t i = 0; i < s.sphere.size(); ++i)
    if (s.sphere.x[i] % 3 == 1 && s.sphere.y[i] % 3 == 1) {
      other.x.push_back(s.sphere.x[i]);
      other.y.push_back(s.sphere.y[i]);
      other.normal.push_back(s.sphere.normal[i]);
      other.view.push_back(s.sphere.view[i]);
    }
  const auto tests = ErrorTestMaterials(s.db);
  std::vector<int> mats;
  for (const auto& t : tests) mats.push_back(t.index);
  const BasisImages ref = RenderReferenceImages(other, s.probe, s.db, mats, 96, 192, nullptr);
  const MatrixXfR B = MaterialColumns(s.db, mats);
  const auto Y = TransportOperator::Build(other, s.probe, s.db.grid, c.quality).Apply(B);
  double worst = 0;
  for (Eigen::Index col = 0; col < B.cols(); ++col) {
    const int ch = static_cast<int>(col % 3);
    worst = std::max(worst, RelativeRmse(Y[ch].col(col).cast<double>(), ref.Y[ch].col(col).cast<double>()));
  }
  std::printf("chosen %s: subset %.4f, other pixels %.4f (target %.3f)\n", c.quality.Describe().c_str(),
              c.trials.back().worst, worst, target);
  EXPECT_LT(worst, 1.5 * target);
}

}  // namespace
}  // namespace brdfshot
