// brdfshot normals: find the sphere in a photo (coarse Hough, sub-pixel rim),
// write its camera model as JSON, an overlay picture and the sphere's mask
// (normals/sphere_from_photo.h).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "apps/common_options.h"
#include "capture/merge_sidecar.h"
#include "normals/sphere_from_photo.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

// The command line as typed; DetectOptions turns it into the detector's options for a photo.
struct NormalsArgs {
  std::string photo, out = "sphere.json", overlay, near, merge_sidecar, normal_map_out;
  SphereDetectOptions detect;
  double focal_35mm = 0;

  void Add(po::options_description& desc) {
    // clang-format off
    desc.add_options()
        ("photo", po::value(&photo)->required(), "linear HDR photo (EXR/HDR/PFM) or an 8/16-bit image")
        ("focal-px", po::value(&detect.focal_px)->default_value(0), "focal length in pixels: perspective model (0: orthographic)")
        ("focal-35mm", po::value(&focal_35mm)->default_value(0), "35 mm-equivalent focal length (EXIF FocalLengthIn35mmFilm) instead of --focal-px")
        ("merge", po::value(&merge_sidecar), "the photo's merge sidecar (from 'brdfshot merge'): its EXIF 35 mm focal length, when the camera wrote one, sets the perspective model unless --focal-px or --focal-35mm is given")
        ("near", po::value(&near), "X,Y: a pixel inside the sphere to measure, when the photo holds more than one")
        ("rays", po::value(&detect.rays)->default_value(detect.rays), "radial profiles for the sub-pixel rim")
        ("normal-map-out", po::value(&normal_map_out), "also write the sphere's normals (camera frame, float EXR, 0 off the sphere): what 'remap --normal-map' reads for other shapes")
        ("overlay", po::value(&overlay), "picture of the detection (default: <out>.png)")
        ("out,o", po::value(&out)->default_value(out), "sphere file (JSON) for 'brdfshot remap'");
    // clang-format on
  }

  // `focal_from` says where the focal length came from, for the user.
  SphereDetectOptions DetectOptions(cv::Size size, std::string* focal_from) const {
    SphereDetectOptions o = detect;
    if (!near.empty()) {
      const std::vector<double> p = ParseNumberList(near, 2, "--near", "X,Y in pixels");
      o.near = {p[0], p[1]};
      if (o.near.x < 0 || o.near.y < 0 || o.near.x > size.width || o.near.y > size.height)
        throw Error("--near " + near + " lies outside the photo (" + std::to_string(size.width) + "x" +
                    std::to_string(size.height) + ")");
    }
    double mm = focal_35mm;
    *focal_from = o.focal_px > 0 || mm > 0 ? "as given" : "";
    if (focal_from->empty() && !merge_sidecar.empty()) {
      mm = MergeSidecar::Read(merge_sidecar).focal_35mm;
      if (mm > 0) *focal_from = "from the EXIF 35 mm focal length in " + merge_sidecar;
    }
    o.focal_px = FocalLengthPx(o.focal_px, mm, size);
    return o;
  }
};

}  // namespace

int NormalsMain(int argc, char** argv) {
  NormalsArgs args;
  po::options_description desc("options");
  args.Add(desc);
  po::positional_options_description pos;
  pos.add("photo", 1);
  if (!ParseOptions("normals", "PHOTO [options]", desc, argc, argv, &pos)) return 0;
  const std::string overlay =
      args.overlay.empty() ? std::filesystem::path(args.out).replace_extension(".png").string() : args.overlay;
  const cv::Mat rgb = ReadPhotoForDetection(args.photo);
  std::string focal_from;
  const SphereInPhoto s = FindSphereInPhoto(rgb, args.DetectOptions(rgb.size(), &focal_from), args.photo);
  for (const std::string& w : s.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const SphereView& v = s.view;
  const std::string text = SphereFileJson(v, s.detection, args.photo, s.seconds).dump(1);
  WriteFileAtomic(args.out, [&](std::ostream& o) { o << text << "\n"; });
  if (!args.normal_map_out.empty()) WriteExr(args.normal_map_out, NormalMapOf(v));
  WritePng(overlay, DetectionOverlay(rgb, s.detection));
  const std::string camera = v.perspective
                                 ? "perspective, f " + std::to_string(std::lround(v.focal_px)) + " px " + focal_from
                                 : "orthographic";
  std::printf(
      "sphere in %s: centre (%.2f, %.2f) radius %.2f px (%s), %d/%d rim points, rms %.3f px, blur %.2f px, %.0f ms\n"
      "wrote %s, %s\n",
      args.photo.c_str(), v.circle.cx, v.circle.cy, v.circle.r, camera.c_str(), s.detection.quality.inliers,
      s.detection.quality.points, s.detection.quality.rms_px, s.detection.blur_sigma, 1000 * s.seconds,
      args.out.c_str(), overlay.c_str());
  return 0;
}

}  // namespace brdfshot
