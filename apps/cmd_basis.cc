// brdfshot basis: the basis images of one scene, cached for every later fit.
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/basis_images.h"
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
  double margin = 80;
  po::options_description desc("options");
  desc.add_options()
      ("probe,p", po::value(&probe_path)->required(), "lat-long light probe (.exr/.hdr/.pfm)")
      ("out,o", po::value(&out)->default_value(out), "basis-image cache")
      ("obs", po::value(&obs_path), "observation file (from 'brdfshot remap'): its pixels' geometry")
      ("sphere", po::value(&sphere)->default_value(sphere), "without --obs: orthographic sphere diameter in pixels")
      ("margin", po::value(&margin)->default_value(margin), "max angle between normal and view (deg)");
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("basis", "--probe P [options]", desc, argc, argv)) return 0;
  Stopwatch sw;
  const LatLongProbe probe = LatLongProbe::Read(probe_path);
  const BasisDatabase base = LoadDatabase(db.ToOptions(true));
  const double t_db = sw.Seconds();
  BasisImages b;
  b.geometry = obs_path.empty() ? OrthographicSphere(sphere, margin) : Observations::Read(obs_path).geometry;
  const TransportOperator t = TransportOperator::Build(b.geometry, probe, base.grid, quality.q);
  const double t_build = sw.Seconds() - t_db;
  b.Y = t.Apply(base.B);
  const double t_apply = sw.Seconds() - t_db - t_build;
  std::vector<std::string> names;
  for (int i = 0; i < base.num_bases(); ++i) names.push_back(base.BasisName(i));
  b.header = {{"format", "brdfshot-basis-images-1"}, {"probe", probe_path}, {"probe_name", probe.name()},
              {"probe_hash", probe.Hash()}, {"geometry", obs_path.empty() ? "orthographic-sphere" : obs_path},
              {"sphere", sphere}, {"margin_deg", margin}, {"geometry_hash", b.geometry.Hash()}, {"quality", quality.q.Describe()},
              {"database", base.label}, {"database_kind", base.kind},
              {"grid", {base.grid.n_th, base.grid.n_td, base.grid.n_pd}}, {"bases", names}};
  b.Write(out);
  std::printf("basis images: %zu pixels x %d bases under %s (%s), %d theta_o levels\n"
              "time: database %.2f s, operator %.2f s, apply %.2f s\nwrote %s\n",
              b.geometry.size(), base.num_bases(), probe.name().c_str(), base.label.c_str(), t.levels(),
              t_db, t_build, t_apply, out.c_str());
  return 0;
}

}  // namespace brdfshot
