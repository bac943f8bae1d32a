// brdfshot calib: the light probe in the pipeline's lat-long frame and its
// relation to the camera: layout conversion (lat-long, angular map, mirror
// ball), rotation camera → probe, radiometric scale photo units per probe unit
// (given, from the two merges' exposure metadata, or measured on a reference
// card in the photo).
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/command.h"
#include "apps/common_options.h"
#include "calib/calibration.h"
#include "calib/mirror_ball.h"
#include "calib/probe_alignment.h"
#include "calib/probe_layout.h"
#include "calib/radiometric_scale.h"
#include "calib/sun_probe.h"
#include "normals/sphere_detect.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/rotation.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {
// How the user says where the mirror ball is: its circle (else detected) and,
// for a perspective camera, the focal length.
struct BallLocation {
  std::string circle;  // cx,cy,r; empty: detected
  double focal_px = 0;
  double focal_35mm = 0;
};

// A photographed mirror ball, unwrapped to lat-long in the camera's frame.
// A ball's rim reflects what lies right behind it, so against its own
// surroundings its silhouette can vanish: then the user marks the circle, as
// HDR tools ask for. With a focal length the ball is seen in perspective: a
// marked circle is taken as its silhouette and the cone fitted to it. The
// circle and options go into `j`.
UnwrappedBall UnwrapBallPhoto(const std::string& path, const BallLocation& where, int width,
                              const MirrorBallOptions& ball, nlohmann::json* j) {
  const cv::Mat img = ReadHdrImage(path);
  SphereDetectOptions detect;
  detect.focal_px = FocalLengthPx(where.focal_px, where.focal_35mm, img.size(), "ball-");
  const cv::Point2d principal(img.cols / 2.0, img.rows / 2.0);
  Circle c;
  SphereCone cone;
  if (!where.circle.empty()) {
    const std::vector<double> v = ParseNumberList(where.circle, 3, "--ball-circle", "cx,cy,r in pixels");
    c = {v[0], v[1], v[2]};
    if (!(c.r > 1)) throw Error("--ball-circle: the radius must be more than a pixel");
    if (detect.focal_px > 0) {
      std::vector<cv::Point2d> rim;
      for (int k = 0; k < 90; ++k)
        rim.emplace_back(c.cx + c.r * std::cos(2 * kPi * k / 90), c.cy + c.r * std::sin(2 * kPi * k / 90));
      cone = FitConeRobust(rim, detect.focal_px, principal);
    }
  } else {
    try {
      const SphereDetection det = DetectSphere(img, detect);
      c = det.circle;
      cone = det.cone;
    } catch (const Error& e) {
      throw FileError(path, std::string(e.what()) +
                                " (a mirror ball's rim can vanish against its surroundings: "
                                "give --ball-circle cx,cy,r)");
    }
  }
  const BallCamera camera = detect.focal_px > 0 ? BallCamera::Perspective(img.cols, img.rows, detect.focal_px,
                                                                          principal, cone.centre_dir, cone.half_angle)
                                                : BallCamera::Orthographic(img.cols, img.rows, c.cx, c.cy, c.r);
  UnwrappedBall u = UnwrapMirrorBall(img, camera, width, ball);
  *j = {{"photo", path},
        {"cx", c.cx},
        {"cy", c.cy},
        {"r", c.r},
        {"circle_given", !where.circle.empty()},
        {"camera", camera.perspective() ? "perspective" : "orthographic"},
        {"reflectance", ball.reflectance},
        {"max_normal_deg", ball.max_normal_deg},
        {"camera_hole_deg", ball.camera_hole_deg},
        {"measured_fraction", cv::countNonZero(u.measured) / double(u.measured.total())}};
  if (camera.perspective())
    (*j)["perspective"] = {{"focal_px", camera.focal_px},
                           {"centre_dir", {cone.centre_dir.x, cone.centre_dir.y, cone.centre_dir.z}},
                           {"half_angle_rad", cone.half_angle}};
  return u;
}

// --rotate-matrix: nine numbers, row-major. Printed matrices carry 4–6 digits,
// so RᵀR may miss I by that much (then the rows are re-orthonormalised); a
// scale, a shear or a mirror is an error.
Rotation ParseRotationMatrix(const std::string& text) {
  const std::vector<double> v = ParseNumberList(text, 9, "--rotate-matrix", "r00,r01,...,r22 row-major");
  const Vec3 r0(v[0], v[1], v[2]), r1(v[3], v[4], v[5]), r2(v[6], v[7], v[8]);
  Rotation given;
  for (int i = 0; i < 9; ++i) given.m[i / 3][i % 3] = v[i];
  const double det = Dot(r0, Cross(r1, r2));
  if (given.OrthonormalityError() > 1e-3 || det < 0)
    throw Error("--rotate-matrix " + text + " is not a rotation (RᵀR differs from I by " +
                std::to_string(given.OrthonormalityError()) + ", det " + std::to_string(det) + ")");
  // Gram–Schmidt on the rows; the third is their cross product (det +1).
  const Vec3 x = Normalize(r0), y = Normalize(r1 - Dot(r1, x) * x), z = Cross(x, y);
  Rotation r;
  r.m = {{{x.x, x.y, x.z}, {y.x, y.y, y.z}, {z.x, z.y, z.z}}};
  return r;
}
}  // namespace

int CalibMain(int argc, char** argv) {
  std::string probe_path, layout = "latlong", rotate = "0,0,0", out = "probe.exr", sidecar, sun, sun_radiance = "1,1,1";
  std::string rotate_from_ball, rotate_matrix;
  BallLocation where;
  double sun_deg = 1.0;
  std::string scale_arg, card_photo, card_region, card_normal = "0,0,1", photo_merge, probe_merge;
  double card_albedo = 0.18;
  int width = 0;
  MirrorBallOptions ball;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path), "probe image (.exr/.hdr/.pfm)")
      ("sun", po::value(&sun), "instead of --probe: one distant light towards x,y,z (probe frame), e.g. a photometric-stereo LED")
      ("sun-radiance", po::value(&sun_radiance)->default_value(sun_radiance), "--sun's irradiance R,G,B at normal incidence")
      ("sun-size", po::value(&sun_deg)->default_value(sun_deg), "--sun's angular radius, degrees")
      ("layout", po::value(&layout)->default_value(layout), "latlong | angular | mirrorball (a photo of a chrome ball)")
      ("width", po::value(&width)->default_value(0), "lat-long width to write (0: as given, 512 for converted layouts)")
      ("rotate", po::value(&rotate)->default_value(rotate), "camera → probe rotation as yaw,pitch,roll degrees (util/rotation.h)")
      ("rotate-matrix", po::value(&rotate_matrix), "instead of --rotate: the camera → probe rotation as a row-major 3×3 matrix r00,r01,...,r22 (e.g. from a calibration tool)")
      ("rotate-from-ball", po::value(&rotate_from_ball), "instead of --rotate: estimate the rotation from this HDR photo of a mirror ball taken from the camera's position (calib/probe_alignment.h)")
      ("scale", po::value(&scale_arg), "photo radiance per probe radiance: s or R,G,B (default 1: probe and photo merged with one camera and response)")
      ("photo-merge", po::value(&photo_merge), "instead of --scale: the scale from exposure metadata, with --probe-merge: the sample photo's merge sidecar (from 'brdfshot merge')")
      ("probe-merge", po::value(&probe_merge), "the probe's merge sidecar (same camera)")
      ("card", po::value(&card_photo), "instead of --scale: measure it on a reference card in this linear photo (the merged HDR of the sample's shot)")
      ("card-region", po::value(&card_region), "--card's pixels x,y,w,h")
      ("card-albedo", po::value(&card_albedo)->default_value(card_albedo), "--card's diffuse reflectance (grey card 0.18)")
      ("card-normal", po::value(&card_normal)->default_value(card_normal), "--card's normal x,y,z in the camera frame (0,0,1: facing the camera)")
      ("ball-circle", po::value(&where.circle), "the mirror ball's circle cx,cy,r in pixels (default: detected)")
      ("ball-focal-px", po::value(&where.focal_px)->default_value(0), "focal length of the ball's photo in pixels: perspective ball (0: orthographic, right for a ball far away or small in the frame)")
      ("ball-focal-35mm", po::value(&where.focal_35mm)->default_value(0), "instead of --ball-focal-px: 35 mm-equivalent focal length (EXIF FocalLengthIn35mmFilm)")
      ("ball-reflectance", po::value(&ball.reflectance)->default_value(ball.reflectance), "mirror ball reflectance")
      ("ball-max-angle", po::value(&ball.max_normal_deg)->default_value(ball.max_normal_deg), "ball normals beyond this (deg) are the unreliable rim")
      ("ball-camera-hole", po::value(&ball.camera_hole_deg)->default_value(ball.camera_hole_deg), "ball normals within this (deg) of the camera show the camera: filled in")
      ("sidecar", po::value(&sidecar), "calibration JSON (default: <out>.json)")
      ("out,o", po::value(&out)->default_value(out), "lat-long probe (EXR)");
  // clang-format on
  if (!ParseOptions("calib",
                    "(--probe P [--layout L] | --sun x,y,z) [--rotate y,p,r | --rotate-from-ball B] [--scale s | "
                    "--photo-merge M --probe-merge M | --card PHOTO --card-region x,y,w,h] [options]",
                    desc, argc, argv))
    return 0;
  if (probe_path.empty() == sun.empty()) throw Error("calib: give exactly one of --probe and --sun");
  if (sidecar.empty()) sidecar = std::filesystem::path(out).replace_extension(".json").string();
  std::vector<double> a = ParseNumberList(rotate, 3, "--rotate", "yaw,pitch,roll in degrees");
  cv::Vec3d scale(1, 1, 1);
  if (!scale_arg.empty()) {
    const bool one = scale_arg.find(',') == std::string::npos;
    const std::vector<double> v = ParseNumberList(scale_arg, one ? 1 : 3, "--scale", "s or R,G,B");
    for (int c = 0; c < 3; ++c) scale[c] = v[one ? 0 : c];
    if (!(scale[0] > 0 && scale[1] > 0 && scale[2] > 0)) throw Error("--scale must be positive");
  }
  if (photo_merge.empty() != probe_merge.empty()) throw Error("calib: --photo-merge and --probe-merge go together");
  if (int(!scale_arg.empty()) + int(!card_photo.empty()) + int(!photo_merge.empty()) > 1)
    throw Error("calib: give at most one of --scale, --card and --photo-merge/--probe-merge");
  if (card_photo.empty() != card_region.empty()) throw Error("calib: --card and --card-region go together");
  if (int(rotate != "0,0,0") + int(!rotate_from_ball.empty()) + int(!rotate_matrix.empty()) > 1)
    throw Error("calib: give one of --rotate, --rotate-matrix and --rotate-from-ball");
  if (!where.circle.empty() && !rotate_from_ball.empty() && layout == "mirrorball")
    throw Error("calib: --ball-circle is ambiguous with both --layout mirrorball and --rotate-from-ball");
  Rotation rot = Rotation::FromYawPitchRoll(a[0], a[1], a[2]);
  if (!rotate_matrix.empty()) {
    rot = ParseRotationMatrix(rotate_matrix);
    const std::array<double, 3> ypr = rot.ToYawPitchRoll();
    a = {ypr[0], ypr[1], ypr[2]};
  }
  Calibration cal;
  cal.source = probe_path;
  cal.layout = layout;
  nlohmann::json& j = cal.provenance;
  LatLongProbe probe;
  if (!sun.empty()) {
    const std::vector<double> d = ParseNumberList(sun, 3, "--sun", "x,y,z");
    const std::vector<double> e = ParseNumberList(sun_radiance, 3, "--sun-radiance", "R,G,B");
    probe = SunProbe(Vec3(d[0], d[1], d[2]), cv::Vec3f(e[0], e[1], e[2]), sun_deg, width > 0 ? width : 512);
    cal.source = "sun " + sun;
    cal.layout = "sun";
    j["sun"] = {{"direction", d}, {"irradiance", e}, {"radius_deg", sun_deg}};
    probe_path = cal.source;
  } else if (layout == "latlong") {
    probe = LatLongProbe::Read(probe_path);
    if (width > 0) probe = probe.Resized(width);
  } else if (layout == "angular") {
    const cv::Mat img = ReadHdrImage(probe_path);
    if (img.cols != img.rows) throw FileError(probe_path, "an angular map must be square");
    probe = AngularMapToLatLong(img, width > 0 ? width : 512);
  } else if (layout == "mirrorball") {
    nlohmann::json jb;
    probe = UnwrapBallPhoto(probe_path, where, width > 0 ? width : 512, ball, &jb).probe;
    j["ball"] = jb;
  } else {
    throw Error("unknown --layout '" + layout + "': expected latlong, angular or mirrorball");
  }
  if (!rotate_from_ball.empty()) {
    nlohmann::json jb;
    const UnwrappedBall u = UnwrapBallPhoto(rotate_from_ball, where, 256, ball, &jb);
    const RotationFit fit = EstimateRotation(probe, u.probe, u.measured);
    rot = fit.rotation;
    a = {fit.yaw, fit.pitch, fit.roll};
    jb["rms_log_radiance"] = fit.rms_log;
    j["rotation_from_ball"] = jb;
  }
  if (!card_photo.empty()) {
    const std::vector<double> r = ParseNumberList(card_region, 4, "--card-region", "x,y,w,h in pixels");
    const std::vector<double> n = ParseNumberList(card_normal, 3, "--card-normal", "x,y,z");
    const ReferenceCard card{
        cv::Rect(static_cast<int>(r[0]), static_cast<int>(r[1]), static_cast<int>(r[2]), static_cast<int>(r[3])),
        card_albedo, Vec3(n[0], n[1], n[2])};
    if (!(Length(card.normal_camera) > 0)) throw Error("--card-normal must not be zero");
    RadiometricScale rs;
    try {
      rs = ScaleFromReferenceCard(ReadHdrImage(card_photo), card, probe, rot);
    } catch (const Error& e) {
      throw FileError(card_photo, e.what());
    }
    scale = rs.scale;
    j["scale_from_card"] = {{"photo", card_photo},
                            {"region", r},
                            {"albedo", card_albedo},
                            {"normal_camera", n},
                            {"measured", {rs.measured[0], rs.measured[1], rs.measured[2]}},
                            {"predicted", {rs.predicted[0], rs.predicted[1], rs.predicted[2]}},
                            {"luminance_spread", rs.spread},
                            {"pixels", rs.pixels}};
    std::printf("reference card: %d px, mean %.4g %.4g %.4g, a/pi E %.4g %.4g %.4g, spread %.1f %%\n", rs.pixels,
                rs.measured[0], rs.measured[1], rs.measured[2], rs.predicted[0], rs.predicted[1], rs.predicted[2],
                100 * rs.spread);
    if (rs.spread > 0.1)
      std::fprintf(stderr,
                   "warning: %s: the card region varies by %.0f %% (std/mean): is it all card, evenly lit and flat?\n",
                   card_photo.c_str(), 100 * rs.spread);
  }
  if (!photo_merge.empty()) {
    const RadiometricScale rs =
        ScaleFromMergeSidecars(ReadJsonFile(photo_merge), photo_merge, ReadJsonFile(probe_merge), probe_merge);
    scale = rs.scale;
    j["scale_from_merges"] = {{"photo", photo_merge}, {"probe", probe_merge}, {"response_ratio_spread", rs.spread}};
    if (rs.spread > 0.05)
      std::fprintf(stderr,
                   "warning: %s, %s: the two response curves differ in shape by %.0f %% over the mid codes; "
                   "merge the photo with the probe's --response, or use --card\n",
                   photo_merge.c_str(), probe_merge.c_str(), 100 * rs.spread);
  }
  WriteExr(out, probe.rgb());
  cal.probe = out;
  cal.width = probe.width();
  cal.camera_to_probe = rot;
  cal.yaw_pitch_roll_deg = {a[0], a[1], a[2]};
  cal.scale = scale;
  cal.Write(sidecar);
  std::printf(
      "probe %s (%s) -> %dx%d lat-long; rotation yaw %.2f pitch %.2f roll %.2f deg, scale %g %g %g\n"
      "wrote %s, %s\n",
      probe_path.c_str(), layout.c_str(), probe.width(), probe.height(), a[0], a[1], a[2], scale[0], scale[1], scale[2],
      out.c_str(), sidecar.c_str());
  return 0;
}

}  // namespace brdfshot
