#include "fit/quality_search.h"

#include <algorithm>
#include <cmath>

#include "fit/basis_reference.h"
#include "util/check.h"

namespace brdfshot {

std::vector<ErrorTestMaterial> ErrorTestMaterials(const BasisDatabase& db) {
  std::vector<ErrorTestMaterial> out;
  for (int m : ReferenceMaterialIndices(db)) out.push_back({m, ReferenceClassOf(db.materials[m])});
  if (!out.empty()) return out;
  if (db.families.size() == db.materials.size()) {
    for (int m = 0; m < db.num_materials(); ++m) {
      const bool seen = std::any_of(out.begin(), out.end(), [&](const auto& t) { return t.label == db.families[m]; });
      if (!seen) out.push_back({m, db.families[m]});
    }
    if (!out.empty()) return out;
  }
  const int n = db.num_materials(), k = std::min(n, 8);
  for (int i = 0; i < k; ++i) {
    const int m = static_cast<int>((2 * i + 1) * int64_t{n} / (2 * k));
    out.push_back({m, db.materials[m]});
  }
  return out;
}

std::vector<RenderQuality> QualityLadder(const RenderQuality& base, int probe_width) {
  std::vector<RenderQuality> ladder;
  const auto add = [&](int theta, int phi, int width) {
    RenderQuality q = base;
    q.theta_samples = theta;
    q.phi_samples = phi;
    q.probe_width = width;
    ladder.push_back(q);
  };
  // 16 × 32 and 24 × 40 are within a few per cent; 32 × 48 is the default;
  // 32 × 64 and 48 × 96 cost 1.1× and 2.5× it at 256² (bench-basis).
  for (const auto& [t, p] : {std::pair{16, 32}, {24, 40}, {32, 48}, {32, 64}}) add(t, p, base.probe_width);
  const bool resampled = base.probe_width > 0 && base.probe_width < probe_width;
  if (resampled)
    for (const auto& [t, p] : {std::pair{32, 48}, {32, 64}}) add(t, p, 0);
  add(48, 96, resampled ? 0 : base.probe_width);
  return ladder;
}

namespace {

// About `pixels` pixels of `g`, spread over the whole image on a regular grid
// (so every part of the sphere, grazing rim included, is represented).
PixelGeometry SpreadSubset(const PixelGeometry& g, int pixels) {
  const int step = std::max(1, static_cast<int>(std::lround(std::sqrt(double(g.size()) / std::max(1, pixels)))));
  PixelGeometry s = Subsample(g, step);
  // A sparse mask can miss the grid entirely: fall back to every step²-th pixel.
  if (s.size() < std::min<size_t>(g.size(), 16)) {
    s = PixelGeometry{};
    s.width = g.width;
    s.height = g.height;
    for (size_t i = 0; i < g.size(); i += static_cast<size_t>(step) * step) {
      s.x.push_back(g.x[i]);
      s.y.push_back(g.y[i]);
      s.normal.push_back(g.normal[i]);
      s.view.push_back(g.view[i]);
    }
  }
  return s;
}

}  // namespace

QualityChoice ChooseQuality(const PixelGeometry& geometry, const LatLongProbe& probe, const BasisDatabase& db,
                            const RenderQuality& base, const QualitySearchOptions& options, Progress* progress) {
  if (!(options.target > 0 && std::isfinite(options.target)))
    throw Error("error target must be a positive fraction (e.g. 0.01 for 1 %)");
  if (geometry.size() == 0) throw Error("no pixels to measure the basis images' error on");
  BRDFSHOT_CHECK(options.pixels > 0 && options.reference_theta > 0 && options.reference_phi > 0);
  const std::vector<ErrorTestMaterial> tests = ErrorTestMaterials(db);
  BRDFSHOT_CHECK(!tests.empty());
  std::vector<int> mats;
  std::vector<std::string> labels;
  for (const auto& t : tests) mats.push_back(t.index), labels.push_back(t.label);

  QualityChoice choice;
  const PixelGeometry sub = SpreadSubset(geometry, options.pixels);
  choice.pixels = sub.size();
  Stopwatch sw;
  const BasisImages ref =
      RenderReferenceImages(sub, probe, db, mats, options.reference_theta, options.reference_phi, progress);
  choice.reference_seconds = sw.Seconds();

  const MatrixXfR B = MaterialColumns(db, mats);
  for (const RenderQuality& q : QualityLadder(base, probe.width())) {
    QualityTrial trial{q, WorstErrorPerLabel(TransportOperator::Build(sub, probe, db.grid, q).Apply(B), ref.Y, labels),
                       0};
    for (const auto& [label, e] : trial.label_error) trial.worst = std::max(trial.worst, e);
    choice.trials.push_back(trial);
    // Every earlier trial missed the target, so one that meets it is also the best so far.
    if (choice.trials.size() == 1 || trial.worst < choice.error) choice.quality = q, choice.error = trial.worst;
    choice.reached = trial.worst <= options.target;
    if (choice.reached) break;
  }
  return choice;
}

}  // namespace brdfshot
