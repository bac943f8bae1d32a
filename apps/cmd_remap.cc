// brdfshot remap: the observation file the solver reads — each valid pixel's
// radiance (probe units), normal and view direction in the probe frame.
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "apps/command.h"
#include "normals/observation.h"
#include "normals/sphere_view.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

int RemapMain(int argc, char** argv) {
  std::string photo_path, sphere_path, calib_path, unreliable_path, out = "observations.bsobs";
  SphereMaskOptions mask;
  po::options_description desc("options");
  desc.add_options()
      ("photo", po::value(&photo_path)->required(), "linear HDR photo (from 'brdfshot merge')")
      ("sphere", po::value(&sphere_path)->required(), "sphere file (from 'brdfshot normals')")
      ("calib", po::value(&calib_path), "probe calibration (from 'brdfshot calib'): rotation and scale")
      ("unreliable", po::value(&unreliable_path), "mask PNG of unreliable pixels (from 'brdfshot merge')")
      ("margin", po::value(&mask.max_angle_deg)->default_value(mask.max_angle_deg), "max angle between normal and view (deg)")
      ("rim-px", po::value(&mask.rim_margin_px)->default_value(mask.rim_margin_px), "pixels this close to the silhouette are dropped")
      ("out,o", po::value(&out)->default_value(out), "observation file");
  if (!ParseOptions("remap", "--photo P --sphere S [--calib C] [options]", desc, argc, argv)) return 0;
  const cv::Mat photo = ReadHdrImage(photo_path);
  const SphereView view = SphereView::FromJson(ReadJsonFile(sphere_path), sphere_path);
  if (view.width != photo.cols || view.height != photo.rows)
    throw FileError(sphere_path, "is for a " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                                     " photo, " + photo_path + " is " + std::to_string(photo.cols) + "x" +
                                     std::to_string(photo.rows));
  Rotation rot;
  cv::Vec3d scale(1, 1, 1);
  std::string probe_name;  // provenance only; without --calib the photo is taken as in the probe frame
  if (!calib_path.empty()) {
    const nlohmann::json calib = ReadJsonFile(calib_path);
    try {
      if (calib.at("format") != "brdfshot-calib-1") throw FileError(calib_path, "not a brdfshot calibration");
      rot.m = calib.at("rotation_camera_to_probe").get<decltype(rot.m)>();
      // One number (older sidecars) or R,G,B.
      const nlohmann::json& js = calib.at("scale");
      for (int c = 0; c < 3; ++c) scale[c] = js.is_array() ? js.at(c).get<double>() : js.get<double>();
      probe_name = calib.value("probe", "");
    } catch (const nlohmann::json::exception& e) {
      throw FileError(calib_path, std::string("incomplete calibration: ") + e.what());
    }
    if (rot.OrthonormalityError() > 1e-6) throw FileError(calib_path, "rotation is not orthonormal");
    if (!(scale[0] > 0 && scale[1] > 0 && scale[2] > 0)) throw FileError(calib_path, "scale must be positive");
  }
  cv::Mat unreliable;
  if (!unreliable_path.empty()) {
    unreliable = cv::imread(unreliable_path, cv::IMREAD_GRAYSCALE);
    if (unreliable.empty()) throw FileError(unreliable_path, "cannot decode mask");
    if (unreliable.size() != photo.size()) throw FileError(unreliable_path, "mask size differs from the photo's");
  }
  Observations obs;
  obs.geometry = SphereViewGeometry(view, rot, mask, unreliable);
  if (obs.geometry.size() < 16)
    throw FileError(sphere_path, "leaves " + std::to_string(obs.geometry.size()) + " usable pixels");
  obs.rgb.resize(obs.geometry.size(), 3);
  for (size_t p = 0; p < obs.geometry.size(); ++p) {
    const cv::Vec3f v = photo.at<cv::Vec3f>(obs.geometry.y[p], obs.geometry.x[p]);
    for (int c = 0; c < 3; ++c) obs.rgb(p, c) = v[c] / scale[c];
  }
  obs.header = {{"photo", photo_path}, {"sphere", sphere_path}, {"calib", calib_path},
                {"probe", probe_name}, {"unreliable", unreliable_path},
                {"margin_deg", mask.max_angle_deg}, {"rim_px", mask.rim_margin_px}, {"scale", {scale[0], scale[1], scale[2]}},
                {"command", CommandLine(argc, argv)}};
  obs.Write(out);
  std::printf("%zu pixels of %s in the probe frame (divided by scale %g %g %g)\nwrote %s\n", obs.geometry.size(),
              photo_path.c_str(), scale[0], scale[1], scale[2], out.c_str());
  return 0;
}

}  // namespace brdfshot
