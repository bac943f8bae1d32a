#include "calib/calibrate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "calib/probe_alignment.h"
#include "calib/probe_layout.h"
#include "calib/sun_probe.h"
#include "normals/sphere_detect.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

std::string Percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f %%", 100 * fraction);
  return buf;
}

// "sun x,y,z": the calibration's source for a generated sun.
std::string SunSource(const SunLight& s) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "sun %g,%g,%g", s.direction.x, s.direction.y, s.direction.z);
  return buf;
}

// A photographed mirror ball, unwrapped to lat-long in the camera's frame.
// With a focal length the ball is seen in perspective: a marked circle is
// taken as its silhouette and the cone fitted to it. The circle and options
// go into `record`.
UnwrappedBall UnwrapBallPhoto(const std::string& path, const BallLocation& where, int width,
                              const MirrorBallOptions& ball, nlohmann::json* record) {
  const cv::Mat img = ReadHdrImage(path);
  SphereDetectOptions detect;
  detect.focal_px = where.focal_35mm > 0 ? FocalPxFrom35mm(where.focal_35mm, img.size()) : where.focal_px;
  const cv::Point2d principal(img.cols / 2.0, img.rows / 2.0);
  Circle c;
  SphereCone cone;
  if (where.circle) {
    c = *where.circle;
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
  *record = {{"photo", path},
             {"cx", c.cx},
             {"cy", c.cy},
             {"r", c.r},
             {"circle_given", where.circle.has_value()},
             {"camera", camera.perspective() ? "perspective" : "orthographic"},
             {"reflectance", ball.reflectance},
             {"max_normal_deg", ball.max_normal_deg},
             {"camera_hole_deg", ball.camera_hole_deg},
             {"measured_fraction", cv::countNonZero(u.measured) / double(u.measured.total())}};
  if (camera.perspective())
    (*record)["perspective"] = {{"focal_px", camera.focal_px},
                                {"centre_dir", {cone.centre_dir.x, cone.centre_dir.y, cone.centre_dir.z}},
                                {"half_angle_rad", cone.half_angle}};
  return u;
}

// The probe in lat-long, from a file in the given layout or a generated sun.
LatLongProbe ReadProbe(const CalibrateOptions& o, Calibration* cal) {
  if (o.sun) {
    const SunLight& s = *o.sun;
    cal->provenance["sun"] = {{"direction", {s.direction.x, s.direction.y, s.direction.z}},
                              {"irradiance", {s.irradiance[0], s.irradiance[1], s.irradiance[2]}},
                              {"radius_deg", s.radius_deg}};
    return SunProbe(s.direction, cv::Vec3f(s.irradiance), s.radius_deg, o.width > 0 ? o.width : 512);
  }
  if (o.layout == "latlong") {
    const LatLongProbe probe = LatLongProbe::Read(o.probe_path);
    return o.width > 0 ? probe.Resized(o.width) : probe;
  }
  if (o.layout == "angular") {
    const cv::Mat img = ReadHdrImage(o.probe_path);
    if (img.cols != img.rows) throw FileError(o.probe_path, "an angular map must be square");
    return AngularMapToLatLong(img, o.width > 0 ? o.width : 512);
  }
  if (o.layout == "mirrorball") {
    nlohmann::json record;
    LatLongProbe probe =
        UnwrapBallPhoto(o.probe_path, o.ball_location, o.width > 0 ? o.width : 512, o.ball, &record).probe;
    cal->provenance["ball"] = record;
    return probe;
  }
  throw Error("unknown --layout '" + o.layout + "': expected latlong, angular or mirrorball");
}

}  // namespace

double FocalPxFrom35mm(double focal_35mm, cv::Size photo) {
  return focal_35mm / 36.0 * std::max(photo.width, photo.height);
}

CalibrateResult Calibrate(const CalibrateOptions& o) {
  BRDFSHOT_CHECK(o.sun.has_value() != !o.probe_path.empty());
  CalibrateResult result;
  Calibration& cal = result.calibration;
  cal.source = o.sun ? SunSource(*o.sun) : o.probe_path;
  cal.layout = o.sun ? "sun" : o.layout;
  cal.camera_to_probe = o.camera_to_probe;
  cal.yaw_pitch_roll_deg = o.yaw_pitch_roll_deg;
  cal.scale = o.scale;
  result.probe = ReadProbe(o, &cal);
  cal.width = result.probe.width();
  nlohmann::json& record = cal.provenance;

  if (!o.rotation_from_ball.empty()) {
    nlohmann::json ball;
    const UnwrappedBall u = UnwrapBallPhoto(o.rotation_from_ball, o.ball_location, 256, o.ball, &ball);
    const RotationFit fit = EstimateRotation(result.probe, u.probe, u.measured);
    cal.camera_to_probe = fit.rotation;
    cal.yaw_pitch_roll_deg = {fit.yaw, fit.pitch, fit.roll};
    ball["rms_log_radiance"] = fit.rms_log;
    record["rotation_from_ball"] = ball;
  }
  if (!o.card_photo.empty()) {
    RadiometricScale rs;
    try {
      rs = ScaleFromReferenceCard(ReadHdrImage(o.card_photo), o.card, result.probe, cal.camera_to_probe);
    } catch (const Error& e) {
      throw FileError(o.card_photo, e.what());
    }
    cal.scale = rs.scale;
    const cv::Rect& r = o.card.region;
    const Vec3& n = o.card.normal_camera;
    record["scale_from_card"] = {{"photo", o.card_photo},
                                 {"region", {double(r.x), double(r.y), double(r.width), double(r.height)}},
                                 {"albedo", o.card.albedo},
                                 {"normal_camera", {n.x, n.y, n.z}},
                                 {"measured", {rs.measured[0], rs.measured[1], rs.measured[2]}},
                                 {"predicted", {rs.predicted[0], rs.predicted[1], rs.predicted[2]}},
                                 {"luminance_spread", rs.spread},
                                 {"pixels", rs.pixels}};
    if (rs.spread > 0.1)
      result.warnings.push_back(o.card_photo + ": the card region varies by " + Percent(rs.spread) +
                                " (std/mean): is it all card, evenly lit and flat?");
    result.card = rs;
  }
  if (!o.photo_merge.empty()) {
    const RadiometricScale rs =
        ScaleFromMergeSidecars(ReadJsonFile(o.photo_merge), o.photo_merge, ReadJsonFile(o.probe_merge), o.probe_merge);
    cal.scale = rs.scale;
    record["scale_from_merges"] = {
        {"photo", o.photo_merge}, {"probe", o.probe_merge}, {"response_ratio_spread", rs.spread}};
    if (rs.spread > 0.05)
      result.warnings.push_back(o.photo_merge + ", " + o.probe_merge + ": the two response curves differ in shape by " +
                                Percent(rs.spread) +
                                " over the mid codes; merge the photo with the probe's --response, or use --card");
  }
  return result;
}

}  // namespace brdfshot
