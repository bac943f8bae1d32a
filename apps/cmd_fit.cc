// brdfshot fit: the class-wise solve for one photo (paper sec. 4).
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "fit/basis_images.h"
#include "fit/class_model.h"
#include "fit/solver.h"
#include "fit/transport.h"
#include "normals/observation.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

int FitMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  std::string basis_path, photo_path, obs_path, classes_path, out = "fit_out", previews;
  double lambda = 0.5;
  po::options_description desc("options");
  desc.add_options()
      ("basis,b", po::value(&basis_path)->required(), "basis-image cache from 'brdfshot basis'")
      ("photo", po::value(&photo_path), "linear HDR photo (EXR) aligned with the basis images' pixels")
      ("obs", po::value(&obs_path), "observation file (from 'brdfshot remap') instead of --photo")
      ("classes,c", po::value(&classes_path)->required(), "class model from 'brdfshot cluster'")
      ("lambda", po::value(&lambda)->default_value(lambda), "regularisation weight (paper: 0.5)")
      ("out,o", po::value(&out)->default_value(out), "output folder")
      ("preview-probes", po::value(&previews), "probes to relight the result under (default: two of <data>/envmaps)");
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("fit", "--basis Y.bsbi (--photo photo.exr | --obs obs.bsobs) --classes classes.json [options]",
                    desc, argc, argv))
    return 0;
  if (photo_path.empty() == obs_path.empty()) throw Error("fit: give exactly one of --photo and --obs");

  const BasisImages basis = BasisImages::Read(basis_path);
  const std::vector<std::string> names = basis.BasisNames();
  const nlohmann::json cj = ReadJsonFile(classes_path);
  const ClassModel model = ClassModel::FromJson(cj, classes_path);
  if (model.label.size() != names.size())
    throw FileError(classes_path, "has " + std::to_string(model.label.size()) + " bases, the basis images " +
                                      std::to_string(names.size()));
  for (size_t i = 0; i < names.size(); ++i)
    if (cj["bases"][i]["name"] != names[i])
      throw FileError(classes_path, "basis " + std::to_string(i) + " is '" + cj["bases"][i]["name"].get<std::string>() +
                                        "', the basis images have '" + names[i] + "'");
  Eigen::MatrixXd y(basis.geometry.size(), 3);
  if (!obs_path.empty()) {
    const Observations obs = Observations::Read(obs_path);
    if (obs.geometry.Hash() != basis.geometry.Hash())
      throw FileError(obs_path, "its pixels are not the ones " + basis_path +
                                    " was computed for: run 'brdfshot basis --obs " + obs_path + "'");
    y = obs.rgb;
    photo_path = obs_path;
  } else {
    const cv::Mat photo = ReadHdrImage(photo_path);
    if (photo.cols != basis.geometry.width || photo.rows != basis.geometry.height)
      throw FileError(photo_path, "is " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows) +
                                      ", the basis images are for " + std::to_string(basis.geometry.width) + "x" +
                                      std::to_string(basis.geometry.height));
    for (size_t p = 0; p < basis.geometry.size(); ++p) {
      const cv::Vec3f v = photo.at<cv::Vec3f>(basis.geometry.y[p], basis.geometry.x[p]);
      for (int c = 0; c < 3; ++c) y(p, c) = v[c];
    }
  }

  MakeOutputDir(out);  // only once the inputs have been read: a refused input leaves nothing behind
  Stopwatch sw;
  const auto factors = FactorBasisImages(basis.Y);
  const double t_factor = sw.Seconds();
  std::vector<std::vector<int>> members(model.classes());
  for (size_t i = 0; i < model.label.size(); ++i) members[model.label[i]].push_back(static_cast<int>(i));
  const std::array<Eigen::MatrixXd, 3> R = {factors[0].R, factors[1].R, factors[2].R};
  Stopwatch solve_sw;
  const Observation obs = MakeObservation(factors, y);
  SolveOptions so;
  so.lambda = lambda;
  so.condition = false;
  const ClasswiseFit fast = SolveClasswise(R, obs, members, so);
  const double t_solve = solve_sw.Seconds();
  so.condition = true;
  const ClasswiseFit fit = SolveClasswise(R, obs, members, so);
  BRDFSHOT_CHECK(fit.chosen == fast.chosen);
  const Eigen::MatrixXd& w = fit.weights();

  // Reconstruction in the photo's own lighting: Y w.
  Eigen::MatrixXd recon(y.rows(), 3);
  for (int c = 0; c < 3; ++c) recon.col(c) = basis.Y[c].cast<double>() * w.col(c);
  const double rel = std::sqrt((recon - y).squaredNorm() / std::max(1e-300, y.squaredNorm()));

  nlohmann::json j;
  j["format"] = "brdfshot-fit-1";
  j["database"] = basis.header["database"];
  j["database_kind"] = basis.header["database_kind"];
  j["grid"] = basis.header["grid"];
  j["probe"] = basis.header["probe"];
  j["photo"] = photo_path;
  j["lambda"] = lambda;
  j["chosen_class"] = fit.chosen;
  j["relative_residual"] = rel;
  for (size_t k = 0; k < fit.classes.size(); ++k) {
    const auto& s = fit.classes[k];
    j["classes"].push_back({{"class", k}, {"members", s.members}, {"residual", s.residual},
                            {"condition", {s.condition[0], s.condition[1], s.condition[2]}}});
  }
  j["bases"] = names;
  for (Eigen::Index i = 0; i < w.rows(); ++i) j["weights"].push_back({w(i, 0), w(i, 1), w(i, 2)});
  j["seconds"] = {{"factor_basis_images", t_factor}, {"solve", t_solve}};
  WriteFileAtomic(out + "/fit.json", [&](std::ostream& o) { o << j.dump(1) << "\n"; });

  // The BRDF itself, in the database's grid.
  DatabaseOptions opt = db.ToOptions(false);
  opt.kind = basis.header["database_kind"];
  const auto g = basis.header["grid"];
  opt.grid = MerlGrid{g[0], g[1], g[2]};
  opt.only = MaterialsOfBases(names);
  const BasisDatabase base = LoadDatabase(opt);
  const MerlBrdf brdf = CombineBases(base, w);
  brdf.Write(out + "/brdf.binary");

  // Previews: photo | reconstruction, then the result relit under other probes.
  const cv::Mat photo_img = PixelsToImage(basis.geometry, y), recon_img = PixelsToImage(basis.geometry, recon);
  const double exposure = AutoExposure(photo_img);
  cv::Mat side;
  cv::hconcat(photo_img, recon_img, side);
  WritePngTonemapped(out + "/photo_vs_fit.png", side, exposure);
  std::vector<std::string> relight = ResolveProbes(previews, db.data);
  const std::string own = basis.header["probe_name"];
  std::vector<std::string> picked;
  for (const auto& p : relight)
    if (std::filesystem::path(p).stem() != own && picked.size() < 2) picked.push_back(p);
  for (const auto& p : picked) {
    const LatLongProbe probe = LatLongProbe::Read(p);
    const PixelGeometry pg = OrthographicSphere(128, 89.5);
    const cv::Mat img = PixelsToImage(pg, TransportOperator::Build(pg, probe, brdf.grid(), quality.q).Render(brdf));
    WritePngTonemapped(out + "/relit_" + probe.name() + ".png", img, AutoExposure(img));
  }
  std::printf("database: %s\nchosen class %d; per-class residual (sum over RGB):", base.label.c_str(), fit.chosen);
  for (size_t k = 0; k < fit.classes.size(); ++k)
    std::printf(" [%zu] %.4g (%d bases, cond %.3g)", k, fit.classes[k].residual, fit.classes[k].members,
                fit.classes[k].condition[1]);
  std::printf("\nrelative residual %.4f; solve %.2f ms (after a %.2f s factorisation of the basis images)\n"
              "wrote %s/fit.json, brdf.binary, photo_vs_fit.png and %zu relit previews\n",
              rel, 1000 * t_solve, t_factor, out.c_str(), picked.size());
  return 0;
}

}  // namespace brdfshot
