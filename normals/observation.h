// The observation file: what the solver reads from a photo. Each valid pixel's
// linear RGB radiance (in the probe's units), its normal and the direction to
// the camera (unit, probe frame), and its image position; a JSON header records
// where it came from. Written by `brdfshot remap`, read by `basis` (geometry)
// and `fit` (radiance).
//
// Layout (little-endian): "BSHOTOB1", uint64 header length, header JSON
// {"format": "brdfshot-observations-1", "pixels", "width", "height", ...},
// then per pixel: int32 x, int32 y, float32 r, g, b, float64 normal[3],
// float64 view[3] (68 bytes).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "normals/sphere_geometry.h"

namespace brdfshot {

struct Observations {
  nlohmann::json header;
  PixelGeometry geometry;
  Eigen::MatrixXd rgb;  // pixels × 3

  void Write(const std::string& path) const;
  // Error naming the file on a bad magic, header, size, non-unit direction,
  // non-finite radiance or a pixel outside the image.
  static Observations Read(const std::string& path);
  static Observations Parse(const std::string& bytes, const std::string& name);
};

// The photo's radiance at the geometry's pixels, divided per channel by
// `scale` (photo units per probe unit), header empty. FileError naming
// `geometry_source` when fewer than 16 pixels are left to fit.
Observations ObservePixels(const cv::Mat& photo_rgb32f, PixelGeometry geometry, const cv::Vec3d& scale,
                           const std::string& geometry_source);

}  // namespace brdfshot
