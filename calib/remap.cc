#include "calib/remap.h"

#include <opencv2/imgcodecs.hpp>

#include "calib/calibration.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

// FileError naming `path` when what it holds is for a photo of another size.
void CheckSize(const std::string& path, cv::Size size, cv::Size photo, const std::string& photo_path) {
  if (size != photo)
    throw FileError(path, "is for a " + std::to_string(size.width) + "x" + std::to_string(size.height) + " photo, " +
                              photo_path + " is " + std::to_string(photo.width) + "x" + std::to_string(photo.height));
}

// A grey mask at `path`, of the photo's size.
cv::Mat ReadMask(const std::string& path, cv::Size photo, const std::string& photo_path) {
  const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (m.empty()) throw FileError(path, "cannot decode mask");
  CheckSize(path, m.size(), photo, photo_path);
  return m;
}

}  // namespace

Observations RemapPhoto(const RemapOptions& o) {
  BRDFSHOT_CHECK(o.sphere.empty() != o.normal_map.empty(), "one geometry: a sphere file or a normal map");
  const cv::Mat photo = ReadHdrImage(o.photo);
  Rotation rotation;
  cv::Vec3d scale(1, 1, 1);
  std::string probe;  // provenance only
  if (!o.calibration.empty()) {
    const Calibration c = Calibration::Read(o.calibration);
    rotation = c.camera_to_probe;
    scale = c.scale;
    probe = c.probe;
  }
  const cv::Mat unreliable = o.unreliable.empty() ? cv::Mat() : ReadMask(o.unreliable, photo.size(), o.photo);
  PixelGeometry geometry;
  if (!o.sphere.empty()) {
    const SphereView view = SphereView::FromJson(ReadJsonFile(o.sphere), o.sphere);
    CheckSize(o.sphere, cv::Size(view.width, view.height), photo.size(), o.photo);
    geometry = SphereViewGeometry(view, rotation, o.sphere_mask, unreliable);
  } else {
    const cv::Mat normals = ReadNormalMap(o.normal_map);
    CheckSize(o.normal_map, normals.size(), photo.size(), o.photo);
    const cv::Mat mask = o.object_mask.empty() ? cv::Mat() : ReadMask(o.object_mask, photo.size(), o.photo);
    NormalMapOptions map = o.normal_map_options;
    map.max_angle_deg = o.sphere_mask.max_angle_deg;
    geometry = NormalMapGeometry(normals, mask, map, rotation, unreliable);
  }
  Observations obs = ObservePixels(photo, std::move(geometry), scale, o.sphere.empty() ? o.normal_map : o.sphere);
  obs.header = {{"photo", o.photo},
                {"sphere", o.sphere},
                {"normal_map", o.normal_map},
                {"mask", o.object_mask},
                {"calib", o.calibration},
                {"probe", probe},
                {"unreliable", o.unreliable},
                {"margin_deg", o.sphere_mask.max_angle_deg},
                {"rim_px", o.sphere_mask.rim_margin_px},
                {"scale", {scale[0], scale[1], scale[2]}},
                {"command", o.command}};
  return obs;
}

}  // namespace brdfshot
