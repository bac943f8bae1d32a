// brdfshot fit: the class-wise solve for one photo (paper sec. 4), with the
// regularisation chosen from the photo's own pixels (fit/lambda_choice.h).
#include <cmath>
#include <cstdio>

#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/scene_setup.h"
#include "fit/fit_stage.h"
#include "fit/transport.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

// The command line as typed; ToOptions checks it and fills the stage's options.
struct FitArgs {
  DatabaseArgs db;
  QualityArgs quality;
  PhotoFitOptions fo;
  std::string basis_path, photo_path, obs_path, classes_path, out = "fit_out", previews, grid;
  double lambda = -1;
  std::string constraint = "bins";

  void Add(po::options_description& desc) {
    // clang-format off
    desc.add_options()
        ("basis,b", po::value(&basis_path)->required(), "basis-image cache from 'brdfshot basis'; several "
         "photos of the same material (other probes, or turned) are fitted jointly: comma-separated, one per photo")
        ("photo", po::value(&photo_path), "linear HDR photo (EXR) aligned with the basis images' pixels (comma-separated: one per --basis)")
        ("obs", po::value(&obs_path), "observation file (from 'brdfshot remap') instead of --photo (comma-separated: one per --basis)")
        ("classes,c", po::value(&classes_path)->required(), "class model from 'brdfshot cluster'")
        ("lambda-rule", po::value(&fo.lambda.rule)->default_value(fo.lambda.rule),
         "how the regularisation weight is chosen: cv (held-out wedges of the sphere), residual (the least λ the "
         "condition bound allows, class by residual), gcv, or fixed (--lambda)")
        ("lambda", po::value(&lambda), "fix the regularisation weight (the paper's: 0.5); implies --lambda-rule fixed")
        ("folds", po::value(&fo.folds)->default_value(fo.folds), "wedges for --lambda-rule cv")
        ("lambda-grid", po::value(&grid), "comma-separated λ values the rule chooses among (default: 0 … 10)")
        ("constraint", po::value(&constraint)->default_value(constraint),
         "what the fit keeps non-negative: bins (the BRDF at every 31st bin; default), weights (every weight ≥ 0: "
         "non-negative everywhere, but relights worse), none")
        ("out,o", po::value(&out)->default_value(out), "output folder")
        ("preview-probes", po::value(&previews), "probes to relight the result under (default: two of <data>/envmaps; none: no relit previews, e.g. where a render stage follows)");
    // clang-format on
    AddConditionBoundOptions(desc, &fo.lambda);
    db.Add(desc);
    quality.Add(desc);
  }

  FitStageOptions ToOptions() const {
    if (photo_path.empty() == obs_path.empty()) throw Error("fit: give exactly one of --photo and --obs");
    FitStageOptions o;
    o.fit = fo;
    LambdaChoiceOptions& l = o.fit.lambda;
    if (lambda >= 0)
      l.rule = "fixed", l.fixed = lambda;
    else if (lambda != -1)
      throw Error("--lambda must be ≥ 0");
    if (l.rule != "cv" && l.rule != "residual" && l.rule != "gcv" && l.rule != "fixed")
      throw Error("unknown --lambda-rule '" + l.rule + "': cv, residual, gcv or fixed");
    if (l.rule == "fixed" && lambda < 0) l.fixed = 0.5;
    if (o.fit.folds < 2) throw Error("--folds must be at least 2");
    CheckConditionBound(l);
    if (!grid.empty()) l.grid = ParseLambdaGrid(grid);
    o.fit.constraint = ParseConstraint(constraint);
    o.basis = SplitList(basis_path), o.photo = SplitList(photo_path), o.observations = SplitList(obs_path);
    if (std::max(o.photo.size(), o.observations.size()) != o.basis.size())
      throw Error("fit: give one --photo or --obs file per --basis file (" + std::to_string(o.basis.size()) + ")");
    o.classes = classes_path, o.out = out;
    o.database = db.ToOptions(false);
    if (previews != "none") o.preview_probes = ResolveProbes(previews, db.data);
    o.preview_quality = quality.q;
    return o;
  }
};

}  // namespace

int FitMain(int argc, char** argv) {
  FitArgs args;
  po::options_description desc("options");
  args.Add(desc);
  if (!ParseOptions("fit", "--basis Y.bsbi (--photo photo.exr | --obs obs.bsobs) --classes classes.json [options]",
                    desc, argc, argv))
    return 0;
  const FitStageOptions o = args.ToOptions();
  const FitStageResult r = RunFitStage(o);
  const FitRecord& record = r.record;
  std::printf(
      "%s\nchosen class %d, lambda %g (%s), constraint: %s (%ld bin-channels below zero clamped); predicted relit "
      "error %.4f (prior sensitivity %.3f); pixel noise %.2e of the photo's RMS, condition bound %.3g; per class "
      "(residual, bases, cond):",
      r.label.c_str(), record.chosen_class, record.lambda, record.lambda_rule.c_str(),
      record.weights_constraint.c_str(), r.clamped, record.predicted_relit_error, record.prior_sensitivity,
      record.relative_noise, record.condition_bound);
  for (size_t k = 0; k < record.classes.size(); ++k)
    std::printf(" [%zu] %.4g, %d, %.3g", k, record.classes[k].residual, record.classes[k].members,
                record.classes[k].condition);
  if (record.parts.size() > 1) {
    std::printf("\nblended:");
    for (const LambdaChoice::Part& p : record.parts)
      std::printf(" %.2f x class %d at lambda %g;", p.weight, p.cls, p.lambda);
  }
  std::printf(
      "\nrelative residual %.4f; solve %.2f ms (after a %.3f s factorisation); whole table checked in %.2f s, "
      "%d bins off the sample constrained",
      record.relative_residual, 1000 * record.seconds_solve, record.seconds_factor, record.seconds_table_check,
      record.negative_bins_added);
  if (record.mean_blend > 0) std::printf(", the rest lifted by a %.2g blend toward the class mean", record.mean_blend);
  std::printf("\nwrote %s/fit.json, brdf.binary, photo_vs_fit.png and %zu relit previews\n", o.out.c_str(),
              r.previews.size());
  if (record.lambert_ggx) {
    const LambertGgxFit& g = *record.lambert_ggx;
    std::printf(
        "analytic baseline (Lambert + GGX, same pixels): relative residual %.4f; diffuse albedo %.3f %.3f %.3f, "
        "specular F0 %.3f %.3f %.3f x %.3f, roughness %.3f (GGX alpha %g); its table: %s/lambert_ggx.binary\n",
        g.relative_residual, g.diffuse_albedo[0], g.diffuse_albedo[1], g.diffuse_albedo[2], g.SpecularF0()[0],
        g.SpecularF0()[1], g.SpecularF0()[2], g.specular_scale, std::sqrt(g.alpha), g.alpha, o.out.c_str());
  }
  return 0;
}

}  // namespace brdfshot
