// brdfshot compare: relative RMSE between two linear images over their non-black
// pixels — the error the demo reports against the truth.
#include <cstdio>

#include "apps/command.h"
#include "util/check.h"
#include "util/image_error.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

int CompareMain(int argc, char** argv) {
  std::string a, b;
  bool up_to_scale = false;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()("reference", po::value(&a)->required(), "reference image (EXR)")
      ("test", po::value(&b)->required(), "image to score (EXR)")
      ("up-to-scale", po::bool_switch(&up_to_scale), "score TEST after the scale that fits it best (least squares): "
       "an HDR merge is known only up to one");
  // clang-format on
  po::positional_options_description pos;
  pos.add("reference", 1).add("test", 1);
  if (!ParseOptions("compare", "REFERENCE.exr TEST.exr", desc, argc, argv, &pos)) return 0;
  const cv::Mat ra = ReadHdrImage(a), rb = ReadHdrImage(b);
  if (ra.size() != rb.size()) throw FileError(b, "size differs from " + a);
  const ImageError e = CompareLinearImages(ra, rb, up_to_scale);
  if (e.pixels == 0) throw FileError(a, "has no lit pixels to compare");
  if (up_to_scale)
    std::printf("relative RMSE %.4f over %zu pixels after scaling by %.6g (%s vs %s)\n", e.relative_rmse, e.pixels,
                e.scale, b.c_str(), a.c_str());
  else
    std::printf("relative RMSE %.4f over %zu pixels (%s vs %s)\n", e.relative_rmse, e.pixels, b.c_str(), a.c_str());
  return 0;
}

}  // namespace brdfshot
