#include "fit/scene_basis.h"

#include "normals/observation.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

SceneBasis ComputeSceneBasis(const SceneBasisOptions& o) {
  SceneBasis r;
  Stopwatch sw;
  const LatLongProbe probe = LatLongProbe::Read(o.probe);
  const BasisDatabase db = LoadDatabase(o.database);
  r.seconds_database = sw.Seconds();
  BasisImages& b = r.images;
  b.geometry =
      o.observations.empty() ? OrthographicSphere(o.sphere, o.margin_deg) : Observations::Read(o.observations).geometry;
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
  b.Y = t.Apply(db.B);
  r.seconds_apply = sw.Seconds() - r.seconds_database - r.seconds_search - r.seconds_operator;
  std::vector<std::string> names;
  for (int i = 0; i < db.num_bases(); ++i) names.push_back(db.BasisName(i));
  b.header = BasisImagesHeader(probe, b.geometry, quality.Describe(), db, names);
  b.header["probe"] = o.probe;
  b.header["geometry"] = o.observations.empty() ? "orthographic-sphere" : o.observations;
  b.header["sphere"] = o.sphere;
  b.header["margin_deg"] = o.margin_deg;
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
  r.bases = db.num_bases();
  r.probe_name = probe.name();
  r.database_label = db.label;
  return r;
}

}  // namespace brdfshot
