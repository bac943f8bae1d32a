// brdfshot compare: relative RMSE between two linear images over their non-black
// pixels — the error the demo reports against the truth.
#include <cmath>
#include <cstdio>

#include "apps/command.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

int CompareMain(int argc, char** argv) {
  std::string a, b;
  po::options_description desc("options");
  desc.add_options()("reference", po::value(&a)->required(), "reference image (EXR)")
      ("test", po::value(&b)->required(), "image to score (EXR)");
  po::positional_options_description pos;
  pos.add("reference", 1).add("test", 1);
  if (!ParseOptions("compare", "REFERENCE.exr TEST.exr", desc, argc, argv, &pos)) return 0;
  const cv::Mat ra = ReadHdrImage(a), rb = ReadHdrImage(b);
  if (ra.size() != rb.size()) throw FileError(b, "size differs from " + a);
  double num = 0, den = 0;
  size_t n = 0;
  for (int y = 0; y < ra.rows; ++y)
    for (int x = 0; x < ra.cols; ++x) {
      const cv::Vec3f p = ra.at<cv::Vec3f>(y, x), q = rb.at<cv::Vec3f>(y, x);
      if (p[0] + p[1] + p[2] <= 0) continue;  // background
      for (int c = 0; c < 3; ++c) num += (p[c] - q[c]) * (p[c] - q[c]), den += p[c] * p[c];
      ++n;
    }
  if (n == 0 || den <= 0) throw FileError(a, "has no lit pixels to compare");
  std::printf("relative RMSE %.4f over %zu pixels (%s vs %s)\n", std::sqrt(num / den), n, b.c_str(), a.c_str());
  return 0;
}

}  // namespace brdfshot
