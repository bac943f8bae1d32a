#include "fit/scene_basis.h"

#include <cstdio>
#include <filesystem>

#include "normals/observation.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/fnv_hash.h"
#include "util/progress.h"

namespace brdfshot {

namespace {

// What decides the images: the header of BasisImagesHeader with the quality
// as asked for (the settings, or the error target the search starts from).
nlohmann::json SceneKey(const SceneBasisOptions& o, const LatLongProbe& probe, const PixelGeometry& geometry,
                        const BasisDatabase& db, const std::vector<std::string>& names) {
  std::string quality = o.quality.Describe();
  if (o.error_target != 0)
    quality += " searched to error target " + std::to_string(o.error_target) + " on " +
               std::to_string(o.error_pixels) + " pixels";
  nlohmann::json key = BasisImagesHeader(probe, geometry, quality, db, names);
  // A sample of the tables themselves (every 997th bin), so that a database
  // whose tables change under the same names does not reuse images rendered
  // from the old ones.
  uint64_t h = kFnv1aOffset;
  for (Eigen::Index r = 0; r < db.B.rows(); r += 997)
    for (Eigen::Index c = 0; c < db.B.cols(); ++c) {
      const float v = db.B(r, c);
      h = Fnv1a(&v, sizeof v, h);
    }
  key["tables_sample_hash"] = h;
  key["lobes"] = o.lobes ? LambertGgxLobes{}.ToJson() : nlohmann::json();
  return key;
}

std::string SharedFileName(const std::string& dir, const nlohmann::json& key) {
  const std::string text = key.dump();
  const uint64_t h = Fnv1a(text.data(), text.size());
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.bsbi", static_cast<unsigned long long>(h));
  return (std::filesystem::path(dir) / name).string();
}

// The shared images of this scene, when a readable file there carries exactly
// this key (a hash collision, a damaged or a foreign file is not trusted).
bool ReadShared(const std::string& path, const nlohmann::json& key, BasisImages* images) {
  if (!std::filesystem::exists(path)) return false;
  try {
    BasisImages b = BasisImages::Read(path);
    if (!b.header.contains("scene_key") || b.header.at("scene_key") != key) return false;
    *images = std::move(b);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

SceneBasis ComputeSceneBasis(const SceneBasisOptions& o, const std::string& out) {
  SceneBasis r;
  Stopwatch sw;
  const LatLongProbe probe = LatLongProbe::Read(o.probe);
  const BasisDatabase db = LoadDatabase(o.database);
  r.seconds_database = sw.Seconds();
  BasisImages& b = r.images;
  b.geometry =
      o.observations.empty() ? OrthographicSphere(o.sphere, o.margin_deg) : Observations::Read(o.observations).geometry;
  std::vector<std::string> names;
  for (int i = 0; i < db.num_bases(); ++i) names.push_back(db.BasisName(i));
  r.bases = db.num_bases();
  r.probe_name = probe.name();
  r.database_label = db.label;
  const nlohmann::json key = SceneKey(o, probe, b.geometry, db, names);
  if (!o.shared_dir.empty()) r.shared_file = SharedFileName(o.shared_dir, key);
  auto name_this_scene = [&] {
    b.header["probe"] = o.probe;
    b.header["geometry"] = o.observations.empty() ? "orthographic-sphere" : o.observations;
    b.header["sphere"] = o.sphere;
    b.header["margin_deg"] = o.margin_deg;
  };
  if (!r.shared_file.empty() && ReadShared(r.shared_file, key, &b)) {
    r.reused = true;
    name_this_scene();
    if (!out.empty()) b.Write(out);
    return r;
  }

  RenderQuality quality = o.quality;
  if (o.error_target != 0) {
    QualitySearchOptions so;
    so.target = o.error_target;
    so.pixels = o.error_pixels;
    Progress progress("error reference", ErrorTestMaterials(db).size(), o.progress);
    r.search = ChooseQuality(b.geometry, probe, db, quality, so, &progress);
    quality = r.search->quality;
    r.seconds_search = sw.Seconds() - r.seconds_database;
  }
  const TransportOperator t = TransportOperator::Build(b.geometry, probe, db.grid, quality);
  r.seconds_operator = sw.Seconds() - r.seconds_database - r.seconds_search;
  const LambertGgxLobes lobes;
  if (o.lobes) {
    // One pass for both: the lighting per sample is the same for every table.
    const MatrixXfR lobe_tables = lobes.Tables(db.grid);
    auto images = TransportOperator::ApplyAll({&t}, {MapOf(db.B), MapOf(lobe_tables)}).front();
    b.Y = std::move(images[0]);
    b.lobes = std::move(images[1]);
  } else {
    b.Y = t.Apply(db.B);
  }
  r.seconds_apply = sw.Seconds() - r.seconds_database - r.seconds_search - r.seconds_operator;
  b.header = BasisImagesHeader(probe, b.geometry, quality.Describe(), db, names);
  if (o.lobes) b.header["lobes"] = lobes.ToJson();
  name_this_scene();
  if (r.search) {
    nlohmann::json s = {{"target", o.error_target},
                        {"reached", r.search->reached},
                        {"pixels", r.search->pixels},
                        {"trials", nlohmann::json::array()}};
    for (const QualityTrial& tr : r.search->trials)
      s["trials"].push_back({{"quality", tr.quality.Describe()}, {"worst", tr.worst}, {"by_class", tr.label_error}});
    b.header["quality_search"] = s;
  }
  r.levels = t.levels();
  if (!r.shared_file.empty()) b.header["scene_key"] = key;
  if (!out.empty()) b.Write(out);
  if (!r.shared_file.empty()) {
    std::filesystem::create_directories(o.shared_dir);
    // Atomic either way: captures rendering the same scene at once each put a
    // whole file there. Linked from this call's own output, never the other
    // way round, so that a capture's output names its own probe and pixels.
    if (out.empty() || !LinkFileAtomic(out, r.shared_file)) b.Write(r.shared_file);
  }
  return r;
}

}  // namespace brdfshot
