#include "fit/fit_stage.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>

#include "fit/class_model.h"
#include "fit/scene_basis.h"
#include "fit/standin.h"
#include "fit/test_databases.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

// A scene whose photo is exactly one database material: basis images, class
// model and photo on disk, as the stages before `fit` leave them.
struct Scene {
  // One folder per test: ctest runs the tests of a binary in parallel.
  fs::path dir =
      fs::temp_directory_path() /
      ("brdfshot_fit_stage_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  FitStageOptions o;
  Scene() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    cv::Mat sky(16, 32, CV_32FC3);
    cv::randu(sky, cv::Scalar::all(0.1), cv::Scalar::all(2.0));
    WriteExr((dir / "sky.exr").string(), sky);
    SceneBasisOptions so;
    so.probe = (dir / "sky.exr").string();
    so.sphere = 24;
    so.quality.theta_samples = 8, so.quality.phi_samples = 12;
    so.database = DemoStandins();
    const SceneBasis basis = ComputeSceneBasis(so);
    basis.images.Write((dir / "basis.bsbi").string());
    const BasisDatabase db = LoadDatabase(DemoStandins());
    ClassModel model = BuildClassModel(db.B.cast<double>().transpose() * db.B.cast<double>(), GmmOptions{});
    model.basis_names = basis.images.BasisNames();
    model.Write((dir / "classes.json").string());
    // The photo: material 5's three channel bases, each under its own light channel.
    const PixelGeometry& g = basis.images.geometry;
    cv::Mat photo(g.height, g.width, CV_32FC3, cv::Scalar::all(0));
    for (size_t i = 0; i < g.size(); ++i)
      for (int c = 0; c < 3; ++c) photo.at<cv::Vec3f>(g.y[i], g.x[i])[c] = basis.images.Y[c](i, 3 * 5 + c);
    WriteExr((dir / "photo.exr").string(), photo);
    o.basis = {(dir / "basis.bsbi").string()};
    o.photo = {(dir / "photo.exr").string()};
    o.classes = (dir / "classes.json").string();
    o.out = (dir / "fit").string();
    o.database = DemoStandins();
  }
  ~Scene() { fs::remove_all(dir); }
};

}  // namespace

// A photo that is exactly a database material is reproduced: the residual
// vanishes, and fit.json and brdf.binary read back.
TEST(FitStage, APhotoOfADatabaseMaterialIsReproducedAndWritten) {
  Scene s;
  const FitStageResult r = RunFitStage(s.o);
  EXPECT_LT(r.record.relative_residual, 0.02);
  const FitRecord back = FitRecord::Read(s.o.out + "/fit.json");
  EXPECT_EQ(back.chosen_class, r.record.chosen_class);
  // The stage holds the tables on the basis images' grid: the prior
  // sensitivity is measured and written.
  EXPECT_GE(r.record.prior_sensitivity, 0);
  EXPECT_EQ(back.prior_sensitivity, r.record.prior_sensitivity);
  EXPECT_EQ(MerlBrdf::Read(s.o.out + "/brdf.binary").grid().size(), MerlGrid({10, 10, 20}).size());
  EXPECT_TRUE(fs::exists(s.o.out + "/photo_vs_fit.png"));
  // The analytic baseline beside it, read back: material 5 is demo-blue-plastic
  // (Lambert kd = 0.05, 0.10, 0.45 under a dielectric GGX lobe of α = 0.08,
  // samples/assets/standin/materials.tsv), which Lambert + GGX nearly holds.
  ASSERT_TRUE(back.lambert_ggx.has_value());
  const LambertGgxFit& g = *back.lambert_ggx;
  EXPECT_EQ(g.alpha, r.record.lambert_ggx->alpha);
  EXPECT_LT(g.relative_residual, 0.03);
  EXPECT_NEAR(std::log(g.alpha / 0.08), 0, std::log(1.25)) << "α within a step of the grid of 0.08";
  const double kd[3] = {0.05, 0.10, 0.45};
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(g.diffuse_albedo[c], kd[c], 0.02) << "channel " << c;
    // F0 of a dielectric of index 1.5 is 0.04; Schlick's curve is not the
    // dielectric's, and a 24-pixel sphere under a random sky lets F0 and the
    // scale trade off (0.04 … 0.07 seen): a dielectric, not a metal (F0 ≥ 0.5).
    EXPECT_GT(g.SpecularF0()[c], 0.01) << "channel " << c;
    EXPECT_LT(g.SpecularF0()[c], 0.12) << "channel " << c;
  }
  EXPECT_NEAR(g.specular_scale, 0.6, 0.15);
  // Its table: the closed form of those parameters (the stand-in code's GGX
  // and Schlick) at every measurable bin.
  const MerlBrdf table = MerlBrdf::Read(s.o.out + "/lambert_ggx.binary");
  const MerlGrid& grid = table.grid();
  int checked = 0;
  for (size_t idx = 0; idx < grid.size(); idx += 7) {
    if (!grid.Measurable(idx)) continue;
    int i, j, k;
    grid.Unindex(idx, &i, &j, &k);
    Vec3 wi, wo;
    FromHalfDiff(grid.LatticePoint(i, j, k), &wi, &wo);
    const double cos_d = Dot(wi, Normalize(wi + wo));
    for (int c = 0; c < 3; ++c) {
      const double want = g.diffuse_albedo[c] / kPi +
                          GgxLobe(g.specular_scale, g.alpha, FresnelSchlick(g.SpecularF0()[c], cos_d), wi, wo);
      ASSERT_NEAR(table.Value(c, idx), want, 1e-5 * std::max(1.0, want)) << "bin " << idx << " channel " << c;
    }
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A class model of other bases is refused before anything is written.
// A joint fit shows every photo beside its own reconstruction. The second
// capture is the first under a probe twice as bright (basis images and photo
// doubled): each picture is tone-mapped by its own photo's exposure, so with
// each reconstruction in its own photo's scale the two pictures are the same
// image; a reconstruction taken from the wrong rows or scale is half as bright.
TEST(FitStage, AJointFitShowsEveryPhotoBesideItsOwnReconstruction) {
  Scene s;
  BasisImages brighter = BasisImages::Read(s.o.basis[0]);
  for (int c = 0; c < 3; ++c) brighter.Y[c] *= 2, brighter.lobes[c] *= 2;
  brighter.Write((s.dir / "basis2.bsbi").string());
  WriteExr((s.dir / "photo2.exr").string(), ReadHdrImage(s.o.photo[0]) * 2);
  s.o.basis = {s.o.basis[0], (s.dir / "basis2.bsbi").string()};
  s.o.photo = {s.o.photo[0], (s.dir / "photo2.exr").string()};
  RunFitStage(s.o);
  const cv::Mat first = cv::imread(s.o.out + "/photo_vs_fit.png"), second = cv::imread(s.o.out + "/photo_vs_fit_2.png");
  ASSERT_FALSE(first.empty());
  ASSERT_FALSE(second.empty());
  const int w = first.cols / 2;
  EXPECT_LE(cv::norm(first.colRange(0, w), second.colRange(0, w), cv::NORM_INF), 1) << "the photos";
  EXPECT_LE(cv::norm(first.colRange(w, 2 * w), second.colRange(w, 2 * w), cv::NORM_INF), 1) << "the fits";
  EXPECT_FALSE(fs::exists(s.o.out + "/photo_vs_fit_3.png"));
}

TEST(FitStage, AClassModelOfOtherBasesIsRefusedAndNothingIsWritten) {
  Scene s;
  ClassModel m = ClassModel::Read(s.o.classes);
  m.basis_names[4] = "other/G";
  m.Write(s.o.classes);
  try {
    RunFitStage(s.o);
    ADD_FAILURE() << "a model of other bases is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(s.o.classes + ": basis 4 is 'other/G'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(s.o.out));
}

}  // namespace brdfshot
