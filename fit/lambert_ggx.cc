#include "fit/lambert_ggx.h"

#include <cmath>
#include <limits>

#include "fit/nonneg.h"
#include "util/check.h"
#include "util/huge_pages.h"

namespace brdfshot {

std::vector<double> LambertGgxLobes::GeometricAlphas(double first, double last, int count) {
  BRDFSHOT_CHECK(first > 0 && last >= first && count >= 1);
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(count == 1 ? first : first * std::pow(last / first, double(i) / (count - 1)));
  return out;
}

MatrixXfR LambertGgxLobes::Tables(const MerlGrid& grid) const {
  const int R = static_cast<int>(alphas.size());
  // 286 MB on the full grid: huge pages, and every entry written once by the
  // threads (zeroing it first, with 4 KB pages on a virtual machine, cost ten
  // times the lobes' arithmetic).
  MatrixXfR T(static_cast<Eigen::Index>(grid.size()), columns());
  AdviseHugePages(T.data(), sizeof(float) * T.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < grid.n_th; ++i)
    for (int j = 0; j < grid.n_td; ++j)
      for (int k = 0; k < grid.n_pd; ++k) {
        Vec3 wi, wo;
        FromHalfDiff(grid.LatticePoint(i, j, k), &wi, &wo);
        const Eigen::Index row = static_cast<Eigen::Index>(grid.Index(i, j, k));
        if (wi.z <= 0 || wo.z <= 0) {
          T.row(row).setZero();
          continue;
        }
        const Vec3 h = Normalize(wi + wo);
        const double s = std::pow(1 - Dot(wi, h), 5);
        // GGX D and Smith's height-correlated G (as GgxLobe in fit/standin.h,
        // with the angle terms computed once for every α).
        const double ch2 = h.z * h.z, th2 = (1 - ch2) / ch2;
        const double ti2 = (1 - wi.z * wi.z) / (wi.z * wi.z), to2 = (1 - wo.z * wo.z) / (wo.z * wo.z);
        T(row, 0) = static_cast<float>(1 / kPi);
        for (int r = 0; r < R; ++r) {
          const double a2 = alphas[r] * alphas[r];
          const double D = a2 / (kPi * ch2 * ch2 * (a2 + th2) * (a2 + th2));
          const double G = 2 / (std::sqrt(1 + a2 * ti2) + std::sqrt(1 + a2 * to2));
          const double lobe = D * G / (4 * wi.z * wo.z);
          T(row, 1 + 2 * r) = static_cast<float>(lobe * (1 - s));
          T(row, 2 + 2 * r) = static_cast<float>(lobe * s);
        }
      }
  return T;
}

nlohmann::json LambertGgxLobes::ToJson() const { return {{"model", "lambert-ggx-schlick"}, {"alphas", alphas}}; }

LambertGgxLobes LambertGgxLobes::FromJson(const nlohmann::json& j, const std::string& source) {
  LambertGgxLobes l;
  try {
    if (j.at("model") != "lambert-ggx-schlick") throw FileError(source, "unknown analytic lobe model " + j.at("model").dump());
    l.alphas = j.at("alphas").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("bad analytic lobe description: ") + e.what());
  }
  for (double a : l.alphas)
    if (!(a > 0 && a <= 1)) throw FileError(source, "analytic lobe roughness out of (0, 1]: " + std::to_string(a));
  if (l.alphas.empty()) throw FileError(source, "analytic lobe description without roughness values");
  return l;
}

LobeSystem MakeLobeSystem(const std::array<MatrixXfR, 3>& L, const Eigen::MatrixXd& y) {
  LobeSystem s;
  for (int c = 0; c < 3; ++c) {
    BRDFSHOT_CHECK(L[c].rows() == y.rows(), "lobe images and image differ in pixels");
    const Eigen::MatrixXd Lc = L[c].cast<double>();
    s.gram[c] = Lc.transpose() * Lc;
    s.z[c] = Lc.transpose() * y.col(c);
    s.norm2[c] = y.col(c).squaredNorm();
  }
  return s;
}

double LobeRelativeError(const LobeSystem& s, const Eigen::MatrixXd& w) {
  double num = 0, den = 0;
  for (int c = 0; c < 3; ++c) {
    num += s.norm2[c] - 2 * w.col(c).dot(s.z[c]) + w.col(c).dot(s.gram[c] * w.col(c));
    den += s.norm2[c];
  }
  return den > 0 ? std::sqrt(std::max(0.0, num) / den) : 0.0;
}

namespace {
// The weights on the lobe columns of kd / π + q [F0 (1 − s) + s] GGX(α_r):
// kd on column 0, q F0 on 1 + 2r, q on 2 + 2r.
Eigen::MatrixXd LobeWeights(int columns, int r, const std::array<double, 3>& kd, const std::array<double, 3>& scaled_f0,
                            double q) {
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(columns, 3);
  for (int c = 0; c < 3; ++c) w(0, c) = kd[c], w(1 + 2 * r, c) = scaled_f0[c], w(2 + 2 * r, c) = q;
  return w;
}
}  // namespace

LambertGgxFit FitLambertGgx(const LambertGgxLobes& lobes, const LobeSystem& s) {
  const int R = static_cast<int>(lobes.alphas.size());
  BRDFSHOT_CHECK(R > 0 && s.gram[0].rows() == lobes.columns(), "lobe system does not match the lobes");
  LambertGgxFit best;
  double best_error = std::numeric_limits<double>::infinity();
  for (int r = 0; r < R; ++r) {
    // Unknowns x = (kd_R, kd_G, kd_B, qF0_R, qF0_G, qF0_B, q) over the
    // columns {0, i0, i1} of each channel, q shared.
    const int i0 = 1 + 2 * r, i1 = 2 + 2 * r;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(7, 7);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(7);
    for (int c = 0; c < 3; ++c) {
      const Eigen::MatrixXd& G = s.gram[c];
      H(c, c) = G(0, 0), H(c, 3 + c) = H(3 + c, c) = G(0, i0), H(3 + c, 3 + c) = G(i0, i0);
      H(c, 6) = H(6, c) = G(0, i1), H(3 + c, 6) = H(6, 3 + c) = G(i0, i1);
      H(6, 6) += G(i1, i1);
      b[c] = s.z[c][0], b[3 + c] = s.z[c][i0], b[6] += s.z[c][i1];
    }
    const Eigen::VectorXd x = SolveNonNegative(H, b).x;
    const std::array<double, 3> kd = {x[0], x[1], x[2]}, scaled_f0 = {x[3], x[4], x[5]};
    const Eigen::MatrixXd w = LobeWeights(lobes.columns(), r, kd, scaled_f0, x[6]);
    const double e = LobeRelativeError(s, w);
    best.residual_by_alpha.push_back(e);
    if (e < best_error) {
      best_error = e;
      best.alpha_index = r;
      best.alpha = lobes.alphas[r];
      best.weights = w;
      best.specular_scale = x[6];
      best.diffuse_albedo = kd;
      best.scaled_f0 = scaled_f0;
    }
  }
  best.relative_residual = best_error;
  return best;
}

std::array<double, 3> LambertGgxFit::SpecularF0() const {
  std::array<double, 3> f0{};
  for (int c = 0; c < 3; ++c) f0[c] = specular_scale > 0 ? scaled_f0[c] / specular_scale : 0.0;
  return f0;
}

nlohmann::json LambertGgxFit::ToJson(const LambertGgxLobes& lobes) const {
  return {{"model", lobes.ToJson()},
          {"what", "the analytic baseline fitted to the same pixels: rho = diffuse_albedo/pi + specular_scale * "
                   "[F0 (1 - s) + s] * D G / (4 cos_i cos_o), s = (1 - cos_d)^5, GGX D with height-correlated "
                   "Smith G; roughness = sqrt(alpha) as Blender and Unreal take it"},
          {"diffuse_albedo", diffuse_albedo},
          {"specular_f0", SpecularF0()},
          {"specular_scale", specular_scale},
          {"scaled_f0", scaled_f0},
          {"alpha", alpha},
          {"roughness", std::sqrt(alpha)},
          {"relative_residual", relative_residual},
          {"residual_by_alpha", residual_by_alpha}};
}

LambertGgxFit LambertGgxFit::FromJson(const nlohmann::json& j, const LambertGgxLobes& lobes, const std::string& source) {
  LambertGgxFit f;
  try {
    f.alpha = j.at("alpha");
    f.diffuse_albedo = j.at("diffuse_albedo");
    f.specular_scale = j.at("specular_scale");
    f.scaled_f0 = j.at("scaled_f0");
    f.relative_residual = j.at("relative_residual");
    f.residual_by_alpha = j.at("residual_by_alpha").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("bad lambert_ggx record: ") + e.what());
  }
  for (size_t r = 0; r < lobes.alphas.size(); ++r)
    if (lobes.alphas[r] == f.alpha) f.alpha_index = static_cast<int>(r);
  if (f.alpha_index < 0) throw FileError(source, "lambert_ggx alpha is not one of its model's");
  f.weights = LobeWeights(lobes.columns(), f.alpha_index, f.diffuse_albedo, f.scaled_f0, f.specular_scale);
  return f;
}

}  // namespace brdfshot
