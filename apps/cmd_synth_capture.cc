// brdfshot synth-capture: a capture folder as a photographer would bring it
// back — bracketed JPEGs (EXIF exposure) of a sphere of a known material under
// a probe, bracketed frames of the probe itself, a small config file — plus the
// truth, so every stage after it can be measured.
#include <cstdio>

#include "apps/brdf_source.h"
#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/synthetic_capture.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {

// The command line as typed; ToOptions checks it and fills the stage's options.
struct SynthCaptureArgs {
  DatabaseArgs db;
  QualityArgs quality;
  BrdfSourceArgs src;
  SyntheticCaptureOptions o;
  std::string probe_path, out = "capture", size = "640x480", at, rotate = "0,0,0", format_name = "jpg";

  void Add(po::options_description& desc) {
    // clang-format off
    desc.add_options()
        ("probe,p", po::value(&probe_path)->required(), "lat-long light probe (the scene's true lighting)")
        ("out,o", po::value(&out)->default_value(out), "capture folder to write")
        ("size", po::value(&size)->default_value(size), "photo size WxH")
        ("radius", po::value(&o.shot.radius_px)->default_value(o.shot.radius_px), "apparent sphere radius, px")
        ("focal-px", po::value(&o.shot.focal_px)->default_value(o.shot.focal_px), "focal length, px")
        ("at", po::value(&at), "where the sphere's centre appears, x,y px (default: right of and above the centre)")
        ("rotate", po::value(&rotate)->default_value(rotate), "camera -> probe yaw,pitch,roll degrees")
        ("blur", po::value(&o.shot.blur_sigma)->default_value(o.shot.blur_sigma), "lens blur sigma, px")
        ("format", po::value(&format_name)->default_value(format_name), "jpg (8-bit through a response curve) | png16 (linear 14-bit RAW-like)")
        ("jpeg-quality", po::value(&o.jpeg_quality)->default_value(o.jpeg_quality), "JPEG quality")
        ("stops", po::value(&o.stops)->default_value(o.stops), "bracket step in stops")
        ("full-well", po::value(&o.camera.full_well)->default_value(o.camera.full_well), "sensor full well, electrons")
        ("read-noise", po::value(&o.camera.read_noise)->default_value(o.camera.read_noise), "read noise, electrons RMS")
        ("seed", po::value(&o.camera.seed)->default_value(o.camera.seed), "noise seed")
        ("probe-shot-width", po::value(&o.probe_shot_width)->default_value(o.probe_shot_width), "width of the probe's own bracket (lat-long panorama; the rendering quality's --probe-width is separate)")
        ("mirror-ball", po::value(&o.mirror_ball)->default_value(0), "also write ball.exr: a mirror ball this many px across, shot from the camera (linear HDR), and let capture.mk estimate the rotation from it instead of stating it");
    // clang-format on
    src.Add(desc);
    db.Add(desc);
    quality.Add(desc);
  }

  SyntheticCaptureOptions ToOptions(const std::string& command) const {
    if (format_name != "jpg" && format_name != "png16")
      throw Error("unknown --format '" + format_name + "': expected jpg or png16");
    SyntheticCaptureOptions r = o;
    r.jpeg = format_name == "jpg";
    if (r.mirror_ball < 0 || r.mirror_ball == 1) throw Error("--mirror-ball must be 0 (none) or a size in pixels");
    if (!r.jpeg) r.camera.raw_bits = 14;
    const cv::Size image = ParseImageSize(size, "--size", 32);
    r.shot.width = image.width;
    r.shot.height = image.height;
    r.shot.centre_px = {r.shot.width * 0.55, r.shot.height * 0.46};
    if (!at.empty()) {
      const std::vector<double> p = ParseNumberList(at, 2, "--at", "x,y in pixels");
      r.shot.centre_px = {p[0], p[1]};
    }
    const std::vector<double> ypr = ParseNumberList(rotate, 3, "--rotate", "yaw,pitch,roll in degrees");
    r.yaw_pitch_roll_deg = {ypr[0], ypr[1], ypr[2]};
    r.shot.camera_to_probe = Rotation::FromYawPitchRoll(ypr[0], ypr[1], ypr[2]);
    r.quality = quality.q;
    r.probe_path = probe_path;
    r.material_args = src.ToArgs(db);
    r.command = command;
    return r;
  }
};

}  // namespace

int SynthCaptureMain(int argc, char** argv) {
  SynthCaptureArgs args;
  po::options_description desc("options");
  args.Add(desc);
  if (!ParseOptions("synth-capture", "--probe P (--standin N | --nbrdf N | --merl F) -o DIR [options]", desc, argc,
                    argv))
    return 0;
  SyntheticCaptureOptions o = args.ToOptions(CommandLine(argc, argv));
  Stopwatch sw;
  const MerlBrdf brdf = args.src.Load(args.db, &o.material);
  const LatLongProbe probe = LatLongProbe::Read(args.probe_path);
  const SyntheticCapture c = WriteSyntheticCapture(brdf, probe, o, args.out);
  const SphereView& v = c.photo.view;
  std::printf(
      "synthetic capture of %s under %s: sphere r %.1f px at (%.1f, %.1f) in %dx%d, f %.0f px\n"
      "photo: %zu frames (%s, %g stops), probe: %zu frames of %dx%d; %.2f s\nwrote %s/{capture.mk, photo/, probe/, "
      "truth/%s}\n",
      o.material.c_str(), probe.name().c_str(), v.circle.r, v.circle.cx, v.circle.cy, o.shot.width, o.shot.height,
      o.shot.focal_px, c.photo_frames.size(), args.format_name.c_str(), o.stops, c.probe_frames.size(),
      c.probe_shot.width, c.probe_shot.height, sw.Seconds(), args.out.c_str(), o.mirror_ball > 0 ? ", ball.exr" : "");
  return 0;
}

}  // namespace brdfshot
