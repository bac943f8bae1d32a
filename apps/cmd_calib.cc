// brdfshot calib: the light probe in the pipeline's lat-long frame and its
// relation to the camera (calib/calibrate.h).
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "apps/common_options.h"
#include "calib/calibrate.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/rotation.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

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

// The command line as typed; ToOptions checks it and turns it into the stage's options.
struct CalibArgs {
  std::string probe, layout = "latlong", rotate = "0,0,0", rotate_matrix, rotate_from_ball, out = "probe.exr", sidecar;
  std::string sun, sun_radiance = "1,1,1", scale, card_photo, card_region, card_normal = "0,0,1", photo_merge,
                   probe_merge, ball_circle;
  double sun_deg = 1.0, card_albedo = 0.18, ball_focal_px = 0, ball_focal_35mm = 0;
  int width = 0;
  MirrorBallOptions ball;

  void Add(po::options_description& desc) {
    // clang-format off
    desc.add_options()
        ("probe,p", po::value(&probe), "probe image (.exr/.hdr/.pfm)")
        ("sun", po::value(&sun), "instead of --probe: one distant light towards x,y,z (probe frame), e.g. a photometric-stereo LED")
        ("sun-radiance", po::value(&sun_radiance)->default_value(sun_radiance), "--sun's irradiance R,G,B at normal incidence")
        ("sun-size", po::value(&sun_deg)->default_value(sun_deg), "--sun's angular radius, degrees")
        ("layout", po::value(&layout)->default_value(layout), "latlong | angular | mirrorball (a photo of a chrome ball)")
        ("width", po::value(&width)->default_value(0), "lat-long width to write (0: as given, 512 for converted layouts)")
        ("rotate", po::value(&rotate)->default_value(rotate), "camera → probe rotation as yaw,pitch,roll degrees (util/rotation.h)")
        ("rotate-matrix", po::value(&rotate_matrix), "instead of --rotate: the camera → probe rotation as a row-major 3×3 matrix r00,r01,...,r22 (e.g. from a calibration tool)")
        ("rotate-from-ball", po::value(&rotate_from_ball), "instead of --rotate: estimate the rotation from this HDR photo of a mirror ball taken from the camera's position (calib/probe_alignment.h)")
        ("scale", po::value(&scale), "photo radiance per probe radiance: s or R,G,B (default 1: probe and photo merged with one camera and response)")
        ("photo-merge", po::value(&photo_merge), "instead of --scale: the scale from exposure metadata, with --probe-merge: the sample photo's merge sidecar (from 'brdfshot merge')")
        ("probe-merge", po::value(&probe_merge), "the probe's merge sidecar (same camera)")
        ("card", po::value(&card_photo), "instead of --scale: measure it on a reference card in this linear photo (the merged HDR of the sample's shot)")
        ("card-region", po::value(&card_region), "--card's pixels x,y,w,h")
        ("card-albedo", po::value(&card_albedo)->default_value(card_albedo), "--card's diffuse reflectance (grey card 0.18)")
        ("card-normal", po::value(&card_normal)->default_value(card_normal), "--card's normal x,y,z in the camera frame (0,0,1: facing the camera)")
        ("ball-circle", po::value(&ball_circle), "the mirror ball's circle cx,cy,r in pixels (default: detected)")
        ("ball-focal-px", po::value(&ball_focal_px)->default_value(0), "focal length of the ball's photo in pixels: perspective ball (0: orthographic, right for a ball far away or small in the frame)")
        ("ball-focal-35mm", po::value(&ball_focal_35mm)->default_value(0), "instead of --ball-focal-px: 35 mm-equivalent focal length (EXIF FocalLengthIn35mmFilm)")
        ("ball-reflectance", po::value(&ball.reflectance)->default_value(ball.reflectance), "mirror ball reflectance")
        ("ball-max-angle", po::value(&ball.max_normal_deg)->default_value(ball.max_normal_deg), "ball normals beyond this (deg) are the unreliable rim")
        ("ball-camera-hole", po::value(&ball.camera_hole_deg)->default_value(ball.camera_hole_deg), "ball normals within this (deg) of the camera show the camera: filled in")
        ("sidecar", po::value(&sidecar), "calibration JSON (default: <out>.json)")
        ("out,o", po::value(&out)->default_value(out), "lat-long probe (EXR)");
    // clang-format on
  }

  CalibrateOptions ToOptions() const {
    if (probe.empty() == sun.empty()) throw Error("calib: give exactly one of --probe and --sun");
    if (photo_merge.empty() != probe_merge.empty()) throw Error("calib: --photo-merge and --probe-merge go together");
    if (int(!scale.empty()) + int(!card_photo.empty()) + int(!photo_merge.empty()) > 1)
      throw Error("calib: give at most one of --scale, --card and --photo-merge/--probe-merge");
    if (card_photo.empty() != card_region.empty()) throw Error("calib: --card and --card-region go together");
    if (int(rotate != "0,0,0") + int(!rotate_from_ball.empty()) + int(!rotate_matrix.empty()) > 1)
      throw Error("calib: give one of --rotate, --rotate-matrix and --rotate-from-ball");
    if (!ball_circle.empty() && !rotate_from_ball.empty() && layout == "mirrorball")
      throw Error("calib: --ball-circle is ambiguous with both --layout mirrorball and --rotate-from-ball");
    CalibrateOptions o;
    o.probe_path = probe;
    o.layout = layout;
    o.width = width;
    if (!sun.empty()) {
      const std::vector<double> d = ParseNumberList(sun, 3, "--sun", "x,y,z");
      const std::vector<double> e = ParseNumberList(sun_radiance, 3, "--sun-radiance", "R,G,B");
      o.sun = SunLight{Vec3(d[0], d[1], d[2]), cv::Vec3d(e[0], e[1], e[2]), sun_deg};
    }
    const std::vector<double> a = ParseNumberList(rotate, 3, "--rotate", "yaw,pitch,roll in degrees");
    o.camera_to_probe = Rotation::FromYawPitchRoll(a[0], a[1], a[2]);
    o.yaw_pitch_roll_deg = {a[0], a[1], a[2]};
    if (!rotate_matrix.empty()) {
      o.camera_to_probe = ParseRotationMatrix(rotate_matrix);
      o.yaw_pitch_roll_deg = o.camera_to_probe.ToYawPitchRoll();
    }
    o.rotation_from_ball = rotate_from_ball;
    if (!scale.empty()) {
      const bool one = scale.find(',') == std::string::npos;
      const std::vector<double> v = ParseNumberList(scale, one ? 1 : 3, "--scale", "s or R,G,B");
      for (int c = 0; c < 3; ++c) o.scale[c] = v[one ? 0 : c];
      if (!(o.scale[0] > 0 && o.scale[1] > 0 && o.scale[2] > 0)) throw Error("--scale must be positive");
    }
    if (!card_photo.empty()) {
      const std::vector<double> r = ParseNumberList(card_region, 4, "--card-region", "x,y,w,h in pixels");
      const std::vector<double> n = ParseNumberList(card_normal, 3, "--card-normal", "x,y,z");
      o.card_photo = card_photo;
      o.card = {
          cv::Rect(static_cast<int>(r[0]), static_cast<int>(r[1]), static_cast<int>(r[2]), static_cast<int>(r[3])),
          card_albedo, Vec3(n[0], n[1], n[2])};
      if (!(Length(o.card.normal_camera) > 0)) throw Error("--card-normal must not be zero");
    }
    o.photo_merge = photo_merge;
    o.probe_merge = probe_merge;
    if (!ball_circle.empty()) {
      const std::vector<double> v = ParseNumberList(ball_circle, 3, "--ball-circle", "cx,cy,r in pixels");
      if (!(v[2] > 1)) throw Error("--ball-circle: the radius must be more than a pixel");
      o.ball_location.circle = Circle{v[0], v[1], v[2]};
    }
    FocalLengthPx(ball_focal_px, ball_focal_35mm, {1, 1}, "ball-");  // the same checks as every focal option
    o.ball_location.focal_px = ball_focal_px;
    o.ball_location.focal_35mm = ball_focal_35mm;
    o.ball = ball;
    return o;
  }
};

}  // namespace

int CalibMain(int argc, char** argv) {
  CalibArgs args;
  po::options_description desc("options");
  args.Add(desc);
  if (!ParseOptions("calib",
                    "(--probe P [--layout L] | --sun x,y,z) [--rotate y,p,r | --rotate-from-ball B] [--scale s | "
                    "--photo-merge M --probe-merge M | --card PHOTO --card-region x,y,w,h] [options]",
                    desc, argc, argv))
    return 0;
  const std::string sidecar =
      args.sidecar.empty() ? std::filesystem::path(args.out).replace_extension(".json").string() : args.sidecar;
  CalibrateResult r = Calibrate(args.ToOptions());
  if (r.card)
    std::printf("reference card: %d px, mean %.4g %.4g %.4g, a/pi E %.4g %.4g %.4g, spread %.1f %%\n", r.card->pixels,
                r.card->measured[0], r.card->measured[1], r.card->measured[2], r.card->predicted[0],
                r.card->predicted[1], r.card->predicted[2], 100 * r.card->spread);
  for (const std::string& w : r.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  WriteExr(args.out, r.probe.rgb());
  Calibration& cal = r.calibration;
  cal.probe = args.out;
  cal.Write(sidecar);
  const std::array<double, 3>& a = cal.yaw_pitch_roll_deg;
  std::printf(
      "probe %s (%s) -> %dx%d lat-long; rotation yaw %.2f pitch %.2f roll %.2f deg, scale %g %g %g\n"
      "wrote %s, %s\n",
      cal.source.c_str(), cal.layout.c_str(), r.probe.width(), r.probe.height(), a[0], a[1], a[2], cal.scale[0],
      cal.scale[1], cal.scale[2], args.out.c_str(), sidecar.c_str());
  return 0;
}

}  // namespace brdfshot
