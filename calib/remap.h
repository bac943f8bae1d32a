// The remap stage: a photo's valid pixels in the probe's frame and units — the
// observation file the solver reads. The geometry comes from a sphere file
// (`normals`) or, for any convex object, a normal map with its mask; the
// calibration (`calib`) turns camera directions into probe directions and
// photo radiance into probe units.
#pragma once

#include <string>

#include "normals/normal_map.h"
#include "normals/observation.h"
#include "normals/sphere_view.h"

namespace brdfshot {

struct RemapOptions {
  std::string photo;        // linear HDR photo
  std::string sphere;       // sphere file, or
  std::string normal_map;   // normal map (camera frame) …
  std::string object_mask;  // … and its mask ("" : every pixel with a unit normal)
  std::string calibration;  // "" : the photo is taken as in the probe frame and units
  std::string unreliable;   // mask of pixels no frame measured well ("" : none)
  SphereMaskOptions sphere_mask;
  NormalMapOptions normal_map_options;  // max_angle_deg taken from sphere_mask
  std::string command;                  // recorded in the header
};

// Errors name the file: a geometry or mask for a photo of another size, an
// undecodable mask, fewer than 16 pixels left. Exactly one of `sphere` and
// `normal_map` must be set (an internal check; the command says which).
Observations RemapPhoto(const RemapOptions& options);

}  // namespace brdfshot
