// brdfshot synth-capture: a capture folder as a photographer would bring it
// back — bracketed JPEGs (EXIF exposure) of a sphere of a known material under
// a probe, bracketed frames of the probe itself, a small config file — plus the
// truth, so every stage after it can be measured.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/brdf_source.h"
#include "apps/command.h"
#include "apps/common_options.h"
#include "apps/synthetic_capture.h"
#include "calib/mirror_ball.h"
#include "capture/exposure.h"
#include "capture/synthetic_bracket.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

struct FrameFormat {
  bool jpeg = true;
  int jpeg_quality = 95;
};

// One bracket, frame by frame: camera → file (atomic) → EXIF. Returns the names.
std::vector<std::string> WriteBracket(const cv::Mat& radiance, const std::vector<double>& times,
                                      const CameraModel& camera, const FrameFormat& format, const fs::path& dir,
                                      const std::string& prefix, double focal_35mm) {
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(dir))  // a re-run must not leave frames of an older bracket
    if (e.path().filename().string().rfind(prefix, 0) == 0) fs::remove(e.path());
  const std::vector<cv::Mat> frames = SimulateBracket(radiance, times, camera);
  std::vector<std::string> names;
  for (size_t j = 0; j < frames.size(); ++j) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%02zu.%s", prefix.c_str(), j + 1, format.jpeg ? "jpg" : "png");
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
      const std::vector<int> params = {cv::IMWRITE_JPEG_QUALITY, format.jpeg_quality};
      if (!cv::imwrite(tmp, bgr, format.jpeg ? params : std::vector<int>{})) throw Error("OpenCV could not encode");
      WriteExif(tmp, exif);
    });
    names.push_back(name);
  }
  return names;
}

}  // namespace

int SynthCaptureMain(int argc, char** argv) {
  DatabaseArgs db;
  QualityArgs quality;
  BrdfSourceArgs src;
  std::string probe_path, out = "capture", size = "640x480", at, rotate = "0,0,0", format_name = "jpg";
  SphereShot shot;
  CameraModel camera;
  FrameFormat format;
  double stops = 2;
  int probe_width = 512, mirror_ball = 0;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("probe,p", po::value(&probe_path)->required(), "lat-long light probe (the scene's true lighting)")
      ("out,o", po::value(&out)->default_value(out), "capture folder to write")
      ("size", po::value(&size)->default_value(size), "photo size WxH")
      ("radius", po::value(&shot.radius_px)->default_value(shot.radius_px), "apparent sphere radius, px")
      ("focal-px", po::value(&shot.focal_px)->default_value(shot.focal_px), "focal length, px")
      ("at", po::value(&at), "where the sphere's centre appears, x,y px (default: right of and above the centre)")
      ("rotate", po::value(&rotate)->default_value(rotate), "camera -> probe yaw,pitch,roll degrees")
      ("blur", po::value(&shot.blur_sigma)->default_value(shot.blur_sigma), "lens blur sigma, px")
      ("format", po::value(&format_name)->default_value(format_name), "jpg (8-bit through a response curve) | png16 (linear 14-bit RAW-like)")
      ("jpeg-quality", po::value(&format.jpeg_quality)->default_value(format.jpeg_quality), "JPEG quality")
      ("stops", po::value(&stops)->default_value(stops), "bracket step in stops")
      ("full-well", po::value(&camera.full_well)->default_value(camera.full_well), "sensor full well, electrons")
      ("read-noise", po::value(&camera.read_noise)->default_value(camera.read_noise), "read noise, electrons RMS")
      ("seed", po::value(&camera.seed)->default_value(camera.seed), "noise seed")
      ("probe-shot-width", po::value(&probe_width)->default_value(probe_width), "width of the probe's own bracket (lat-long panorama; the rendering quality's --probe-width is separate)")
      ("mirror-ball", po::value(&mirror_ball)->default_value(0), "also write ball.exr: a mirror ball this many px across, shot from the camera (linear HDR), and let capture.mk estimate the rotation from it instead of stating it");
  // clang-format on
  src.Add(desc);
  db.Add(desc);
  quality.Add(desc);
  if (!ParseOptions("synth-capture", "--probe P (--standin N | --nbrdf N | --merl F) -o DIR [options]", desc, argc,
                    argv))
    return 0;
  if (format_name != "jpg" && format_name != "png16")
    throw Error("unknown --format '" + format_name + "': expected jpg or png16");
  format.jpeg = format_name == "jpg";
  if (mirror_ball < 0 || mirror_ball == 1) throw Error("--mirror-ball must be 0 (none) or a size in pixels");
  if (!format.jpeg) camera.raw_bits = 14;
  const cv::Size image = ParseImageSize(size, "--size", 32);
  shot.width = image.width;
  shot.height = image.height;
  shot.centre_px = {shot.width * 0.55, shot.height * 0.46};
  if (!at.empty()) {
    const std::vector<double> p = ParseNumberList(at, 2, "--at", "x,y in pixels");
    shot.centre_px = {p[0], p[1]};
  }
  const std::vector<double> ypr = ParseNumberList(rotate, 3, "--rotate", "yaw,pitch,roll in degrees");
  shot.camera_to_probe = Rotation::FromYawPitchRoll(ypr[0], ypr[1], ypr[2]);

  Stopwatch sw;
  std::string label;
  const MerlBrdf brdf = src.Load(db, &label);
  const LatLongProbe probe = LatLongProbe::Read(probe_path);
  const SyntheticPhoto photo = RenderSphereShot(brdf, probe, shot, quality.q);
  const fs::path dir(out);
  fs::create_directories(dir / "truth");
  const std::vector<double> photo_times = CoveringBracketTimes(photo.radiance, stops);
  const auto photo_frames = WriteBracket(photo.radiance, photo_times, camera, format, dir / "photo", "IMG_",
                                         shot.focal_px * 36 / std::max(shot.width, shot.height));
  // The probe shot with the same camera (a lat-long panorama bracket), so the
  // merged probe and photo share one response and hence one radiometric scale.
  const LatLongProbe pano = probe.Resized(probe_width);
  CameraModel probe_camera = camera;
  probe_camera.seed = camera.seed + 1;
  const std::vector<double> probe_times = CoveringBracketTimes(pano.rgb(), stops);
  const auto probe_frames = WriteBracket(pano.rgb(), probe_times, probe_camera, format, dir / "probe", "PANO_", 0);

  std::string ball_circle;  // where the ball is in ball.exr (the user marks it on a real one)
  if (mirror_ball > 0) {
    // The lighting as the camera sees it, L_cam(d) = L_probe(R d), in a ball
    // framed by a black border, shot with the capture's lens (perspective) on
    // its optical axis. Its circle goes into capture.mk, as a user would mark
    // it: a mirror ball's rim need not stand out from its surround.
    const int pad = std::max(8, mirror_ball / 10), side = mirror_ball + 2 * pad;
    const double r = mirror_ball / 2.0, c = side / 2.0;
    const BallCamera lens =
        BallCamera::Perspective(side, side, shot.focal_px, {c, c}, Vec3(0, 0, -1), std::atan(r / shot.focal_px));
    WriteExr((dir / "ball.exr").string(), RenderMirrorBall(probe.Rotated(shot.camera_to_probe), lens));
    ball_circle = std::to_string(c) + "," + std::to_string(c) + "," + std::to_string(r);
  }
  WriteExr((dir / "truth" / "photo.exr").string(), photo.radiance);
  WriteExr((dir / "truth" / "probe.exr").string(), pano.rgb());
  WriteFileAtomic((dir / "truth" / "sphere.json").string(),
                  [&](std::ostream& o) { o << photo.view.ToJson().dump(1) << "\n"; });
  const std::string truth_args = src.ToArgs(db);
  const std::string cmdline = CommandLine(argc, argv);
  const nlohmann::json truth = {{"format", "brdfshot-synthetic-capture-1"},
                                {"material", label},
                                {"material_args", truth_args},
                                {"probe", probe_path},
                                {"yaw_pitch_roll_deg", ypr},
                                {"rotation_camera_to_probe", shot.camera_to_probe.m},
                                {"sphere", photo.view.ToJson()},
                                {"photo_times", photo_times},
                                {"probe_times", probe_times},
                                {"camera",
                                 {{"gamma", camera.gamma},
                                  {"shoulder", camera.shoulder},
                                  {"full_well", camera.full_well},
                                  {"read_noise", camera.read_noise},
                                  {"raw_bits", camera.raw_bits},
                                  {"seed", camera.seed}}},
                                {"render_quality", quality.q.Describe()},
                                {"command", cmdline}};
  WriteFileAtomic((dir / "truth" / "truth.json").string(), [&](std::ostream& o) { o << truth.dump(1) << "\n"; });
  // The capture's config, in Make syntax so samples/Makefile can include it;
  // a real capture folder has the same file, written by hand.
  WriteFileAtomic((dir / "capture.mk").string(), [&](std::ostream& o) {
    o << "# brdfshot capture folder: photo/ (bracket of the sphere), probe/ (bracket of the probe).\n"
      << "# Written by: " << cmdline << "\n"
      << "FOCAL_PX     = " << shot.focal_px << "\n"
      << "ROTATE       = " << rotate << "\n"
      << (mirror_ball > 0 ? "# The pipeline estimates the rotation from this mirror-ball photo (ROTATE, the\n"
                            "# truth, is then used only by PERFECT=1 runs); it was shot with the photo's lens.\n"
                            "BALL_FILE    = ball.exr\nBALL_CIRCLE  = " +
                                ball_circle + "\n"
                          : "");
    if (mirror_ball > 0) o << "BALL_FOCAL_PX = " << shot.focal_px << "\n";
    o << "PROBE_LAYOUT = latlong\n"
      << "# Synthetic only: the true material, for the report's error against the truth.\n"
      << "TRUTH        = " << truth_args << "\n";
  });
  std::printf(
      "synthetic capture of %s under %s: sphere r %.1f px at (%.1f, %.1f) in %dx%d, f %.0f px\n"
      "photo: %zu frames (%s, %g stops), probe: %zu frames of %dx%d; %.2f s\nwrote %s/{capture.mk, photo/, probe/, "
      "truth/%s}\n",
      label.c_str(), probe.name().c_str(), photo.view.circle.r, photo.view.circle.cx, photo.view.circle.cy, shot.width,
      shot.height, shot.focal_px, photo_frames.size(), format_name.c_str(), stops, probe_frames.size(), pano.width(),
      pano.height(), sw.Seconds(), out.c_str(), mirror_ball > 0 ? ", ball.exr" : "");
  return 0;
}

}  // namespace brdfshot
