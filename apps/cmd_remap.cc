// brdfshot remap: the observation file the solver reads — each valid pixel's
// radiance (probe units), normal and view direction in the probe frame.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "apps/command.h"
#include "calib/calibration.h"
#include "normals/normal_map.h"
#include "normals/observation.h"
#include "normals/sphere_view.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

int RemapMain(int argc, char** argv) {
  std::string photo_path, sphere_path, normal_map_path, object_mask_path, calib_path, unreliable_path,
      out = "observations.bsobs";
  SphereMaskOptions mask;
  NormalMapOptions map_options;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("photo", po::value(&photo_path)->required(), "linear HDR photo (from 'brdfshot merge')")
      ("sphere", po::value(&sphere_path), "sphere file (from 'brdfshot normals')")
      ("normal-map", po::value(&normal_map_path), "instead of --sphere, any convex object: its normals (camera frame: x right, y up, z towards the camera) as a 8/16-bit PNG ((n + 1)/2) or a float EXR/PFM")
      ("mask", po::value(&object_mask_path), "--normal-map's object mask (nonzero = object; default: every pixel with a unit normal)")
      ("focal-px", po::value(&map_options.focal_px)->default_value(0), "--normal-map's camera: focal length in pixels (0: orthographic)")
      ("erode", po::value(&map_options.erode_px)->default_value(map_options.erode_px), "--normal-map's mask shrunk by this many pixels (its edge mixes background)")
      ("calib", po::value(&calib_path), "probe calibration (from 'brdfshot calib'): rotation and scale")
      ("unreliable", po::value(&unreliable_path), "mask PNG of unreliable pixels (from 'brdfshot merge')")
      ("margin", po::value(&mask.max_angle_deg)->default_value(mask.max_angle_deg), "max angle between normal and view (deg)")
      ("rim-px", po::value(&mask.rim_margin_px)->default_value(mask.rim_margin_px), "pixels this close to the silhouette are dropped")
      ("out,o", po::value(&out)->default_value(out), "observation file");
  // clang-format on
  if (!ParseOptions("remap", "--photo P (--sphere S | --normal-map N [--mask M]) [--calib C] [options]", desc, argc,
                    argv))
    return 0;
  if (sphere_path.empty() == normal_map_path.empty())
    throw Error("remap: give exactly one of --sphere and --normal-map");
  if (!object_mask_path.empty() && normal_map_path.empty()) throw Error("remap: --mask goes with --normal-map");
  const cv::Mat photo = ReadHdrImage(photo_path);
  auto check_size = [&](const std::string& path, cv::Size size) {
    if (size != photo.size())
      throw FileError(path, "is for a " + std::to_string(size.width) + "x" + std::to_string(size.height) + " photo, " +
                                photo_path + " is " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows));
  };
  SphereView view;
  cv::Mat normal_map, object_mask;
  if (!sphere_path.empty()) {
    view = SphereView::FromJson(ReadJsonFile(sphere_path), sphere_path);
    check_size(sphere_path, cv::Size(view.width, view.height));
  } else {
    normal_map = ReadNormalMap(normal_map_path);
    check_size(normal_map_path, normal_map.size());
    if (!object_mask_path.empty()) {
      object_mask = cv::imread(object_mask_path, cv::IMREAD_GRAYSCALE);
      if (object_mask.empty()) throw FileError(object_mask_path, "cannot decode mask");
      check_size(object_mask_path, object_mask.size());
    }
    if (!(map_options.focal_px >= 0)) throw Error("--focal-px must be a focal length in pixels, or 0 for orthographic");
    if (map_options.erode_px < 0) throw Error("--erode must be 0 or more pixels");
    map_options.max_angle_deg = mask.max_angle_deg;
  }
  Rotation rot;
  cv::Vec3d scale(1, 1, 1);
  std::string probe_name;  // provenance only; without --calib the photo is taken as in the probe frame
  if (!calib_path.empty()) {
    const Calibration calib = Calibration::Read(calib_path);
    rot = calib.camera_to_probe;
    scale = calib.scale;
    probe_name = calib.probe;
  }
  cv::Mat unreliable;
  if (!unreliable_path.empty()) {
    unreliable = cv::imread(unreliable_path, cv::IMREAD_GRAYSCALE);
    if (unreliable.empty()) throw FileError(unreliable_path, "cannot decode mask");
    if (unreliable.size() != photo.size()) throw FileError(unreliable_path, "mask size differs from the photo's");
  }
  const std::string& geometry_path = sphere_path.empty() ? normal_map_path : sphere_path;
  Observations obs =
      ObservePixels(photo,
                    sphere_path.empty() ? NormalMapGeometry(normal_map, object_mask, map_options, rot, unreliable)
                                        : SphereViewGeometry(view, rot, mask, unreliable),
                    scale, geometry_path);
  obs.header = {{"photo", photo_path},
                {"sphere", sphere_path},
                {"normal_map", normal_map_path},
                {"mask", object_mask_path},
                {"calib", calib_path},
                {"probe", probe_name},
                {"unreliable", unreliable_path},
                {"margin_deg", mask.max_angle_deg},
                {"rim_px", mask.rim_margin_px},
                {"scale", {scale[0], scale[1], scale[2]}},
                {"command", CommandLine(argc, argv)}};
  obs.Write(out);
  std::printf("%zu pixels of %s in the probe frame (divided by scale %g %g %g)\nwrote %s\n", obs.geometry.size(),
              photo_path.c_str(), scale[0], scale[1], scale[2], out.c_str());
  return 0;
}

}  // namespace brdfshot
