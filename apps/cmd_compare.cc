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
  bool up_to_scale = false;
  po::options_description desc("options");
  desc.add_options()("reference", po::value(&a)->required(), "reference image (EXR)")
      ("test", po::value(&b)->required(), "image to score (EXR)")
      ("up-to-scale", po::bool_switch(&up_to_scale), "score TEST after the scale that fits it best (least squares): "
       "an HDR merge is known only up to one");
  po::positional_options_description pos;
  pos.add("reference", 1).add("test", 1);
  if (!ParseOptions("compare", "REFERENCE.exr TEST.exr", desc, argc, argv, &pos)) return 0;
  const cv::Mat ra = ReadHdrImage(a), rb = ReadHdrImage(b);
  if (ra.size() != rb.size()) throw FileError(b, "size differs from " + a);
  // Σ p², Σ pq, Σ q² in double: the scale s = Σpq / Σq² and the error
  // Σ (p − s q)² = Σp² − 2 s Σpq + s² Σq² follow from them.
  double pp = 0, pq = 0, qq = 0;
  size_t n = 0;
  for (int y = 0; y < ra.rows; ++y)
    for (int x = 0; x < ra.cols; ++x) {
      const cv::Vec3f p = ra.at<cv::Vec3f>(y, x), q = rb.at<cv::Vec3f>(y, x);
      if (p[0] + p[1] + p[2] <= 0) continue;  // background
      for (int c = 0; c < 3; ++c) pp += double(p[c]) * p[c], pq += double(p[c]) * q[c], qq += double(q[c]) * q[c];
      ++n;
    }
  if (n == 0 || pp <= 0) throw FileError(a, "has no lit pixels to compare");
  const double s = up_to_scale ? (qq > 0 ? pq / qq : 0) : 1.0;
  const double err = std::sqrt(std::max(0.0, pp - 2 * s * pq + s * s * qq) / pp);
  if (up_to_scale)
    std::printf("relative RMSE %.4f over %zu pixels after scaling by %.6g (%s vs %s)\n", err, n, s, b.c_str(), a.c_str());
  else
    std::printf("relative RMSE %.4f over %zu pixels (%s vs %s)\n", err, n, b.c_str(), a.c_str());
  return 0;
}

}  // namespace brdfshot
