// brdfshot calib: the light probe in the pipeline's lat-long frame and its
// relation to the camera: layout conversion (lat-long, angular map, mirror
// ball), rotation camera → probe, radiometric scale photo units per probe unit.
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/command.h"
#include "apps/common_options.h"
#include "calib/probe_alignment.h"
#include "calib/probe_layout.h"
#include "calib/sun_probe.h"
#include "normals/sphere_detect.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/rotation.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {
// A photographed mirror ball, found by the sphere detector and unwrapped to
// lat-long in the camera's frame; its circle and options go into `j`.
UnwrappedBall UnwrapBallPhoto(const std::string& path, int width, const MirrorBallOptions& ball, nlohmann::json* j) {
  const cv::Mat img = ReadHdrImage(path);
  SphereDetection det;
  try {
    det = DetectSphere(img);
  } catch (const Error& e) {
    throw FileError(path, e.what());
  }
  UnwrappedBall u = UnwrapMirrorBall(img, det.circle.cx, det.circle.cy, det.circle.r, width, ball);
  *j = {{"photo", path}, {"cx", det.circle.cx}, {"cy", det.circle.cy}, {"r", det.circle.r},
        {"reflectance", ball.reflectance}, {"max_normal_deg", ball.max_normal_deg},
        {"camera_hole_deg", ball.camera_hole_deg},
        {"measured_fraction", cv::countNonZero(u.measured) / double(u.measured.total())}};
  return u;
}
}  // namespace

int CalibMain(int argc, char** argv) {
  std::string probe_path, layout = "latlong", rotate = "0,0,0", out = "probe.exr", sidecar, sun, sun_radiance = "1,1,1";
  std::string rotate_from_ball;
  double sun_deg = 1.0;
  double scale = 1;
  int width = 0;
  MirrorBallOptions ball;
  po::options_description desc("options");
  desc.add_options()
      ("probe,p", po::value(&probe_path), "probe image (.exr/.hdr/.pfm)")
      ("sun", po::value(&sun), "instead of --probe: one distant light towards x,y,z (probe frame), e.g. a photometric-stereo LED")
      ("sun-radiance", po::value(&sun_radiance)->default_value(sun_radiance), "--sun's irradiance R,G,B at normal incidence")
      ("sun-size", po::value(&sun_deg)->default_value(sun_deg), "--sun's angular radius, degrees")
      ("layout", po::value(&layout)->default_value(layout), "latlong | angular | mirrorball (a photo of a chrome ball)")
      ("width", po::value(&width)->default_value(0), "lat-long width to write (0: as given, 512 for converted layouts)")
      ("rotate", po::value(&rotate)->default_value(rotate), "camera → probe rotation as yaw,pitch,roll degrees (util/rotation.h)")
      ("rotate-from-ball", po::value(&rotate_from_ball), "instead of --rotate: estimate the rotation from this HDR photo of a mirror ball taken from the camera's position (calib/probe_alignment.h)")
      ("scale", po::value(&scale)->default_value(scale), "photo radiance per probe radiance (exposure ratio)")
      ("ball-reflectance", po::value(&ball.reflectance)->default_value(ball.reflectance), "mirror ball reflectance")
      ("ball-max-angle", po::value(&ball.max_normal_deg)->default_value(ball.max_normal_deg), "ball normals beyond this (deg) are the unreliable rim")
      ("ball-camera-hole", po::value(&ball.camera_hole_deg)->default_value(ball.camera_hole_deg), "ball normals within this (deg) of the camera show the camera: filled in")
      ("sidecar", po::value(&sidecar), "calibration JSON (default: <out>.json)")
      ("out,o", po::value(&out)->default_value(out), "lat-long probe (EXR)");
  if (!ParseOptions("calib", "(--probe P [--layout L] | --sun x,y,z) [--rotate y,p,r] [--scale s] [options]", desc,
                    argc, argv))
    return 0;
  if (probe_path.empty() == sun.empty()) throw Error("calib: give exactly one of --probe and --sun");
  if (sidecar.empty()) sidecar = std::filesystem::path(out).replace_extension(".json").string();
  std::vector<double> a = ParseNumberList(rotate, 3, "--rotate", "yaw,pitch,roll in degrees");
  if (!(scale > 0)) throw Error("--scale must be positive");
  if (!rotate_from_ball.empty() && rotate != "0,0,0") throw Error("calib: give --rotate or --rotate-from-ball, not both");
  Rotation rot = Rotation::FromYawPitchRoll(a[0], a[1], a[2]);
  nlohmann::json j = {{"format", "brdfshot-calib-1"}, {"source", probe_path}, {"layout", layout}};
  LatLongProbe probe;
  if (!sun.empty()) {
    const std::vector<double> d = ParseNumberList(sun, 3, "--sun", "x,y,z");
    const std::vector<double> e = ParseNumberList(sun_radiance, 3, "--sun-radiance", "R,G,B");
    probe = SunProbe(Vec3(d[0], d[1], d[2]), cv::Vec3f(e[0], e[1], e[2]), sun_deg, width > 0 ? width : 512);
    j["source"] = "sun " + sun;
    j["layout"] = "sun";
    j["sun"] = {{"direction", d}, {"irradiance", e}, {"radius_deg", sun_deg}};
    probe_path = j["source"];
  } else if (layout == "latlong") {
    probe = LatLongProbe::Read(probe_path);
    if (width > 0) probe = probe.Resized(width);
  } else if (layout == "angular") {
    const cv::Mat img = ReadHdrImage(probe_path);
    if (img.cols != img.rows) throw FileError(probe_path, "an angular map must be square");
    probe = AngularMapToLatLong(img, width > 0 ? width : 512);
  } else if (layout == "mirrorball") {
    nlohmann::json jb;
    probe = UnwrapBallPhoto(probe_path, width > 0 ? width : 512, ball, &jb).probe;
    j["ball"] = jb;
  } else {
    throw Error("unknown --layout '" + layout + "': expected latlong, angular or mirrorball");
  }
  if (!rotate_from_ball.empty()) {
    nlohmann::json jb;
    const UnwrappedBall u = UnwrapBallPhoto(rotate_from_ball, 256, ball, &jb);
    const RotationFit fit = EstimateRotation(probe, u.probe, u.measured);
    rot = fit.rotation;
    a = {fit.yaw, fit.pitch, fit.roll};
    jb["rms_log_radiance"] = fit.rms_log;
    j["rotation_from_ball"] = jb;
  }
  WriteExr(out, probe.rgb());
  j["probe"] = out;
  j["width"] = probe.width();
  j["rotation_camera_to_probe"] = rot.m;
  j["yaw_pitch_roll_deg"] = {a[0], a[1], a[2]};
  j["scale"] = scale;
  WriteFileAtomic(sidecar, [&](std::ostream& s) { s << j.dump(1) << "\n"; });
  std::printf("probe %s (%s) -> %dx%d lat-long; rotation yaw %.2f pitch %.2f roll %.2f deg, scale %g\nwrote %s, %s\n",
              probe_path.c_str(), layout.c_str(), probe.width(), probe.height(), a[0], a[1], a[2], scale, out.c_str(),
              sidecar.c_str());
  return 0;
}

}  // namespace brdfshot
