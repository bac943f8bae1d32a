#include "fit/synthetic_capture.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/mirror_ball.h"
#include "capture/exposure.h"
#include "util/atomic_file.h"
#include "util/image_io.h"

#include "normals/circle_fit.h"
#include "util/check.h"

namespace brdfshot {

SphereView ShotView(const SphereShot& s) {
  BRDFSHOT_CHECK(s.width > 0 && s.height > 0 && s.focal_px > 0 && s.radius_px > 0, "bad SphereShot");
  SphereView v;
  v.width = s.width;
  v.height = s.height;
  v.perspective = true;
  v.focal_px = s.focal_px;
  v.principal = {s.width / 2.0, s.height / 2.0};
  // A unit sphere whose cone of tangent rays has half-angle α = atan(r / f):
  // its apparent circle then has about the asked radius (exactly on axis).
  v.cone = {PixelRay(s.centre_px, s.focal_px, v.principal), std::atan(s.radius_px / s.focal_px)};
  v.circle = ApparentCircle(v.cone, v.focal_px, v.principal);
  return v;
}

SyntheticPhoto RenderSphereShot(const MerlBrdf& brdf, const LatLongProbe& probe, const SphereShot& s,
                                const RenderQuality& quality) {
  SyntheticPhoto out;
  out.view = ShotView(s);
  const SphereView& v = out.view;
  cv::Mat img(s.height, s.width, CV_32FC3);
  // Background: the environment along each pixel's ray (probe frame).
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      img.at<cv::Vec3f>(y, x) =
          probe.Bilinear(s.camera_to_probe(PixelRay({x + 0.5, y + 0.5}, v.focal_px, v.principal)));

  // Sphere samples: one per pixel inside, rim_supersample² where the rim
  // crosses the pixel, all rendered in one operator, then box-filtered.
  PixelGeometry g;
  g.width = s.width;
  g.height = s.height;
  struct Target {
    int x, y;
    float weight;
  };
  std::vector<Target> target;
  std::vector<std::pair<cv::Point, float>> background_share;  // rim pixels: how much background stays
  const int k = std::max(1, s.rim_supersample);
  const cv::Rect box = v.Bounds(2);
  auto add = [&](int x, int y, double px, double py, float w) {
    Vec3 n, o;
    if (!v.Trace(px, py, &n, &o)) return false;
    g.x.push_back(x);
    g.y.push_back(y);
    g.normal.push_back(s.camera_to_probe(n));
    g.view.push_back(s.camera_to_probe(o));
    target.push_back({x, y, w});
    return true;
  };
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const double inside = v.RimDistance(x + 0.5, y + 0.5);
      if (inside > 1.0) {
        add(x, y, x + 0.5, y + 0.5, 1.0f);
      } else if (inside > -1.0) {
        int hits = 0;
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) hits += add(x, y, x + (i + 0.5) / k, y + (j + 0.5) / k, 1.0f / (k * k));
        background_share.push_back({{x, y}, 1.0f - static_cast<float>(hits) / (k * k)});
      }
    }
  for (const auto& [p, share] : background_share) img.at<cv::Vec3f>(p) *= share;
  for (const Target& t : target)
    if (t.weight == 1.0f) img.at<cv::Vec3f>(t.y, t.x) = cv::Vec3f(0, 0, 0);
  const Eigen::MatrixXd rgb = TransportOperator::Build(g, probe, brdf.grid(), quality).Render(brdf);
  for (size_t i = 0; i < target.size(); ++i) {
    cv::Vec3f& px = img.at<cv::Vec3f>(target[i].y, target[i].x);
    for (int c = 0; c < 3; ++c) px[c] += target[i].weight * static_cast<float>(std::max(0.0, rgb(i, c)));
  }
  if (s.blur_sigma > 0) cv::GaussianBlur(img, img, cv::Size(), s.blur_sigma);
  out.radiance = img;
  return out;
}

namespace {
namespace fs = std::filesystem;

// One bracket, frame by frame: camera → file (atomic) → EXIF. Returns the names.
std::vector<std::string> WriteBracket(const cv::Mat& radiance, const std::vector<double>& times,
                                      const SyntheticCaptureOptions& o, const CameraModel& camera, const fs::path& dir,
                                      const std::string& prefix, double focal_35mm) {
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(dir))  // a re-run must not leave frames of an older bracket
    if (e.path().filename().string().rfind(prefix, 0) == 0) fs::remove(e.path());
  const std::vector<cv::Mat> frames = SimulateBracket(radiance, times, camera);
  std::vector<std::string> names;
  for (size_t j = 0; j < frames.size(); ++j) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%02zu.%s", prefix.c_str(), j + 1, o.jpeg ? "jpg" : "png");
    const std::string path = (dir / name).string();
    cv::Mat bgr;
    cv::cvtColor(frames[j], bgr, cv::COLOR_RGB2BGR);
    ExifInfo exif;
    exif.exposure_time = times[j];
    exif.f_number = 8;
    exif.iso = 100;
    exif.focal_35mm = focal_35mm;
    exif.camera = "brdfshot synthetic";
    WriteFileAtomicByName(path, [&](const std::string& tmp) {
      const std::vector<int> params = {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality};
      if (!cv::imwrite(tmp, bgr, o.jpeg ? params : std::vector<int>{})) throw Error("OpenCV could not encode");
      WriteExif(tmp, exif);
    });
    names.push_back(name);
  }
  return names;
}

std::string NumberList(const std::array<double, 3>& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%g,%g,%g", v[0], v[1], v[2]);
  return buf;
}

// The capture's config, in Make syntax so samples/Makefile can include it; a
// real capture folder has the same file, written by hand. `ball_circle`: where
// the ball is in ball.exr, as a user marks it on a real one (a mirror ball's
// rim need not stand out from its surround); empty without a ball.
void WriteCaptureMk(const fs::path& path, const SyntheticCaptureOptions& o, const std::string& ball_circle) {
  WriteFileAtomic(path.string(), [&](std::ostream& out) {
    out << "# brdfshot capture folder: photo/ (bracket of the sphere), probe/ (bracket of the probe).\n"
        << "# Written by: " << o.command << "\n"
        << "FOCAL_PX     = " << o.shot.focal_px << "\n"
        << "ROTATE       = " << NumberList(o.yaw_pitch_roll_deg) << "\n";
    if (!ball_circle.empty())
      out << "# The pipeline estimates the rotation from this mirror-ball photo (ROTATE, the\n"
          << "# truth, is then used only by PERFECT=1 runs); it was shot with the photo's lens.\n"
          << "BALL_FILE    = ball.exr\nBALL_CIRCLE  = " << ball_circle << "\n"
          << "BALL_FOCAL_PX = " << o.shot.focal_px << "\n";
    out << "PROBE_LAYOUT = latlong\n"
        << "# Synthetic only: the true material, for the report's error against the truth.\n"
        << "TRUTH        = " << o.material_args << "\n";
  });
}

}  // namespace

SyntheticCapture WriteSyntheticCapture(const MerlBrdf& brdf, const LatLongProbe& probe,
                                       const SyntheticCaptureOptions& o, const std::string& out) {
  BRDFSHOT_CHECK(o.mirror_ball == 0 || o.mirror_ball > 1, "a mirror ball needs more than a pixel");
  SyntheticCapture result;
  result.photo = RenderSphereShot(brdf, probe, o.shot, o.quality);
  const fs::path dir(out);
  fs::create_directories(dir / "truth");
  SyntheticCaptureTruth truth;
  truth.photo_times = CoveringBracketTimes(result.photo.radiance, o.stops);
  result.photo_frames = WriteBracket(result.photo.radiance, truth.photo_times, o, o.camera, dir / "photo", "IMG_",
                                     o.shot.focal_px * 36 / std::max(o.shot.width, o.shot.height));
  // The probe shot with the same camera (a lat-long panorama bracket), so the
  // merged probe and photo share one response and hence one radiometric scale.
  const LatLongProbe pano = probe.Resized(o.probe_shot_width);
  CameraModel probe_camera = o.camera;
  probe_camera.seed = o.camera.seed + 1;
  truth.probe_times = CoveringBracketTimes(pano.rgb(), o.stops);
  result.probe_frames = WriteBracket(pano.rgb(), truth.probe_times, o, probe_camera, dir / "probe", "PANO_", 0);
  result.probe_shot = pano.rgb().size();

  std::string ball_circle;
  if (o.mirror_ball > 0) {
    // The lighting as the camera sees it, L_cam(d) = L_probe(R d), in a ball
    // framed by a black border, shot with the capture's lens (perspective) on
    // its optical axis.
    const int pad = std::max(8, o.mirror_ball / 10), side = o.mirror_ball + 2 * pad;
    const double r = o.mirror_ball / 2.0, c = side / 2.0;
    const BallCamera lens =
        BallCamera::Perspective(side, side, o.shot.focal_px, {c, c}, Vec3(0, 0, -1), std::atan(r / o.shot.focal_px));
    WriteExr((dir / "ball.exr").string(), RenderMirrorBall(probe.Rotated(o.shot.camera_to_probe), lens));
    ball_circle = std::to_string(c) + "," + std::to_string(c) + "," + std::to_string(r);
  }
  WriteExr((dir / "truth" / "photo.exr").string(), result.photo.radiance);
  WriteExr((dir / "truth" / "probe.exr").string(), pano.rgb());
  WriteFileAtomic((dir / "truth" / "sphere.json").string(),
                  [&](std::ostream& s) { s << result.photo.view.ToJson().dump(1) << "\n"; });
  truth.material = o.material;
  truth.material_args = o.material_args;
  truth.probe = o.probe_path;
  truth.yaw_pitch_roll_deg = o.yaw_pitch_roll_deg;
  truth.camera_to_probe = o.shot.camera_to_probe;
  truth.sphere = result.photo.view;
  truth.camera = o.camera;
  truth.render_quality = o.quality.Describe();
  truth.command = o.command;
  truth.Write((dir / "truth" / "truth.json").string());
  WriteCaptureMk(dir / "capture.mk", o, ball_circle);
  return result;
}

nlohmann::json SyntheticCaptureTruth::ToJson() const {
  return {{"format", "brdfshot-synthetic-capture-1"},
          {"material", material},
          {"material_args", material_args},
          {"probe", probe},
          {"yaw_pitch_roll_deg", yaw_pitch_roll_deg},
          {"rotation_camera_to_probe", camera_to_probe.m},
          {"sphere", sphere.ToJson()},
          {"photo_times", photo_times},
          {"probe_times", probe_times},
          {"camera",
           {{"gamma", camera.gamma},
            {"shoulder", camera.shoulder},
            {"full_well", camera.full_well},
            {"read_noise", camera.read_noise},
            {"raw_bits", camera.raw_bits},
            {"seed", camera.seed}}},
          {"render_quality", render_quality},
          {"command", command}};
}

SyntheticCaptureTruth SyntheticCaptureTruth::FromJson(const nlohmann::json& j, const std::string& source) {
  try {
    if (!HasFormat(j, "brdfshot-synthetic-capture-1"))
      throw FileError(source, "is not a synthetic capture's truth (format brdfshot-synthetic-capture-1)");
    SyntheticCaptureTruth t;
    t.material = j.at("material");
    t.material_args = j.at("material_args");
    t.probe = j.at("probe");
    t.yaw_pitch_roll_deg = j.at("yaw_pitch_roll_deg");
    t.camera_to_probe.m = j.at("rotation_camera_to_probe");
    t.sphere = SphereView::FromJson(j.at("sphere"), source);
    t.photo_times = j.at("photo_times").get<std::vector<double>>();
    t.probe_times = j.at("probe_times").get<std::vector<double>>();
    const nlohmann::json& c = j.at("camera");
    t.camera.gamma = c.at("gamma");
    t.camera.shoulder = c.at("shoulder");
    t.camera.full_well = c.at("full_well");
    t.camera.read_noise = c.at("read_noise");
    t.camera.raw_bits = c.at("raw_bits");
    t.camera.seed = c.at("seed");
    t.render_quality = j.at("render_quality");
    t.command = j.at("command");
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("bad synthetic capture truth: ") + e.what());
  }
}

void SyntheticCaptureTruth::Write(const std::string& path) const {
  const std::string text = ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& o) { o << text << "\n"; });
}

SyntheticCaptureTruth SyntheticCaptureTruth::Read(const std::string& path) {
  return FromJson(ReadJsonFile(path), path);
}

}  // namespace brdfshot
