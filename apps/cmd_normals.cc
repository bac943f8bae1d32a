// brdfshot normals: find the sphere in a photo (coarse Hough, sub-pixel rim),
// write its camera model as JSON, an overlay picture and the sphere's mask.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/command.h"
#include "capture/merge_sidecar.h"
#include "normals/sphere_from_photo.h"
#include "apps/common_options.h"
#include "normals/sphere_detect.h"
#include "normals/sphere_view.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

int NormalsMain(int argc, char** argv) {
  std::string photo_path, out = "sphere.json", overlay;
  SphereDetectOptions o;
  double focal_35mm = 0;
  std::string near, merge_sidecar, normal_map_out;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("photo", po::value(&photo_path)->required(), "linear HDR photo (EXR/HDR/PFM) or an 8/16-bit image")
      ("focal-px", po::value(&o.focal_px)->default_value(0), "focal length in pixels: perspective model (0: orthographic)")
      ("focal-35mm", po::value(&focal_35mm)->default_value(0), "35 mm-equivalent focal length (EXIF FocalLengthIn35mmFilm) instead of --focal-px")
      ("merge", po::value(&merge_sidecar), "the photo's merge sidecar (from 'brdfshot merge'): its EXIF 35 mm focal length, when the camera wrote one, sets the perspective model unless --focal-px or --focal-35mm is given")
      ("near", po::value(&near), "X,Y: a pixel inside the sphere to measure, when the photo holds more than one")
      ("rays", po::value(&o.rays)->default_value(o.rays), "radial profiles for the sub-pixel rim")
      ("normal-map-out", po::value(&normal_map_out), "also write the sphere's normals (camera frame, float EXR, 0 off the sphere): what 'remap --normal-map' reads for other shapes")
      ("overlay", po::value(&overlay), "picture of the detection (default: <out>.png)")
      ("out,o", po::value(&out)->default_value(out), "sphere file (JSON) for 'brdfshot remap'");
  // clang-format on
  po::positional_options_description pos;
  pos.add("photo", 1);
  if (!ParseOptions("normals", "PHOTO [options]", desc, argc, argv, &pos)) return 0;
  if (overlay.empty()) overlay = std::filesystem::path(out).replace_extension(".png").string();
  const cv::Mat rgb = ReadPhotoForDetection(photo_path);
  if (!near.empty()) {
    const std::vector<double> p = ParseNumberList(near, 2, "--near", "X,Y in pixels");
    o.near = {p[0], p[1]};
    if (o.near.x < 0 || o.near.y < 0 || o.near.x > rgb.cols || o.near.y > rgb.rows)
      throw Error("--near " + near + " lies outside the photo (" + std::to_string(rgb.cols) + "x" +
                  std::to_string(rgb.rows) + ")");
  }
  std::string focal_from = o.focal_px > 0 || focal_35mm > 0 ? "as given" : "";
  if (focal_from.empty() && !merge_sidecar.empty()) {
    focal_35mm = MergeSidecar::Read(merge_sidecar).focal_35mm;
    if (focal_35mm > 0) focal_from = "from the EXIF 35 mm focal length in " + merge_sidecar;
  }
  o.focal_px = FocalLengthPx(o.focal_px, focal_35mm, rgb.size());
  Stopwatch sw;
  SphereDetection det;
  try {
    det = DetectSphere(rgb, o);
  } catch (const Error& e) {
    throw FileError(photo_path, e.what());
  }
  const double secs = sw.Seconds();
  if (det.rim_in_shadow)
    std::fprintf(stderr,
                 "warning: %s: part of the sphere's rim is in shadow; found from log-luminance edges, "
                 "expect ~0.5 px instead of ~0.1 px (a photo lit from the camera's side measures it better)\n",
                 photo_path.c_str());
  // A sphere cut by the border is still measured (the visible rim fixes the
  // circle), but the user should know part of it is missing.
  if (const int outside = RimOutsidePercent(det.circle, rgb.size()); outside > 0)
    std::fprintf(stderr,
                 "warning: %s: the sphere is cut by the image border (%d %% of its rim outside); "
                 "the fit uses the visible rim\n",
                 photo_path.c_str(), outside);
  const SphereView v = ViewOfDetection(det, rgb.size());
  const std::string text = SphereFileJson(v, det, photo_path, secs).dump(1);
  WriteFileAtomic(out, [&](std::ostream& s) { s << text << "\n"; });
  if (!normal_map_out.empty()) WriteExr(normal_map_out, NormalMapOf(v));
  WritePng(overlay, DetectionOverlay(rgb, det));
  const std::string camera =
      v.perspective
          ? "perspective, f " + std::to_string(static_cast<int>(std::lround(v.focal_px))) + " px " + focal_from
          : "orthographic";
  std::printf(
      "sphere in %s: centre (%.2f, %.2f) radius %.2f px (%s), %d/%d rim points, rms %.3f px, blur %.2f px, %.0f ms\n"
      "wrote %s, %s\n",
      photo_path.c_str(), v.circle.cx, v.circle.cy, v.circle.r, camera.c_str(), det.quality.inliers, det.quality.points,
      det.quality.rms_px, det.blur_sigma, 1000 * secs, out.c_str(), overlay.c_str());
  return 0;
}

}  // namespace brdfshot
