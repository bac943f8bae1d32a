// brdfshot fit: the class-wise solve for one photo (paper sec. 4), with the
// regularisation chosen from the photo's own pixels (fit/lambda_choice.h).
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "fit/fit_previews.h"
#include "fit/photo_fit.h"
#include "fit/transport.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

int FitMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  PhotoFitOptions fo;
  std::string basis_path, photo_path, obs_path, classes_path, out = "fit_out", previews, grid;
  double lambda = -1;
  std::string constraint = "bins";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("basis,b", po::value(&basis_path)->required(), "basis-image cache from 'brdfshot basis'")
      ("photo", po::value(&photo_path), "linear HDR photo (EXR) aligned with the basis images' pixels")
      ("obs", po::value(&obs_path), "observation file (from 'brdfshot remap') instead of --photo")
      ("classes,c", po::value(&classes_path)->required(), "class model from 'brdfshot cluster'")
      ("lambda-rule", po::value(&fo.lambda.rule)->default_value(fo.lambda.rule),
       "how the regularisation weight is chosen: cv (held-out wedges of the sphere), gcv, or fixed (--lambda)")
      ("lambda", po::value(&lambda), "fix the regularisation weight (the paper's: 0.5); implies --lambda-rule fixed")
      ("folds", po::value(&fo.folds)->default_value(fo.folds), "wedges for --lambda-rule cv")
      ("max-condition", po::value(&fo.lambda.max_condition)->default_value(fo.lambda.max_condition),
       "a λ is a candidate only while the condition number of G_JJ + λ_j I stays below this")
      ("lambda-grid", po::value(&grid), "comma-separated λ values the rule chooses among (default: 0 … 10)")
      ("constraint", po::value(&constraint)->default_value(constraint),
       "what the fit keeps non-negative: bins (the BRDF at every 31st bin; default), weights (every weight ≥ 0: "
       "non-negative everywhere, but relights worse), none")
      ("out,o", po::value(&out)->default_value(out), "output folder")
      ("preview-probes", po::value(&previews), "probes to relight the result under (default: two of <data>/envmaps)");
  // clang-format on
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("fit", "--basis Y.bsbi (--photo photo.exr | --obs obs.bsobs) --classes classes.json [options]",
                    desc, argc, argv))
    return 0;
  if (photo_path.empty() == obs_path.empty()) throw Error("fit: give exactly one of --photo and --obs");
  if (lambda >= 0)
    fo.lambda.rule = "fixed", fo.lambda.fixed = lambda;
  else if (lambda != -1)
    throw Error("--lambda must be ≥ 0");
  if (fo.lambda.rule != "cv" && fo.lambda.rule != "gcv" && fo.lambda.rule != "fixed")
    throw Error("unknown --lambda-rule '" + fo.lambda.rule + "': cv, gcv or fixed");
  if (fo.lambda.rule == "fixed" && lambda < 0) fo.lambda.fixed = 0.5;
  if (fo.folds < 2) throw Error("--folds must be at least 2");
  if (!(fo.lambda.max_condition >= 1)) throw Error("--max-condition must be at least 1");
  if (!grid.empty()) fo.lambda.grid = ParseLambdaGrid(grid);
  fo.constraint = ParseConstraint(constraint);

  const BasisImages basis = BasisImages::Read(basis_path);
  const nlohmann::json model_json = ReadJsonFile(classes_path);
  CheckModelMatchesBases(model_json, classes_path, basis.BasisNames());
  const ClassModel model = ClassModel::FromJson(model_json, classes_path);
  const Eigen::MatrixXd y = ReadFitPixels(basis, basis_path, photo_path, obs_path);

  const BasisDatabase tables = DatabaseOfBases(basis, db.ToOptions(false));

  MakeOutputDir(out);  // only once the inputs have been read: a refused input leaves nothing behind
  const PhotoFit fit = FitPhoto(basis, model, y, fo, &tables.B);
  const FitRecord record = FitRecord::From(fit, basis, obs_path.empty() ? photo_path : obs_path);
  record.Write(out + "/fit.json");
  std::string label;
  long clamped = 0;
  const MerlBrdf brdf = BrdfOfFit(record, tables, &label, &clamped);
  brdf.Write(out + "/brdf.binary");

  // Previews: photo | reconstruction, then the result relit under two other probes.
  WritePhotoVersusFit(basis, y, fit.reconstruction, out);
  std::vector<LatLongProbe> others;
  for (const auto& p : ResolveProbes(previews, db.data))
    if (std::filesystem::path(p).stem() != basis.header.value("probe_name", "") && others.size() < 2)
      others.push_back(LatLongProbe::Read(p));
  const std::vector<std::string> relit = WriteRelitPreviews(brdf, others, quality.q, out);
  std::printf(
      "%s\nchosen class %d, lambda %g (%s), constraint: %s (%ld bin-channels below zero clamped); predicted relit "
      "error %.4f; per class (residual, bases, cond):",
      label.c_str(), record.chosen_class, record.lambda, record.lambda_rule.c_str(), record.weights_constraint.c_str(),
      clamped, record.predicted_relit_error);
  for (size_t k = 0; k < record.classes.size(); ++k)
    std::printf(" [%zu] %.4g, %d, %.3g", k, record.classes[k].residual, record.classes[k].members,
                record.classes[k].condition);
  std::printf(
      "\nrelative residual %.4f; solve %.2f ms (after a %.3f s factorisation); whole table checked in %.2f s, "
      "%d bins off the sample constrained\n"
      "wrote %s/fit.json, brdf.binary, photo_vs_fit.png and %zu relit previews\n",
      record.relative_residual, 1000 * record.seconds_solve, record.seconds_factor, record.seconds_table_check,
      record.negative_bins_added, out.c_str(), relit.size());
  return 0;
}

}  // namespace brdfshot
