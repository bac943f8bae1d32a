// brdfshot basis: the basis images of one scene, cached for every later fit.
#include <cmath>
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/basis_images.h"
#include "fit/quality_search.h"
#include "normals/observation.h"
#include "fit/transport.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

int BasisMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  std::string probe_path, obs_path, out = "basis.bsbi";
  int sphere = 64;
  double margin = 80, error_target = 0;
  int error_pixels = QualitySearchOptions{}.pixels;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path)->required(), "lat-long light probe (.exr/.hdr/.pfm)")
      ("out,o", po::value(&out)->default_value(out), "basis-image cache")
      ("obs", po::value(&obs_path), "observation file (from 'brdfshot remap'): its pixels' geometry")
      ("sphere", po::value(&sphere)->default_value(sphere), "without --obs: orthographic sphere diameter in pixels")
      ("margin", po::value(&margin)->default_value(margin), "max angle between normal and view (deg)")
      ("error-target", po::value(&error_target)->default_value(0),
       "choose the sample counts and probe width by measuring: the cheapest setting whose worst basis image "
       "of the test materials is within this relative RMSE of the converged reference on this scene (e.g. 0.01; "
       "0: use the quality options as given)")
      ("error-pixels", po::value(&error_pixels)->default_value(error_pixels), "with --error-target: about this many pixels carry the error");
  // clang-format on
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("basis", "--probe P [options]", desc, argc, argv)) return 0;
  if (!(error_target >= 0 && std::isfinite(error_target)))
    throw Error("--error-target must be a relative RMSE such as 0.01, or 0 to use the quality options as given");
  if (error_pixels <= 0) throw Error("--error-pixels must be positive");
  Stopwatch sw;
  const LatLongProbe probe = LatLongProbe::Read(probe_path);
  const BasisDatabase base = LoadDatabase(db.ToOptions(true));
  const double t_db = sw.Seconds();
  BasisImages b;
  b.geometry = obs_path.empty() ? OrthographicSphere(sphere, margin) : Observations::Read(obs_path).geometry;
  nlohmann::json search;
  double t_search = 0;
  if (error_target != 0) {
    QualitySearchOptions so;
    so.target = error_target;
    so.pixels = error_pixels;
    Progress progress("error reference", ErrorTestMaterials(base).size(), true);
    const QualityChoice c = ChooseQuality(b.geometry, probe, base, quality.q, so, &progress);
    search = {
        {"target", error_target}, {"reached", c.reached}, {"pixels", c.pixels}, {"trials", nlohmann::json::array()}};
    std::printf("error target %.4g on %zu pixels (reference %.1f s):\n", error_target, c.pixels, c.reference_seconds);
    for (const QualityTrial& tr : c.trials) {
      std::printf("  %2dx%-3d probe %-5s worst %.4f  (", tr.quality.theta_samples, tr.quality.phi_samples,
                  tr.quality.probe_width > 0 ? std::to_string(tr.quality.probe_width).c_str() : "full", tr.worst);
      for (const auto& [label, e] : tr.label_error) std::printf(" %s %.4f", label.c_str(), e);
      std::printf(" )\n");
      search["trials"].push_back(
          {{"quality", tr.quality.Describe()}, {"worst", tr.worst}, {"by_class", tr.label_error}});
    }
    if (!c.reached)
      std::fprintf(stderr, "warning: no setting reached %.4g on this scene; using the best, %s (worst %.4f)\n",
                   error_target, c.quality.Describe().c_str(), c.error);
    quality.q = c.quality;
    t_search = sw.Seconds() - t_db;
  }
  const TransportOperator t = TransportOperator::Build(b.geometry, probe, base.grid, quality.q);
  const double t_build = sw.Seconds() - t_db - t_search;
  b.Y = t.Apply(base.B);
  const double t_apply = sw.Seconds() - t_db - t_search - t_build;
  std::vector<std::string> names;
  for (int i = 0; i < base.num_bases(); ++i) names.push_back(base.BasisName(i));
  b.header = {{"format", "brdfshot-basis-images-1"},
              {"probe", probe_path},
              {"probe_name", probe.name()},
              {"probe_hash", probe.Hash()},
              {"geometry", obs_path.empty() ? "orthographic-sphere" : obs_path},
              {"sphere", sphere},
              {"margin_deg", margin},
              {"geometry_hash", b.geometry.Hash()},
              {"quality", quality.q.Describe()},
              {"database", base.label},
              {"database_kind", base.kind},
              {"grid", {base.grid.n_th, base.grid.n_td, base.grid.n_pd}},
              {"bases", names}};
  if (!search.is_null()) b.header["quality_search"] = search;
  b.Write(out);
  std::printf(
      "basis images: %zu pixels x %d bases under %s (%s), %d theta_o levels\n"
      "time: database %.2f s, quality search %.2f s, operator %.2f s, apply %.2f s\nwrote %s\n",
      b.geometry.size(), base.num_bases(), probe.name().c_str(), base.label.c_str(), t.levels(), t_db, t_search,
      t_build, t_apply, out.c_str());
  return 0;
}

}  // namespace brdfshot
