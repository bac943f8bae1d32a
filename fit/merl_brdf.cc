#include "fit/merl_brdf.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/huge_pages.h"

namespace brdfshot {

MerlBrdf::MerlBrdf(const MerlGrid& grid) : grid_(grid) {
  // 35 MB for MERL's grid, filled at once: on huge pages that is a few dozen
  // page faults, not 8,500 (util/huge_pages.h); a render reads two or three.
  const size_t n = 3 * grid.size();
  raw_.reserve(n);
  AdviseHugePages(raw_.data(), n * sizeof(double));
  raw_.assign(n, -1.0);
}

MerlBrdf MerlBrdf::Read(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError(path, "is a folder, expected a MERL .binary file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open MERL file (missing or unreadable)");
  const auto file_size = std::filesystem::file_size(path, ec);
  int32_t dims[3];
  if (ec || file_size < sizeof dims || !in.read(reinterpret_cast<char*>(dims), sizeof dims))
    throw FileError(path, "too short for a MERL header (12 bytes)");
  for (int d : dims)
    if (d <= 0 || d > 4096)
      throw FileError(path, "bad MERL header (" + std::to_string(dims[0]) + ", " + std::to_string(dims[1]) + ", " +
                                std::to_string(dims[2]) + "): expected (90, 90, 180) or a reduced positive grid");
  // The size check comes before the allocation: a corrupt header must not ask
  // for 4096³ doubles (found by fuzz_merl).
  const MerlGrid grid{dims[0], dims[1], dims[2]};
  const uint64_t expected = sizeof dims + 3ull * grid.size() * sizeof(double);
  if (file_size != expected)
    throw FileError(path, "size " + std::to_string(file_size) + " bytes does not match header (" +
                              std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                              " needs " + std::to_string(expected) + "): truncated or not a MERL file");
  MerlBrdf brdf(grid);
  in.read(reinterpret_cast<char*>(brdf.raw_.data()), brdf.raw_.size() * sizeof(double));
  if (!in) throw FileError(path, "read failed");
  size_t bad = 0;
  for (double v : brdf.raw_) bad += !std::isfinite(v);
  if (bad) throw FileError(path, std::to_string(bad) + " entries are NaN or Inf");
  return brdf;
}

void MerlBrdf::Write(const std::string& path) const {
  BRDFSHOT_CHECK(raw_.size() == 3 * grid_.size());
  WriteFileAtomic(path, [&](std::ostream& out) {
    const int32_t dims[3] = {grid_.n_th, grid_.n_td, grid_.n_pd};
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
    out.write(reinterpret_cast<const char*>(raw_.data()), raw_.size() * sizeof(double));
  });
}

Rgb MerlBrdf::Eval(const Vec3& wi, const Vec3& wo) const {
  if (wi.z <= 0 || wo.z <= 0) return {};
  return EvalHalfDiff(ToHalfDiff(wi, wo));
}

Rgb MerlBrdf::EvalHalfDiff(const HalfDiff& hd) const {
  size_t idx[8];
  double w[8];
  const int n = grid_.TrilinearCorners(hd, idx, w);
  double acc[3] = {0, 0, 0}, wsum[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      const double v = Value(c, idx[k]);
      if (v < 0) continue;  // unmeasured corner: left out, weights renormalised
      acc[c] += w[k] * v;
      wsum[c] += w[k];
    }
  Rgb out;
  out.r = wsum[0] > 0 ? acc[0] / wsum[0] : 0;
  out.g = wsum[1] > 0 ? acc[1] / wsum[1] : 0;
  out.b = wsum[2] > 0 ? acc[2] / wsum[2] : 0;
  return out;
}

double MerlBrdf::UnmeasuredFraction() const {
  size_t neg = 0;
  for (double v : raw_) neg += v < 0;
  return static_cast<double>(neg) / raw_.size();
}

}  // namespace brdfshot
