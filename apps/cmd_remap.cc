// brdfshot remap: the observation file the solver reads — each valid pixel's
// radiance (probe units), normal and view direction in the probe frame
// (calib/remap.h).
#include <cstdio>

#include "apps/command.h"
#include "calib/remap.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

int RemapMain(int argc, char** argv) {
  RemapOptions o;
  std::string out = "observations.bsobs";
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("photo", po::value(&o.photo)->required(), "linear HDR photo (from 'brdfshot merge')")
      ("sphere", po::value(&o.sphere), "sphere file (from 'brdfshot normals')")
      ("normal-map", po::value(&o.normal_map), "instead of --sphere, any convex object: its normals (camera frame: x right, y up, z towards the camera) as a 8/16-bit PNG ((n + 1)/2) or a float EXR/PFM")
      ("mask", po::value(&o.object_mask), "--normal-map's object mask (nonzero = object; default: every pixel with a unit normal)")
      ("focal-px", po::value(&o.normal_map_options.focal_px)->default_value(0), "--normal-map's camera: focal length in pixels (0: orthographic)")
      ("erode", po::value(&o.normal_map_options.erode_px)->default_value(o.normal_map_options.erode_px), "--normal-map's mask shrunk by this many pixels (its edge mixes background)")
      ("calib", po::value(&o.calibration), "probe calibration (from 'brdfshot calib'): rotation and scale")
      ("unreliable", po::value(&o.unreliable), "mask PNG of unreliable pixels (from 'brdfshot merge')")
      ("margin", po::value(&o.sphere_mask.max_angle_deg)->default_value(o.sphere_mask.max_angle_deg), "max angle between normal and view (deg)")
      ("rim-px", po::value(&o.sphere_mask.rim_margin_px)->default_value(o.sphere_mask.rim_margin_px), "pixels this close to the silhouette are dropped")
      ("out,o", po::value(&out)->default_value(out), "observation file");
  // clang-format on
  if (!ParseOptions("remap", "--photo P (--sphere S | --normal-map N [--mask M]) [--calib C] [options]", desc, argc,
                    argv))
    return 0;
  if (o.sphere.empty() == o.normal_map.empty()) throw Error("remap: give exactly one of --sphere and --normal-map");
  if (!o.object_mask.empty() && o.normal_map.empty()) throw Error("remap: --mask goes with --normal-map");
  if (!(o.normal_map_options.focal_px >= 0))
    throw Error("--focal-px must be a focal length in pixels, or 0 for orthographic");
  if (o.normal_map_options.erode_px < 0) throw Error("--erode must be 0 or more pixels");
  o.command = CommandLine(argc, argv);
  const Observations obs = RemapPhoto(o);
  obs.Write(out);
  const cv::Vec3d scale(obs.header["scale"][0], obs.header["scale"][1], obs.header["scale"][2]);
  std::printf("%zu pixels of %s in the probe frame (divided by scale %g %g %g)\nwrote %s\n", obs.geometry.size(),
              o.photo.c_str(), scale[0], scale[1], scale[2], out.c_str());
  return 0;
}

}  // namespace brdfshot
