#include "fit/fit_stage.h"

#include <filesystem>

#include "fit/fit_previews.h"
#include "fit/joint_photos.h"
#include "util/check.h"

namespace brdfshot {

namespace {
std::string Joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}
}  // namespace

FitStageResult RunFitStage(const FitStageOptions& o) {
  const size_t P = o.basis.size();
  BRDFSHOT_CHECK(P >= 1 && (o.photo.empty() != o.observations.empty()) &&
                     std::max(o.photo.size(), o.observations.size()) == P,
                 "one photo or observation file per basis-image file");
  const ClassModel model = ClassModel::Read(o.classes);
  std::vector<BasisImages> bases;
  std::vector<Eigen::MatrixXd> pixels;
  for (size_t i = 0; i < P; ++i) {
    bases.push_back(BasisImages::Read(o.basis[i]));
    CheckModelMatchesBases(model, o.classes, bases[i].BasisNames());
    pixels.push_back(ReadFitPixels(bases[i], o.basis[i], o.photo.empty() ? "" : o.photo[i],
                                   o.observations.empty() ? "" : o.observations[i]));
  }
  const BasisDatabase tables = DatabaseOfBases(bases[0], o.database);
  const JointPhotos joint = P > 1 ? StackPhotos(bases, pixels, o.basis, std::max(2, o.fit.folds)) : JointPhotos{};

  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (!std::filesystem::is_directory(o.out, ec)) throw FileError(o.out, "cannot create output folder");
  PhotoFitOptions joint_options = o.fit;
  if (!joint_options.relative_noise) joint_options.relative_noise = joint.relative_noise;
  const PhotoFit fit = P > 1 ? FitPhoto(joint.basis, model, joint.y, joint_options, &tables.B, &joint.fold_of_pixel)
                             : FitPhoto(bases[0], model, pixels[0], o.fit, &tables.B);
  FitStageResult r;
  r.record = FitRecord::From(fit, P > 1 ? joint.basis : bases[0], Joined(o.observations.empty() ? o.photo : o.observations));
  r.record.Write(o.out + "/fit.json");
  const MerlBrdf brdf = BrdfOfFit(r.record, tables, &r.label, &r.clamped);
  brdf.Write(o.out + "/brdf.binary");
  if (r.record.lambert_ggx)  // the analytic baseline as a table too, for any MERL renderer
    LambertGgxBrdf(r.record).Write(o.out + "/lambert_ggx.binary");

  // Each photo beside its reconstruction, in its own scale: photo_vs_fit.png,
  // then photo_vs_fit_2.png … for the other photos of a joint fit.
  Eigen::Index row = 0;
  for (size_t i = 0; i < P; ++i) {
    const Eigen::Index n = static_cast<Eigen::Index>(bases[i].geometry.size());
    const Eigen::MatrixXd reconstruction =
        P > 1 ? Eigen::MatrixXd(fit.reconstruction.middleRows(row, n) / joint.scale[i]) : fit.reconstruction;
    WritePhotoVersusFit(bases[i], pixels[i], reconstruction, o.out,
                        i == 0 ? "photo_vs_fit.png" : "photo_vs_fit_" + std::to_string(i + 1) + ".png");
    row += n;
  }
  std::vector<LatLongProbe> others;
  for (const std::string& p : o.preview_probes) {
    bool own = false;
    for (const BasisImages& b : bases) own = own || std::filesystem::path(p).stem() == b.header.value("probe_name", "");
    if (!own && others.size() < 2) others.push_back(LatLongProbe::Read(p));
  }
  r.previews = WriteRelitPreviews(brdf, others, o.preview_quality, o.out);
  return r;
}

}  // namespace brdfshot
