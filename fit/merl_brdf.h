// A MERL-format BRDF table: read, write, look up.
//
// File: three int32 (n_th, n_td, n_pd) then 3 × n_th·n_td·n_pd float64, all red,
// then green, then blue; multiply by kMerlScale for the BRDF. Negative = not
// measured. The full MERL resolution is 90 × 90 × 180; reduced grids (for tests
// and the demo) use the same layout with their own header.
#pragma once

#include <string>
#include <vector>

#include "fit/merl_grid.h"
#include "util/vec3.h"

namespace brdfshot {

struct Rgb {
  double r = 0, g = 0, b = 0;
  double operator[](int c) const { return c == 0 ? r : (c == 1 ? g : b); }
};

class MerlBrdf {
 public:
  MerlBrdf() = default;
  explicit MerlBrdf(const MerlGrid& grid);

  // Errors name the file: missing, folder, short header, bad dimensions, size
  // that does not match the header (truncated or trailing bytes), NaN/Inf.
  static MerlBrdf Read(const std::string& path);
  void Write(const std::string& path) const;  // atomic

  const MerlGrid& grid() const { return grid_; }
  // Raw stored value (MERL units, before the channel scale); negative = unmeasured.
  double raw(int c, size_t idx) const { return raw_[c * grid_.size() + idx]; }
  void set_raw(int c, size_t idx, double v) { raw_[c * grid_.size() + idx] = v; }
  // BRDF value of an entry in 1/sr, or a negative number when unmeasured.
  double Value(int c, size_t idx) const {
    const double v = raw(c, idx);
    return v < 0 ? v : v * kMerlScale[c];
  }
  // ρ(ω_i, ω_o) in the local frame (z = normal): trilinear between lattice points
  // in (√θ_h, θ_d, φ_d), φ_d wrapping by reciprocity, unmeasured corners left out
  // and the weights renormalised; 0 below the horizon or where nothing is measured.
  Rgb Eval(const Vec3& wi, const Vec3& wo) const;
  Rgb EvalHalfDiff(const HalfDiff& hd) const;
  double UnmeasuredFraction() const;

 private:
  MerlGrid grid_;
  std::vector<double> raw_;
};

}  // namespace brdfshot
