// brdfshot render: one BRDF on a sphere under a probe, to EXR + tone-mapped PNG.
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>

#include "apps/brdf_source.h"
#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/transport.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

int RenderMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  BrdfSourceArgs src;
  std::string probe_path, out = "render.exr";
  int sphere = 256, pad = 0;
  double exposure = 0;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path)->required(), "lat-long light probe")
      ("out,o", po::value(&out)->default_value(out), "EXR output (a tone-mapped .png is written beside it)")
      ("sphere", po::value(&sphere)->default_value(sphere), "sphere diameter in pixels")
      ("exposure", po::value(&exposure)->default_value(0), "PNG exposure scale (0: automatic)")
      ("pad", po::value(&pad)->default_value(0), "black border in pixels around the sphere (a photo to detect it in)");
  // clang-format on
  src.Add(desc);
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("render", "--probe P (--merl F | --standin N | --nbrdf N | --weights fit.json) [options]", desc,
                    argc, argv))
    return 0;
  Stopwatch sw;
  std::string label;
  const MerlBrdf brdf = src.Load(db, &label);
  const LatLongProbe probe = LatLongProbe::Read(probe_path);
  const PixelGeometry g = OrthographicSphere(sphere, 89.5);
  cv::Mat img = PixelsToImage(g, TransportOperator::Build(g, probe, brdf.grid(), quality.q).Render(brdf));
  if (pad > 0) cv::copyMakeBorder(img, img, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  WriteExr(out, img);
  const std::string png = std::filesystem::path(out).replace_extension(".png").string();
  WritePngTonemapped(png, img, exposure > 0 ? exposure : AutoExposure(img));
  std::printf("rendered %s under %s (%dx%d, %s) in %.2f s\nwrote %s and %s\n", label.c_str(), probe.name().c_str(),
              sphere, sphere, quality.q.Describe().c_str(), sw.Seconds(), out.c_str(), png.c_str());
  return 0;
}

}  // namespace brdfshot
