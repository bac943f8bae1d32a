// A distant-light environment in latitude-longitude layout, the probe frame of the
// whole pipeline. Convention (documented in docs/formats.md "Frames"): +Y is up; row 0 is
// the zenith; the map's horizontal centre looks along −Z; +X is to the right of
// that centre. A camera at +Z looking down −Z sees the middle of the map behind
// the object.
//
//   θ = π (row + ½)/H,  φ = 2π (col + ½)/W,  d = (−sinθ sinφ, cosθ, sinθ cosφ).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "util/rotation.h"
#include "util/vec3.h"

namespace brdfshot {

class LatLongProbe {
 public:
  LatLongProbe() = default;
  // `rgb` is CV_32FC3 RGB radiance, width == 2 × height.
  explicit LatLongProbe(cv::Mat rgb, std::string name = "");

  // Reads .exr/.hdr/.pfm lat-long maps; Error naming the file if the aspect is not 2:1.
  static LatLongProbe Read(const std::string& path);

  int width() const { return rgb_.cols; }
  int height() const { return rgb_.rows; }
  const cv::Mat& rgb() const { return rgb_; }
  const std::string& name() const { return name_; }

  Vec3 DirectionAt(double col, double row) const;  // continuous pixel coords
  void PixelAt(const Vec3& dir, double* col, double* row) const;
  cv::Vec3f Bilinear(const Vec3& dir) const;  // radiance, bilinear, wrapping in longitude
  double TexelSolidAngle(int row) const;      // sr
  cv::Vec3f Texel(int col, int row) const { return rgb_.at<cv::Vec3f>(row, col); }

  // Box-resampled to `width`×`width/2` with solid-angle weights (area-preserving
  // in radiant power), for probes finer than the scene needs.
  LatLongProbe Resized(int width) const;
  // The same lighting in another frame: L'(d) = L(to_this(d)), read bilinearly
  // (e.g. the probe as the camera sees it, `to_this` = camera → probe).
  LatLongProbe Rotated(const Rotation& to_this) const;
  // Content hash (FNV-1a over the floats), used to key basis-image caches.
  uint64_t Hash() const;

 private:
  cv::Mat rgb_;
  std::string name_;
};

// Radiance at a direction averaged over a cone of solid angle `omega`, from a
// mip pyramid built with solid-angle weights: trilinear between the two levels
// whose texels bracket `omega`. This is what lets the basis-image quadrature use
// few samples on a mirror-like BRDF without aliasing the probe.
class PrefilteredProbe {
 public:
  explicit PrefilteredProbe(const LatLongProbe& probe);
  cv::Vec3f Lookup(const Vec3& dir, double omega) const;
  cv::Vec3f LookupLevel(const Vec3& dir, int level) const;  // bilinear in one level
  int levels() const { return static_cast<int>(levels_.size()); }

  // Lookup for n directions at once (the basis-image inner loop): the angle and
  // filter-width math runs over plain float arrays, which the compiler turns
  // into SIMD, and only the texel fetches stay scalar. `dir_xyz` and `rgb` are
  // n×3 interleaved; `omega` ≤ 0 marks an unused entry (its rgb is 0).
  // `scratch` must hold 3n floats. Same result as Lookup to float precision.
  void LookupMany(int n, const float* dir_xyz, const float* omega, float* scratch, float* rgb) const;

 private:
  static void Angles(const Vec3& dir, double* u, double* v);  // lat-long coords in [0,1]²
  cv::Vec3f Trilinear(double u, double v, double lod) const;  // between the two levels around lod
  cv::Vec3f Bilinear(int level, double u, double v) const;
  std::vector<cv::Mat> levels_;  // CV_32FC3, level 0 is the probe
  // The levels again, RGB with one texel of border: column 0 repeats the last
  // column and column w+1 the first (φ wraps), rows 0 and h+1 repeat the edge
  // rows (θ clamps). LookupMany's bilinear reads then need no wrap or clamp,
  // which made the fetches ~2× faster (`brdfshot bench-basis`).
  struct PaddedLevel {
    int w, h;
    std::vector<float> rgb;  // (h + 2) × (w + 2) × 3
  };
  std::vector<PaddedLevel> padded_;
  double texel0_omega_;  // mean texel solid angle at level 0
};

}  // namespace brdfshot
