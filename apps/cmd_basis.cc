// brdfshot basis: the basis images of one scene, cached for every later fit
// (fit/scene_basis.h).
#include <cmath>
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/scene_basis.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

void PrintQualitySearch(const QualityChoice& c, double target) {
  std::printf("error target %.4g on %zu pixels (reference %.1f s):\n", target, c.pixels, c.reference_seconds);
  for (const QualityTrial& tr : c.trials) {
    std::printf("  %2dx%-3d probe %-5s worst %.4f  (", tr.quality.theta_samples, tr.quality.phi_samples,
                tr.quality.probe_width > 0 ? std::to_string(tr.quality.probe_width).c_str() : "full", tr.worst);
    for (const auto& [label, e] : tr.label_error) std::printf(" %s %.4f", label.c_str(), e);
    std::printf(" )\n");
  }
  if (!c.reached)
    std::fprintf(stderr, "warning: no setting reached %.4g on this scene; using the best, %s (worst %.4f)\n", target,
                 c.quality.Describe().c_str(), c.error);
}

}  // namespace

int BasisMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  SceneBasisOptions o;
  std::string out = "basis.bsbi";
  po::options_description desc("options");
  // clang-format off
  bool no_lobes = false;
  desc.add_options()
      ("probe,p", po::value(&o.probe)->required(), "lat-long light probe (.exr/.hdr/.pfm)")
      ("out,o", po::value(&out)->default_value(out), "basis-image cache")
      ("obs", po::value(&o.observations), "observation file (from 'brdfshot remap'): its pixels' geometry")
      ("sphere", po::value(&o.sphere)->default_value(o.sphere), "without --obs: orthographic sphere diameter in pixels")
      ("margin", po::value(&o.margin_deg)->default_value(o.margin_deg), "max angle between normal and view (deg)")
      ("error-target", po::value(&o.error_target)->default_value(0),
       "choose the sample counts and probe width by measuring: the cheapest setting whose worst basis image "
       "of the test materials is within this relative RMSE of the converged reference on this scene (e.g. 0.01; "
       "0: use the quality options as given)")
      ("error-pixels", po::value(&o.error_pixels)->default_value(o.error_pixels), "with --error-target: about this many pixels carry the error")
      ("shared", po::value(&o.shared_dir), "folder of basis images shared by captures: images of an identical scene "
       "(probe, pixel geometry, quality, database) are taken from it, new ones stored in it")
      ("no-lobes", po::bool_switch(&no_lobes), "leave out the Lambert + GGX baseline's lobe images (49 of 349 columns, a third of the stage's time on the default capture); "
       "'fit' then writes no baseline");
  // clang-format on
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("basis", "--probe P [options]", desc, argc, argv)) return 0;
  if (!(o.error_target >= 0 && std::isfinite(o.error_target)))
    throw Error("--error-target must be a relative RMSE such as 0.01, or 0 to use the quality options as given");
  if (o.error_pixels <= 0) throw Error("--error-pixels must be positive");
  o.quality = quality.q;
  o.lobes = !no_lobes;
  o.database = db.ToOptions(true);
  o.progress = true;
  const SceneBasis r = ComputeSceneBasis(o, out);
  if (r.search) PrintQualitySearch(*r.search, o.error_target);
  if (r.reused) {
    std::printf("basis images: %zu pixels x %d bases under %s (%s), taken from %s\nwrote %s\n",
                r.images.geometry.size(), r.bases, r.probe_name.c_str(), r.database_label.c_str(),
                r.shared_file.c_str(), out.c_str());
    return 0;
  }
  std::printf(
      "basis images: %zu pixels x %d bases under %s (%s), %d theta_o levels\n"
      "time: database %.2f s, quality search %.2f s, operator %.2f s, apply %.2f s\nwrote %s\n",
      r.images.geometry.size(), r.bases, r.probe_name.c_str(), r.database_label.c_str(), r.levels, r.seconds_database,
      r.seconds_search, r.seconds_operator, r.seconds_apply, out.c_str());
  return 0;
}

}  // namespace brdfshot
