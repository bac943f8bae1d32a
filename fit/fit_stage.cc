#include "fit/fit_stage.h"

#include <filesystem>

#include "fit/fit_previews.h"
#include "util/check.h"

namespace brdfshot {

FitStageResult RunFitStage(const FitStageOptions& o) {
  const BasisImages basis = BasisImages::Read(o.basis);
  const ClassModel model = ClassModel::Read(o.classes);
  CheckModelMatchesBases(model, o.classes, basis.BasisNames());
  const Eigen::MatrixXd y = ReadFitPixels(basis, o.basis, o.photo, o.observations);
  const BasisDatabase tables = DatabaseOfBases(basis, o.database);

  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (!std::filesystem::is_directory(o.out, ec)) throw FileError(o.out, "cannot create output folder");
  const PhotoFit fit = FitPhoto(basis, model, y, o.fit, &tables.B);
  FitStageResult r;
  r.record = FitRecord::From(fit, basis, o.observations.empty() ? o.photo : o.observations);
  r.record.Write(o.out + "/fit.json");
  const MerlBrdf brdf = BrdfOfFit(r.record, tables, &r.label, &r.clamped);
  brdf.Write(o.out + "/brdf.binary");

  WritePhotoVersusFit(basis, y, fit.reconstruction, o.out);
  std::vector<LatLongProbe> others;
  for (const std::string& p : o.preview_probes)
    if (std::filesystem::path(p).stem() != basis.header.value("probe_name", "") && others.size() < 2)
      others.push_back(LatLongProbe::Read(p));
  r.previews = WriteRelitPreviews(brdf, others, o.preview_quality, o.out);
  return r;
}

}  // namespace brdfshot
