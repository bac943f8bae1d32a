// The analytic stand-in database (shared/standin/README.md): 100 materials whose
// BRDF is known in closed form everywhere — the exact oracle of the test suite.
// Results computed on it say "stand-in", never "MERL".
#pragma once

#include <string>
#include <vector>

#include "fit/merl_brdf.h"

namespace brdfshot {

struct StandinMaterial {
  std::string name, family;  // family: diffuse | plastic | metal | paint
  double kd[3] = {0, 0, 0};
  double sigma = 0;  // Oren–Nayar roughness (radians); 0 = Lambert
  double ks1 = 0, alpha1 = 0, ks2 = 0, alpha2 = 0;
  double eta = 1.5;
  double f0[3] = {0, 0, 0};

  // ρ(ω_i, ω_o) in 1/sr, local frame; {0,0,0} where either is below the horizon.
  Rgb Eval(const Vec3& wi, const Vec3& wo) const;
  // Sampled onto a MERL grid exactly as the stand-in README specifies.
  MerlBrdf ToMerl(const MerlGrid& grid) const;
};

// Parses materials.tsv; Error naming the file and line on any malformed row.
std::vector<StandinMaterial> ReadStandinTable(const std::string& path);

// Closed-form pieces, exposed for tests.
double GgxLobe(double k, double alpha, double fresnel, const Vec3& wi, const Vec3& wo);
double FresnelDielectric(double eta, double cos_d);
double FresnelSchlick(double f0, double cos_d);

}  // namespace brdfshot
