// The MERL BRDF table's parameterisation (Matusik et al. 2003), generalised to a
// reduced resolution. Entry (i, j, k) holds ρ at the lattice point
//   θ_h = (i/n_th)² π/2,  θ_d = j (π/2)/n_td,  φ_d = k π/n_pd,
// i.e. the point MERL's reference lookup maps exactly onto that index. θ_h is
// non-linear so that specular peaks get most bins; φ_d covers [0, π) only because
// reciprocity makes φ_d and φ_d + π the same entry. File order: k fastest, then j, i.
#pragma once

#include <array>
#include <vector>
#include <cstddef>

#include "util/vec3.h"

namespace brdfshot {

// Rusinkiewicz half/difference angles of a direction pair in the local frame.
struct HalfDiff {
  double theta_h = 0, theta_d = 0, phi_d = 0;  // phi_d in [0, 2π)
};
HalfDiff ToHalfDiff(const Vec3& wi, const Vec3& wo);
// Inverse with φ_h = 0: the incoming and outgoing directions of an entry.
void FromHalfDiff(const HalfDiff& hd, Vec3* wi, Vec3* wo);

struct MerlGrid {
  int n_th = 90, n_td = 90, n_pd = 180;

  static constexpr MerlGrid Full() { return {90, 90, 180}; }
  size_t size() const { return static_cast<size_t>(n_th) * n_td * n_pd; }
  size_t Index(int i, int j, int k) const { return (static_cast<size_t>(i) * n_td + j) * n_pd + k; }
  void Unindex(size_t idx, int* i, int* j, int* k) const {
    *k = static_cast<int>(idx % n_pd);
    *j = static_cast<int>((idx / n_pd) % n_td);
    *i = static_cast<int>(idx / (static_cast<size_t>(n_pd) * n_td));
  }
  HalfDiff LatticePoint(int i, int j, int k) const;
  // Continuous lattice coordinates of an angle triple (φ_d folded into [0, π)).
  void Continuous(const HalfDiff& hd, double* u_h, double* u_d, double* u_p) const;
  // Nearest-entry index (what MERL's reference lookup returns, rounded not floored).
  size_t NearestIndex(const HalfDiff& hd) const;
  // The 8 entries around an angle triple and their trilinear weights (summing to
  // 1; φ_d wraps, the other axes clamp at the table's ends). Returns how many
  // corners have a non-zero weight (they come first).
  int TrilinearCorners(const HalfDiff& hd, size_t idx[8], double w[8]) const;
  // Both directions of the entry above the horizon, i.e. measurable.
  bool Measurable(size_t idx) const;
  // cos θ_i · cos θ_o at the entry's lattice point (0 where not measurable).
  double CosineWeight(size_t idx) const;
  // CosineWeight of every entry as float, in index order: the trigonometry of
  // each axis taken once (a few hundred sines, not three pairs per entry: the
  // table has 1.46 M entries and a BRDF is combined over all of them).
  std::vector<float> CosineWeightTable() const;
  bool operator==(const MerlGrid& o) const { return n_th == o.n_th && n_td == o.n_td && n_pd == o.n_pd; }
};

// MERL's channel scales: stored value × scale = BRDF (1/sr).
constexpr std::array<double, 3> kMerlScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

}  // namespace brdfshot
