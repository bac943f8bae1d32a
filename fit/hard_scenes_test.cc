// Numerically hard scenes (docs/benchmarks.md, "Numerically hard scenes"), end to end through the
// fit stage: basis images → class model → class-wise solve, leave-one-out on
// the demo stand-in database (samples/assets, always in the repository).
//
// Every scene states what it expects: finite weights, the conditioning the fit
// reports, and the relit error (relative RMSE of the fitted material's image
// under the studio probe turned by 90°, against the true material's) within a
// stated factor of the same fit on an easy scene — a 64-pixel sphere, material
// of normal brightness, studio lighting. The bounds were set from measured
// values with margin; the measured values are in docs/benchmarks.md "Numerically hard
// scenes".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <filesystem>

#include "fit/class_model.h"
#include "fit/database.h"
#include "fit/loo_eval.h"
#include "fit/solver.h"
#include "fit/transport.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace {

using Images = std::array<MatrixXfR, 3>;

struct World {
  BasisDatabase db;
  Eigen::MatrixXd gram;
  LatLongProbe studio, turned;
};

const World* GetWorld() {
  static const World* world = []() -> const World* {
    const std::string tsv = AssetPath("standin/materials.tsv");
    const std::string exr = AssetPath("envmaps/studio_256.exr");
    if (tsv.empty() || exr.empty()) return nullptr;
    auto* w = new World;
    DatabaseOptions opt;
    opt.kind = "standin";
    opt.data_root = std::filesystem::path(tsv).parent_path().parent_path().string();
    opt.grid = MerlGrid{30, 30, 60};
    w->db = LoadDatabase(opt);
    w->gram = GramMatrix(w->db.B);
    w->studio = LatLongProbe::Read(exr);
    cv::Mat turned;  // yaw 90°: roll the columns by a quarter turn
    const cv::Mat& s = w->studio.rgb();
    const int q = s.cols / 4;
    cv::hconcat(s.colRange(q, s.cols), s.colRange(0, q), turned);
    w->turned = LatLongProbe(turned, "studio turned 90°");
    return w;
  }();
  return world;
}

Images BasisImagesOf(const PixelGeometry& g, const LatLongProbe& probe, const BasisDatabase& db) {
  return TransportOperator::Build(g, probe, db.grid, RenderQuality{}).Apply(db.B);
}

std::array<Eigen::MatrixXd, 3> Grams(const Images& Y) {
  std::array<Eigen::MatrixXd, 3> g;
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd y = Y[c].cast<double>();
    g[c] = y.transpose() * y;
  }
  return g;
}

// The true material m's image: channel c of m under light channel c.
Eigen::MatrixXd ImageOf(const Images& Y, int m) {
  Eigen::MatrixXd y(Y[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = Y[c].col(3 * m + c).cast<double>();
  return y;
}

Images KeepRows(const Images& Y, const std::vector<int>& rows) {
  Images out;
  for (int c = 0; c < 3; ++c) {
    out[c].resize(static_cast<Eigen::Index>(rows.size()), Y[c].cols());
    for (size_t i = 0; i < rows.size(); ++i) out[c].row(static_cast<Eigen::Index>(i)) = Y[c].row(rows[i]);
  }
  return out;
}

struct FitResult {
  Eigen::MatrixXd weights;  // n × 3, in the units of the observation
  int chosen = -1;
  double condition = 0;  // green channel, chosen class
  double insample = 0;   // ‖Y w − y‖ / ‖y‖
};

// Leave-one-out fit of observation y (pixels × 3) of material m on the rows of
// basis images Y: m's columns are dropped and the classes re-fitted without them.
FitResult FitLeavingOut(const World& w, const Images& Y, const Eigen::MatrixXd& y, int m, double lambda) {
  std::vector<int> keep;
  for (int i = 0; i < w.db.num_bases(); ++i)
    if (i / 3 != m) keep.push_back(i);
  const ClassModel model = FitGmm(ProjectFromGram(w.gram(keep, keep), 4), GmmOptions{});
  std::vector<std::vector<int>> members(model.classes());
  for (size_t i = 0; i < keep.size(); ++i) members[model.label[i]].push_back(keep[i]);
  const auto f = FactorBasisImages(Y, true);
  SolveOptions so;
  so.lambda = lambda;
  const ClasswiseFit fit = SolveClasswise(f, MakeObservation(f, Y, y), members, so);
  FitResult r;
  r.weights = fit.weights();
  r.chosen = fit.chosen;
  r.condition = fit.classes[fit.chosen].condition[1];
  double num = 0;
  for (int c = 0; c < 3; ++c) num += (Y[c].cast<double>() * r.weights.col(c) - y.col(c)).squaredNorm();
  r.insample = std::sqrt(num) / y.norm();
  return r;
}

double RelitError(const std::array<Eigen::MatrixXd, 3>& g, const Eigen::MatrixXd& w, int m) {
  return RelativeError({&g[0], &g[1], &g[2]}, w, m);
}

bool AllFinite(const Eigen::MatrixXd& m) { return m.allFinite(); }

// Material m fitted from its own image under Y (leave-one-out, λ 0.5), and
// that fit's relit error under the Gram matrices `relight`.
struct Scored {
  FitResult fit;
  double relit = 0;
};
Scored FitOwnImage(const World& w, const Images& Y, int m, const std::array<Eigen::MatrixXd, 3>& relight) {
  FitResult r = FitLeavingOut(w, Y, ImageOf(Y, m), m, 0.5);
  const double relit = RelitError(relight, r.weights, m);
  return {std::move(r), relit};
}

// One material per family of the demo table.
std::vector<int> OnePerFamily(const BasisDatabase& db) {
  std::vector<int> out;
  std::vector<std::string> seen;
  for (int m = 0; m < db.num_materials(); ++m)
    if (std::find(seen.begin(), seen.end(), db.families[m]) == seen.end()) {
      seen.push_back(db.families[m]);
      out.push_back(m);
    }
  return out;
}

struct Baseline {
  Images Y;
  std::array<Eigen::MatrixXd, 3> relight;  // Gram matrices under the turned probe
  std::vector<double> error;               // per material of OnePerFamily
  std::vector<double> condition;
};

const Baseline& GetBaseline(const World& w) {
  static const Baseline b = [&] {
    Baseline b;
    const PixelGeometry g = OrthographicSphere(64);
    b.Y = BasisImagesOf(g, w.studio, w.db);
    b.relight = Grams(BasisImagesOf(g, w.turned, w.db));
    for (int m : OnePerFamily(w.db)) {
      const Scored sc = FitOwnImage(w, b.Y, m, b.relight);
      const FitResult& r = sc.fit;
      b.error.push_back(sc.relit);
      b.condition.push_back(r.condition);
      std::printf("[easy] %-24s relit %.4f  condition %.3g  in-sample %.4f\n", w.db.materials[m].c_str(),
                  b.error.back(), r.condition, r.insample);
    }
    return b;
  }();
  return b;
}

#define REQUIRE_WORLD()                                   \
  const World* world = GetWorld();                        \
  if (!world) GTEST_SKIP() << "samples/assets not found"; \
  const World& w = *world;                                \
  const Baseline& base = GetBaseline(w);                  \
  const std::vector<int> mats = OnePerFamily(w.db)

}  // namespace

// λ → 0 with exactly collinear basis images: every material's columns doubled.
// The augmented system is singular; the fit must stay finite, report an
// infinite (or ≥ 1e12) condition number, and — since the minimum-norm answer
// splits a weight between the twins — reproduce the same fitted image as the
// λ → 0 fit without the twins.
TEST(HardScenes, LambdaToZeroWithExactlyCollinearBases) {
  REQUIRE_WORLD();
  const int m = mats[1];
  const Eigen::MatrixXd y = ImageOf(base.Y, m);
  Images twins;
  for (int c = 0; c < 3; ++c) {
    twins[c].resize(base.Y[c].rows(), 2 * base.Y[c].cols());
    twins[c] << base.Y[c], base.Y[c];
  }
  const auto f1 = FactorBasisImages(base.Y, true), f2 = FactorBasisImages(twins, true);
  // One class holding everything but m (and m's twin).
  std::vector<int> one, two;
  for (int i = 0; i < w.db.num_bases(); ++i)
    if (i / 3 != m) {
      one.push_back(i);
      two.push_back(i);
      two.push_back(i + w.db.num_bases());
    }
  SolveOptions so;
  so.lambda = 0;
  const ClasswiseFit a = SolveClasswise(f1, MakeObservation(f1, base.Y, y), {one}, so);
  const ClasswiseFit b = SolveClasswise(f2, MakeObservation(f2, twins, y), {two}, so);
  ASSERT_TRUE(AllFinite(b.weights()));
  EXPECT_GT(b.classes[0].condition[1], 1e12) << "a singular system must be reported as such";
  double max_w = 0;
  for (int c = 0; c < 3; ++c) max_w = std::max(max_w, b.weights().col(c).cwiseAbs().maxCoeff());
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd ya = base.Y[c].cast<double>() * a.weights().col(c);
    const Eigen::VectorXd yb = twins[c].cast<double>() * b.weights().col(c);
    EXPECT_LT((ya - yb).norm(), 1e-6 * ya.norm()) << "channel " << c;
    // Minimum norm: a twin pair carries equal halves.
    for (int i : one) EXPECT_NEAR(b.weights()(i, c), b.weights()(i + w.db.num_bases(), c), 1e-4 * max_w);
  }
  // λ → 0 through positive values: finite at every λ, the fitted image
  // continuous (the weights need not be: along directions the data do not
  // see, a tiny λ and the rank cut of λ = 0 pick different answers).
  for (int c = 0; c < 3; ++c) max_w = std::max(max_w, a.weights().col(c).cwiseAbs().maxCoeff());
  for (double lambda : {1e-12, 1e-9, 1e-6, 1e-3, 0.5}) {
    SolveOptions so2;
    so2.lambda = lambda;
    const ClasswiseFit t = SolveClasswise(f1, MakeObservation(f1, base.Y, y), {one}, so2);
    ASSERT_TRUE(AllFinite(t.weights())) << "lambda " << lambda;
    double dy = 0;
    for (int c = 0; c < 3; ++c)
      dy += (base.Y[c].cast<double>() * (t.weights().col(c) - a.weights().col(c))).squaredNorm();
    std::printf("[lambda] %-8g |w| %.3g relit %.4f condition %.3g in-sample change %.2g\n", lambda, t.weights().norm(),
                RelitError(base.relight, t.weights(), m), t.classes[0].condition[1], std::sqrt(dy) / y.norm());
    if (lambda <= 1e-6) {
      EXPECT_LT(std::sqrt(dy), 1e-3 * y.norm()) << "lambda " << lambda;
    }
    // The reported conditioning grows as 1/√λ once λ dominates the smallest
    // singular value (the demo's grey diffuse bases are exactly collinear).
    if (lambda == 1e-12) {
      EXPECT_GT(t.classes[0].condition[1], 1e8);
    }
    if (lambda == 0.5) {
      EXPECT_LT(t.classes[0].condition[1], 1e4);
    }
  }
  EXPECT_TRUE(std::isinf(a.classes[0].condition[1])) << "λ = 0 on collinear bases is singular";
  std::printf("[lambda] 0        |w| %.3g relit %.4f condition %.3g\n", a.weights().norm(),
              RelitError(base.relight, a.weights(), m), a.classes[0].condition[1]);
}

// A nearly black material: the true image scaled by 1e-4. The paper's prior
// (the class mean, 1/c_j per basis) is in absolute units while λ_j = λ‖y‖²/c_j
// scales with the data, so for a dark material the pull towards the mean
// fades as its brightness squared: the fit of s·y is s times the λ → 0 fit.
// Documented, not "fixed" (docs/benchmarks.md "Numerically hard scenes"); the test pins it.
TEST(HardScenes, NearlyBlackMaterialIsFittedAsLambdaToZero) {
  REQUIRE_WORLD();
  for (size_t k = 0; k < mats.size(); ++k) {
    const int m = mats[k];
    const double s = 1e-4;
    const Eigen::MatrixXd y = ImageOf(base.Y, m);
    const FitResult dark = FitLeavingOut(w, base.Y, s * y, m, 0.5);
    const FitResult lsq = FitLeavingOut(w, base.Y, y, m, 0.0);
    ASSERT_TRUE(AllFinite(dark.weights));
    const double err = RelitError(base.relight, dark.weights / s, m);
    double dy = 0;
    for (int c = 0; c < 3; ++c)
      dy += (base.Y[c].cast<double>() * (dark.weights.col(c) / s - lsq.weights.col(c))).squaredNorm();
    std::printf("[black] %-24s relit %.4f (easy %.4f, lambda 0 %.4f) condition %.3g in-sample %.4f\n",
                w.db.materials[m].c_str(), err, base.error[k], RelitError(base.relight, lsq.weights, m), dark.condition,
                dark.insample);
    EXPECT_EQ(dark.chosen, lsq.chosen);
    EXPECT_LT(std::sqrt(dy), 0.01 * y.norm()) << w.db.materials[m];
  }
}

// Overcast: a constant probe with the studio's mean radiance.
TEST(HardScenes, OvercastConstantProbe) {
  REQUIRE_WORLD();
  const cv::Scalar mean = cv::mean(w.studio.rgb());
  const LatLongProbe overcast(cv::Mat(w.studio.height(), w.studio.width(), CV_32FC3, mean), "overcast");
  const PixelGeometry g = OrthographicSphere(64);
  const Images Y = BasisImagesOf(g, overcast, w.db);
  // What an overcast sky shows: every basis image depends on θ_o alone (closed
  // form: rotate the sphere about the view axis and nothing changes). Checked
  // on pixel pairs mirrored through the centre, which share θ_o.
  for (int i = 0; i < w.db.num_bases(); i += 5)
    for (size_t p = 0; p < g.size(); p += 97) {
      for (size_t r = 0; r < g.size(); ++r)
        if (g.x[r] == g.width - 1 - g.x[p] && g.y[r] == g.height - 1 - g.y[p]) {
          const double a = Y[1](p, i), b = Y[1](r, i);
          EXPECT_NEAR(a, b, 0.02 * std::max(std::abs(a), 1e-3 * Y[1].col(i).cwiseAbs().maxCoeff())) << "basis " << i;
        }
    }
  double relit = 0, easy = 0;
  for (size_t k = 0; k < mats.size(); ++k) {
    const int m = mats[k];
    const Scored sc = FitOwnImage(w, Y, m, base.relight);
    const FitResult& r = sc.fit;
    ASSERT_TRUE(AllFinite(r.weights));
    const double err = sc.relit;
    std::printf("[overcast] %-24s relit %.4f (easy %.4f) condition %.3g (easy %.3g) in-sample %.4f\n",
                w.db.materials[m].c_str(), err, base.error[k], r.condition, base.condition[k], r.insample);
    EXPECT_LT(r.insample, 0.03) << "the fit must still match what it saw";
    relit += err;
    easy += base.error[k];
  }
  // Only a function of θ_o is observed, so the BRDF is not identified: relit
  // elsewhere it is far worse than under the studio (measured 2.5–11×).
  EXPECT_GT(relit, 2 * easy);
}

// A 30-pixel sphere.
TEST(HardScenes, ThirtyPixelSphere) {
  REQUIRE_WORLD();
  const PixelGeometry g = OrthographicSphere(30);
  const Images Y = BasisImagesOf(g, w.studio, w.db);
  for (size_t k = 0; k < mats.size(); ++k) {
    const int m = mats[k];
    const Scored sc = FitOwnImage(w, Y, m, base.relight);
    const FitResult& r = sc.fit;
    ASSERT_TRUE(AllFinite(r.weights));
    // Scored on the 64-pixel sphere: the BRDF, not the few pixels.
    const double err = sc.relit;
    std::printf("[30px] %-24s pixels %zu relit %.4f (easy %.4f) condition %.3g\n", w.db.materials[m].c_str(), g.size(),
                err, base.error[k], r.condition);
    EXPECT_LT(err, 1.25 * base.error[k]) << "measured within 5 % of the 64-pixel sphere";
  }
}

// Half the sphere saturated: pixels whose brightest channel is above the median are clipped.
// The capture stage flags them (merge's mask) and remap drops them; fitting the
// clipped values instead is what happens without the mask.
TEST(HardScenes, HalfSaturatedSphere) {
  REQUIRE_WORLD();
  double sum_masked = 0, sum_naive = 0;
  for (size_t k = 0; k < mats.size(); ++k) {
    const int m = mats[k];
    const Eigen::MatrixXd y = ImageOf(base.Y, m);
    const Eigen::VectorXd brightest = y.rowwise().maxCoeff();
    std::vector<double> sorted(brightest.data(), brightest.data() + brightest.size());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double clip = sorted[sorted.size() / 2];
    std::vector<int> kept;
    for (Eigen::Index p = 0; p < y.rows(); ++p)
      if (brightest[p] <= clip) kept.push_back(static_cast<int>(p));
    const Eigen::MatrixXd clipped = y.cwiseMin(clip);
    Eigen::MatrixXd ykept(kept.size(), 3);
    for (size_t i = 0; i < kept.size(); ++i) ykept.row(i) = y.row(kept[i]);
    const FitResult masked = FitLeavingOut(w, KeepRows(base.Y, kept), ykept, m, 0.5);
    const FitResult naive = FitLeavingOut(w, base.Y, clipped, m, 0.5);
    ASSERT_TRUE(AllFinite(masked.weights));
    const double e_masked = RelitError(base.relight, masked.weights, m);
    const double e_naive = RelitError(base.relight, naive.weights, m);
    std::printf("[saturated] %-24s kept %zu/%ld masked %.4f (in-sample %.4f) clipped-in %.4f (easy %.4f)\n",
                w.db.materials[m].c_str(), kept.size(), static_cast<long>(y.rows()), e_masked, masked.insample, e_naive,
                base.error[k]);
    sum_masked += e_masked;
    sum_naive += e_naive;
  }
  // Clipped values are wrong data; dropping them is better overall (measured
  // 1.80 vs 2.85 summed over the four), though both lose the highlight, which
  // no solve can recover: the bracket must expose it (merge names such frames).
  EXPECT_LT(sum_masked, 0.8 * sum_naive);
}

// A single-texel sun over a dim sky (the sun holds ~99 % of the power).
TEST(HardScenes, SingleTexelSun) {
  REQUIRE_WORLD();
  cv::Mat img(128, 256, CV_32FC3, cv::Scalar::all(0.01));
  const LatLongProbe shape(img.clone());
  const int sc = 100, sr = 40;  // upper hemisphere, in front of the camera
  const double sky = 0.01 * 4 * kPi;
  img.at<cv::Vec3f>(sr, sc) = cv::Vec3f::all(static_cast<float>(99 * sky / shape.TexelSolidAngle(sr)));
  const LatLongProbe sun(img, "sun");
  const Images Y = BasisImagesOf(OrthographicSphere(64), sun, w.db);
  double sum_sun = 0, sum_easy = 0;
  for (size_t k = 0; k < mats.size(); ++k) {
    const int m = mats[k];
    const Scored sc = FitOwnImage(w, Y, m, base.relight);
    const FitResult& r = sc.fit;
    ASSERT_TRUE(AllFinite(r.weights));
    const double err = sc.relit;
    std::printf("[sun] %-24s relit %.4f (easy %.4f) condition %.3g in-sample %.4f\n", w.db.materials[m].c_str(), err,
                base.error[k], r.condition, r.insample);
    EXPECT_LT(r.insample, 0.25);
    sum_sun += err;
    sum_easy += base.error[k];
  }
  // One sun shows a highlight and a terminator: more than an overcast sky
  // (summed relit error 2.59), less than the studio (0.40); measured 1.02.
  EXPECT_GT(sum_sun, sum_easy);
  EXPECT_LT(sum_sun, 0.6 * 2.59);
}

}  // namespace brdfshot
