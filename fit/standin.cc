#include "fit/standin.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "util/check.h"

namespace brdfshot {

double FresnelDielectric(double eta, double c) {
  const double g = std::sqrt(eta * eta - 1 + c * c);
  const double a = (g - c) / (g + c);
  const double b = (c * (g + c) - 1) / (c * (g - c) + 1);
  return 0.5 * a * a * (1 + b * b);
}

double FresnelSchlick(double f0, double c) { return f0 + (1 - f0) * std::pow(1 - c, 5); }

namespace {
double Tan2(double cos_t) { return std::max(0.0, 1 - cos_t * cos_t) / (cos_t * cos_t); }
double SmithLambda(double alpha, double cos_t) { return (-1 + std::sqrt(1 + alpha * alpha * Tan2(cos_t))) / 2; }
}  // namespace

double GgxLobe(double k, double alpha, double fresnel, const Vec3& wi, const Vec3& wo) {
  if (k == 0) return 0;
  const Vec3 h = Normalize(wi + wo);
  const double a2 = alpha * alpha, ch = h.z, t2 = Tan2(ch);
  const double D = a2 / (kPi * ch * ch * ch * ch * (a2 + t2) * (a2 + t2));
  const double G = 1 / (1 + SmithLambda(alpha, wi.z) + SmithLambda(alpha, wo.z));
  return k * D * G * fresnel / (4 * wi.z * wo.z);
}

Rgb StandinMaterial::Eval(const Vec3& wi, const Vec3& wo) const {
  if (wi.z <= 0 || wo.z <= 0) return {};
  const double cos_d = Dot(wi, Normalize(wi + wo));
  double out[3] = {0, 0, 0};
  // Diffuse term (Oren–Nayar; Lambert when σ = 0 or the family says so).
  if (family != "metal") {
    const double s2 = family == "diffuse" ? sigma * sigma : 0.0;
    const double A = 1 - 0.5 * s2 / (s2 + 0.33), B = 0.45 * s2 / (s2 + 0.09);
    double extra = 0;
    if (B > 0) {
      const double ti = std::acos(std::min(1.0, wi.z)), to = std::acos(std::min(1.0, wo.z));
      const double a = std::max(ti, to), b = std::min(ti, to);
      const double ri = std::hypot(wi.x, wi.y), ro = std::hypot(wo.x, wo.y);
      const double cos_dphi = (ri > 0 && ro > 0) ? (wi.x * wo.x + wi.y * wo.y) / (ri * ro) : 0;
      extra = B * std::max(0.0, cos_dphi) * std::sin(a) * std::tan(b);
    }
    for (int c = 0; c < 3; ++c) out[c] += kd[c] / kPi * (A + extra);
  }
  const double f_diel = FresnelDielectric(eta, cos_d);
  const bool flakes = f0[0] != 0 || f0[1] != 0 || f0[2] != 0;
  for (int c = 0; c < 3; ++c) {
    const double f_cond = FresnelSchlick(f0[c], cos_d);
    if (family == "metal") {
      out[c] += GgxLobe(ks1, alpha1, f_cond, wi, wo);
    } else {
      out[c] += GgxLobe(ks1, alpha1, f_diel, wi, wo);
      if (family == "paint") out[c] += GgxLobe(ks2, alpha2, flakes ? f_cond : f_diel, wi, wo);
    }
  }
  return {out[0], out[1], out[2]};
}

MerlBrdf StandinMaterial::ToMerl(const MerlGrid& grid) const {
  MerlBrdf m(grid);
  for (int i = 0; i < grid.n_th; ++i)
    for (int j = 0; j < grid.n_td; ++j)
      for (int k = 0; k < grid.n_pd; ++k) {
        Vec3 wi, wo;
        FromHalfDiff(grid.LatticePoint(i, j, k), &wi, &wo);
        const size_t idx = grid.Index(i, j, k);
        if (wi.z <= 0 || wo.z <= 0) continue;  // stays -1: unmeasured
        const Rgb v = Eval(wi, wo);
        for (int c = 0; c < 3; ++c) m.set_raw(c, idx, v[c] / kMerlScale[c]);
      }
  return m;
}

std::vector<StandinMaterial> ReadStandinTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot open stand-in table");
  std::vector<StandinMaterial> out;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    StandinMaterial m;
    s >> m.name >> m.family >> m.kd[0] >> m.kd[1] >> m.kd[2] >> m.sigma >> m.ks1 >> m.alpha1 >> m.ks2 >> m.alpha2 >>
        m.eta >> m.f0[0] >> m.f0[1] >> m.f0[2];
    if (!s) throw FileError(path, "line " + std::to_string(lineno) + ": expected 14 columns");
    if (m.family != "diffuse" && m.family != "plastic" && m.family != "metal" && m.family != "paint")
      throw FileError(path, "line " + std::to_string(lineno) + ": unknown family '" + m.family + "'");
    out.push_back(m);
  }
  if (out.empty()) throw FileError(path, "no materials");
  return out;
}

}  // namespace brdfshot
