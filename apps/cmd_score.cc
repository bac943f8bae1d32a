// brdfshot score: a fit's relit error on a photo it was not fitted to — the
// same object under another light, its basis images rendered on that photo's
// pixels (fit/photo_score.h). Several fits are scored against one photo in
// one call: the photo's basis images, most of the work, are read once.
#include <cstdio>
#include <limits>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/photo_score.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

int ScoreMain(int argc, char** argv) {
  std::string fit_list, basis_path, photo_path, obs_path;
  bool tsv = false;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()("fit", po::value(&fit_list)->required(),
       "fit.json from 'brdfshot fit' (comma-separated: several fits, each scored on the photo)")
      ("basis,b", po::value(&basis_path)->required(),
       "basis images of the held-out photo's scene (its probe, its pixels) from 'brdfshot basis', same database")
      ("obs", po::value(&obs_path), "the held-out photo's observation file (from 'brdfshot remap')")
      ("photo", po::value(&photo_path), "or the held-out photo itself: linear HDR aligned with the basis images' pixels")
      ("tsv", po::bool_switch(&tsv), "print one tab-separated line per fit: fit, basis, pixels, relative RMSE, at "
       "the best scale, and the same of the Lambert + GGX baseline (nan where there is none)");
  // clang-format on
  if (!ParseOptions("score", "--fit fit.json[,…] --basis Y.bsbi (--obs obs.bsobs | --photo photo.exr) [options]", desc,
                    argc, argv))
    return 0;
  if (obs_path.empty() == photo_path.empty()) throw Error("score: give one of --obs and --photo");
  const std::vector<std::string> fits = SplitList(fit_list);
  if (fits.empty()) throw Error("score: --fit names no fit");
  const BasisImages basis = BasisImages::Read(basis_path);
  const Eigen::MatrixXd y = ReadFitPixels(basis, basis_path, photo_path, obs_path);
  const std::string photo = obs_path.empty() ? photo_path : obs_path;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::string& fit_path : fits) {
    const PhotoScore s = ScoreFitOnPhoto(FitRecord::Read(fit_path), fit_path, basis, basis_path, y, photo);
    if (tsv) {
      std::printf("%s\t%s\t%zu\t%.6g\t%.6g\t%.6g\t%.6g\n", fit_path.c_str(), basis_path.c_str(), s.pixels,
                  s.fit.relative_rmse, s.fit.relative_rmse_scaled, s.lambert_ggx ? s.lambert_ggx->relative_rmse : nan,
                  s.lambert_ggx ? s.lambert_ggx->relative_rmse_scaled : nan);
      continue;
    }
    if (fits.size() > 1) std::printf("%s:\n", fit_path.c_str());
    std::printf("held-out photo, %zu pixels: relative RMSE %.4f (%.4f after scaling by %.4g)\n", s.pixels,
                s.fit.relative_rmse, s.fit.relative_rmse_scaled, s.fit.scale);
    if (s.lambert_ggx)
      std::printf("Lambert + GGX baseline: relative RMSE %.4f (%.4f after scaling by %.4g)\n",
                  s.lambert_ggx->relative_rmse, s.lambert_ggx->relative_rmse_scaled, s.lambert_ggx->scale);
  }
  return 0;
}

}  // namespace brdfshot
