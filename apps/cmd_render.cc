// brdfshot render: BRDFs on a sphere under a probe, to EXR + tone-mapped PNG.
#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <set>

#include "apps/brdf_source.h"
#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/transport.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {
// The same file by any spelling of its path.
std::string SamePathKey(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
  return ec ? path : p.string();
}
}  // namespace

int RenderMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  BrdfSourceArgs src;
  std::string probe_path;
  std::vector<std::string> outs;
  int sphere = 256, pad = 0;
  double exposure = 0;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path)->required(), "lat-long light probe")
      ("out,o", po::value(&outs)->composing(), "EXR output (a tone-mapped .png is written beside it), one per BRDF in the order the BRDFs are given (default: render.exr for one)")
      ("sphere", po::value(&sphere)->default_value(sphere), "sphere diameter in pixels")
      ("exposure", po::value(&exposure)->default_value(0), "PNG exposure scale (0: automatic, per image)")
      ("pad", po::value(&pad)->default_value(0), "black border in pixels around the sphere (a photo to detect it in)");
  // clang-format on
  src.Add(desc, /*several=*/true);
  db.Add(desc);
  quality.Add(desc);
  std::vector<std::string> given;
  if (!ParseOptions("render",
                    "--probe P (--merl F | --standin N | --nbrdf N | --weights fit.json) [-o OUT.exr] [more BRDFs, "
                    "each with its -o] [options]",
                    desc, argc, argv, nullptr, &given))
    return 0;
  const std::vector<BrdfSource> sources = src.Given(given);
  if (sources.empty()) throw Error("give a BRDF: --merl, --standin, --nbrdf or --weights");
  if (outs.empty() && sources.size() == 1) outs.push_back("render.exr");
  if (outs.size() != sources.size())
    throw Error("give one -o per BRDF: " + std::to_string(sources.size()) + " BRDFs, " +
                std::to_string(outs.size()) + " outputs");
  std::set<std::string> inputs, written;
  for (const BrdfSource& s : sources)
    if (s.option == "merl" || s.option == "weights") inputs.insert(SamePathKey(s.value));
  inputs.insert(SamePathKey(probe_path));
  for (const std::string& out : outs) {
    const std::string png = std::filesystem::path(out).replace_extension(".png").string();
    for (const std::string& file : {out, png}) {
      if (inputs.count(SamePathKey(file))) throw FileError(file, "is an input of this render: not overwritten");
      if (!written.insert(SamePathKey(file)).second) throw FileError(file, "is written twice by this render");
    }
  }
  Stopwatch sw;
  std::vector<MerlBrdf> brdfs;
  std::vector<std::string> labels(sources.size());
  brdfs.reserve(sources.size());
  for (size_t i = 0; i < sources.size(); ++i) brdfs.push_back(BrdfSourceArgs::Load(sources[i], db, &labels[i]));
  const LatLongProbe probe = LatLongProbe::Read(probe_path);
  const PixelGeometry g = OrthographicSphere(sphere, 89.5);
  // One operator per grid the BRDFs come on, each rendering its BRDFs in one
  // pass.
  std::map<std::array<int, 3>, std::vector<size_t>> by_grid;
  for (size_t i = 0; i < brdfs.size(); ++i) {
    const MerlGrid& grid = brdfs[i].grid();
    by_grid[{grid.n_th, grid.n_td, grid.n_pd}].push_back(i);
  }
  std::vector<Eigen::MatrixXd> images(brdfs.size());
  for (const auto& [grid, members] : by_grid) {
    std::vector<const MerlBrdf*> these;
    for (size_t i : members) these.push_back(&brdfs[i]);
    const std::vector<Eigen::MatrixXd> y =
        TransportOperator::Build(g, probe, brdfs[members[0]].grid(), quality.q).RenderAll(these);
    for (size_t k = 0; k < members.size(); ++k) images[members[k]] = y[k];
  }
  for (size_t i = 0; i < brdfs.size(); ++i) {
    cv::Mat img = PixelsToImage(g, images[i]);
    if (pad > 0) cv::copyMakeBorder(img, img, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar::all(0));
    WriteExr(outs[i], img);
    const std::string png = std::filesystem::path(outs[i]).replace_extension(".png").string();
    WritePngTonemapped(png, img, exposure > 0 ? exposure : AutoExposure(img));
    std::printf("rendered %s under %s\nwrote %s and %s\n", labels[i].c_str(), probe.name().c_str(), outs[i].c_str(),
                png.c_str());
  }
  std::printf("%zu BRDF%s, %dx%d, %s, in %.2f s\n", brdfs.size(), brdfs.size() == 1 ? "" : "s", sphere, sphere,
              quality.q.Describe().c_str(), sw.Seconds());
  return 0;
}

}  // namespace brdfshot
