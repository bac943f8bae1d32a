#include "normals/rim_profile.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <type_traits>

#include "util/check.h"
#include "util/vec3.h"

namespace brdfshot {
namespace {
constexpr double kRampLo = -8, kRampHi = 64, kRampStep = 1.0 / 64;
}

// R_1(u) = ∫ √t g(u − t) dt over t ≥ 0 (midpoint rule), tabulated once.
const std::vector<double>& UnitRamp() {
  static const std::vector<double> table = [] {
    const int n = static_cast<int>((kRampHi - kRampLo) / kRampStep);
    std::vector<double> r(n);
    const double dt = 1.0 / 64;
    for (int i = 0; i < n; ++i) {
      const double u = kRampLo + i * kRampStep;
      double sum = 0;
      for (double t = std::max(0.0, u - 6) + dt / 2; t < u + 6; t += dt)
        sum += std::sqrt(t) * std::exp(-0.5 * (u - t) * (u - t));
      r[i] = sum * dt / std::sqrt(2 * 3.14159265358979323846);
    }
    return r;
  }();
  return table;
}

RimProfileModel::RimProfileModel(double sigma, bool curved_interior)
    : sigma_(sigma), curved_interior_(curved_interior), ramp1_(UnitRamp()) {
  BRDFSHOT_CHECK(sigma > 0);
}

double RimProfileModel::Ramp(double u) const {
  // R_σ(u) = √σ R_1(u/σ).
  const double x = (u / sigma_ - kRampLo) / kRampStep;
  if (x <= 0) return 0;
  const int i = static_cast<int>(x);
  if (i + 1 >= static_cast<int>(ramp1_.size())) return std::sqrt(sigma_ * std::max(0.0, u / sigma_));
  const double f = x - i;
  return std::sqrt(sigma_) * ((1 - f) * ramp1_[i] + f * ramp1_[i + 1]);
}

double RimProfileModel::InsideLine(double u, double step_u) const {
  // ∫ max(0, t) g_σ(u − t) dt = σ (z Φ(z) + φ(z)), z = u/σ; Φ(z) is the
  // step column, already computed.
  const double z = u / sigma_;
  return sigma_ * (z * step_u + std::exp(-0.5 * z * z) / std::sqrt(2 * kPi));
}

double RimProfileModel::Fit(const float* p, int n, double r0, double step, double guess, double* rss,
                            double half) const {
  if (half <= 0) half = std::max(3.0, 4 * sigma_) + 1;  // window half-width, px
  const int i0 = static_cast<int>(std::ceil((guess - half - r0) / step));
  const int i1 = static_cast<int>(std::floor((guess + half - r0) / step));
  if (i0 < 0 || i1 >= n || i1 - i0 < 8) {
    if (rss) *rss = std::numeric_limits<double>::quiet_NaN();
    return std::numeric_limits<double>::quiet_NaN();
  }
  const int m = i1 - i0 + 1;
  Eigen::VectorXd y(m);
  for (int k = 0; k < m; ++k) y(k) = p[i0 + k];
  const double yy = y.squaredNorm();
  // Normal equations (4×4, or 5×5 with the curved interior): the columns are
  // well scaled over a few pixels, and this runs 20 times per ray.
  auto residual_n = [&](double s0, auto terms) {
    constexpr int N = decltype(terms)::value;
    Eigen::Matrix<double, N, N> AtA = Eigen::Matrix<double, N, N>::Zero();
    Eigen::Matrix<double, N, 1> Aty = Eigen::Matrix<double, N, 1>::Zero(), a;
    for (int k = 0; k < m; ++k) {
      const double s = r0 + (i0 + k) * step, u = s0 - s;
      a(0) = 1.0;
      a(1) = -u;
      a(2) = 0.5 * std::erfc(-u / (sigma_ * std::sqrt(2.0)));
      a(3) = Ramp(u);
      if constexpr (N == 5) a(4) = InsideLine(u, a(2));
      AtA.template selfadjointView<Eigen::Lower>().rankUpdate(a);
      Aty += a * y(k);
    }
    AtA = AtA.template selfadjointView<Eigen::Lower>();
    const Eigen::Matrix<double, N, 1> b = AtA.ldlt().solve(Aty);
    return std::max(0.0, yy - b.dot(Aty));
  };
  auto residual = [&](double s0) {
    return curved_interior_ ? residual_n(s0, std::integral_constant<int, 5>())
                            : residual_n(s0, std::integral_constant<int, 4>());
  };
  // Scan ±1 px at ¼ px, then ±¼ px around the best at 1/20 px, then a
  // parabola through the best three: 20 solves instead of 41.
  auto scan = [&](double centre, double ds, int half_n, double* best_out) {
    double best = std::numeric_limits<double>::infinity();
    int best_k = 0;
    std::vector<double> r(2 * half_n + 1);
    for (int k = -half_n; k <= half_n; ++k) {
      r[k + half_n] = residual(centre + k * ds);
      if (r[k + half_n] < best) best = r[k + half_n], best_k = k;
    }
    double s = centre + best_k * ds;
    if (best_k > -half_n && best_k < half_n) {
      const double a = r[best_k + half_n - 1], b = r[best_k + half_n], c = r[best_k + half_n + 1];
      const double denom = a - 2 * b + c;
      if (denom > 0) s += 0.5 * ds * (a - c) / denom;
    }
    *best_out = best;
    return s;
  };
  double best;
  double s0 = scan(guess, 0.25, 4, &best);
  s0 = scan(s0, 0.05, 5, &best);
  if (rss) *rss = residual(s0);
  return s0;
}

double EstimateRimBlur(const std::vector<const float*>& profiles, int n, double r0, double step,
                       const std::vector<double>& guesses) {
  // Each ray votes for the σ that fits it best over one fixed window (so that
  // windows of different size are not compared); the median vote wins, which
  // ignores the rays that clutter spoils.
  auto vote = [&](const std::vector<double>& sigmas) {
    std::vector<RimProfileModel> models;
    for (double sigma : sigmas) models.emplace_back(sigma, /*curved_interior=*/true);
    std::vector<double> votes;
    for (size_t k = 0; k < profiles.size(); ++k) {
      double best = std::numeric_limits<double>::infinity(), best_sigma = 0;
      for (size_t j = 0; j < models.size(); ++j) {
        double rss;
        models[j].Fit(profiles[k], n, r0, step, guesses[k], &rss, 8.0);
        if (rss < best) best = rss, best_sigma = sigmas[j];
      }
      if (best_sigma > 0) votes.push_back(best_sigma);
    }
    if (votes.empty()) return 1.0;
    std::nth_element(votes.begin(), votes.begin() + votes.size() / 2, votes.end());
    return votes[votes.size() / 2];
  };
  // A ¼ px grid, then ⅛ px around its winner.
  std::vector<double> grid;
  for (double sigma = 0.5; sigma <= 4.0; sigma += 0.25) grid.push_back(sigma);
  const double coarse = vote(grid);
  return vote({std::max(0.375, coarse - 0.125), coarse, coarse + 0.125});
}

}  // namespace brdfshot
