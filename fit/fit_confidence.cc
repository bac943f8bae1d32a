#include "fit/fit_confidence.h"

#include <algorithm>
#include <cmath>

#include "fit/database.h"
#include "util/check.h"

namespace brdfshot {

double PriorSensitivity(const ClassSpectrum& cls, const Observation& obs, double lambda,
                        const Eigen::MatrixXd& metric) {
  const std::vector<int>& J = cls.members;
  BRDFSHOT_CHECK(!J.empty() && lambda >= 0 && cls.solvable(),
                 "a prior sensitivity needs a class with its eigenvectors or tridiagonal form and λ ≥ 0");
  BRDFSHOT_CHECK(metric.rows() == static_cast<Eigen::Index>(J.size()) && metric.cols() == metric.rows(),
                 "the BRDF metric is not over the class's bases");
  const Eigen::Index k = static_cast<Eigen::Index>(J.size());
  const double cj = static_cast<double>(k);
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(k, 1.0 / cj);
  // Per channel the fit w and its moves to λ/10 and 10λ, side by side, so
  // that the metric, common to the channels, is applied in one matrix product
  // rather than nine: the penalty of the λ choice asks for several
  // sensitivities per photo, and these products are their cost.
  Eigen::MatrixXd moves(k, 9);
  for (int c = 0; c < 3; ++c) {
    const double scale = obs.norm2[c] / cj;  // λ_j = λ ‖y_c‖² / c_j, as SolveClass
    if (cls.tridiagonal()) {
      // The three solves through T (SolveClassSystem), the same w(λ).
      const Eigen::Vector3d lj(lambda * scale, lambda / 10 * scale, std::max(10 * lambda, 1e-4) * scale);
      const Eigen::MatrixXd w = SolveClassSystem(cls, c, obs.z[c](J) - cls.gram_prior[c], lj);
      moves.col(3 * c) = w.col(0) + prior;
      moves.col(3 * c + 1) = w.col(1) - w.col(0);
      moves.col(3 * c + 2) = w.col(2) - w.col(0);
      continue;
    }
    const Eigen::VectorXd& e = cls.e[c];
    // w(λ) = μ' + V diag(1/(e + λ_j)) b with b = Vᵀ(z_J − G_JJ μ'), as
    // SolveFromSpectrum, with b projected once for the three λ; directions
    // with e + λ_j below 1e-13 e_max keep the prior.
    const Eigen::VectorXd b = cls.V[c].transpose() * (obs.z[c](J) - cls.gram_prior[c]);
    const double floor = 1e-13 * std::max(e[k - 1], 1e-300);
    const auto coefficients = [&](double l) {
      Eigen::VectorXd a(k);
      for (Eigen::Index i = 0; i < k; ++i) {
        const double den = e[i] + l * scale;
        a[i] = den > floor ? b[i] / den : 0.0;
      }
      return a;
    };
    Eigen::MatrixXd a(k, 3);
    a.col(0) = coefficients(lambda);
    a.col(1) = coefficients(lambda / 10) - a.col(0);
    a.col(2) = coefficients(std::max(10 * lambda, 1e-4)) - a.col(0);
    moves.middleCols(3 * c, 3).noalias() = cls.V[c] * a;
    moves.col(3 * c) += prior;
  }
  const Eigen::MatrixXd metric_moves = metric * moves;
  double norm2 = 0, down2 = 0, up2 = 0;
  for (int c = 0; c < 3; ++c) {
    norm2 += moves.col(3 * c).dot(metric_moves.col(3 * c));
    down2 += moves.col(3 * c + 1).dot(metric_moves.col(3 * c + 1));
    up2 += moves.col(3 * c + 2).dot(metric_moves.col(3 * c + 2));
  }
  if (!(norm2 > 0)) return 0;
  return std::sqrt(std::max(0.0, down2) / norm2 + std::max(0.0, up2) / norm2);
}

FitConfidence ConfidenceOf(const LambdaChoice& choice, const std::vector<ClassSpectrum>& classes,
                           const Observation& obs, const std::function<Eigen::MatrixXd(int cls)>& metric) {
  BRDFSHOT_CHECK(!choice.parts.empty(), "a choice without parts");
  FitConfidence out;
  out.prior_sensitivity = 0;
  for (const LambdaChoice::Part& part : choice.parts) {
    const double s = PriorSensitivity(classes.at(static_cast<size_t>(part.cls)), obs, part.lambda, metric(part.cls));
    out.part_predicted_relit_error.push_back(part.held_out_error + s);
    out.prior_sensitivity += part.weight * s;
    out.predicted_relit_error += part.weight * out.part_predicted_relit_error.back();
  }
  return out;
}

std::vector<Eigen::MatrixXd> ClassMetrics(const Eigen::MatrixXd& gram, const std::vector<std::vector<int>>& members) {
  std::vector<Eigen::MatrixXd> out;
  for (const std::vector<int>& J : members) out.push_back(gram(J, J));
  return out;
}

Eigen::MatrixXd SampledCosineGram(const TablesRef& tables, const MerlGrid& grid, const std::vector<int>& members,
                                  int stride) {
  BRDFSHOT_CHECK(stride >= 1 && !members.empty());
  BRDFSHOT_CHECK(static_cast<size_t>(tables.rows()) == grid.size(), "tables and grid differ in bins");
  const Eigen::Index rows = (tables.rows() + stride - 1) / stride, k = static_cast<Eigen::Index>(members.size());
  // Rows cos θ_i cos θ_o · b_J of the sampled bins (SᵀS weighs each by cos²),
  // gathered a block at a time: the weights of the sampled bins alone, and no
  // matrix of every sampled row (100-odd MB of fresh pages for 300 bases).
  constexpr Eigen::Index kBlock = 256;
  Eigen::MatrixXd S(kBlock, k);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);
  for (Eigen::Index r0 = 0; r0 < rows; r0 += kBlock) {
    const Eigen::Index m = std::min(kBlock, rows - r0);
    for (Eigen::Index r = 0; r < m; ++r) {
      const Eigen::Index bin = (r0 + r) * stride;
      const double weight = static_cast<float>(grid.CosineWeight(bin));  // as CosineWeightTable holds it
      for (Eigen::Index i = 0; i < k; ++i) S(r, i) = weight * tables(bin, members[i]);
    }
    gram.selfadjointView<Eigen::Lower>().rankUpdate(S.topRows(m).transpose());
  }
  return gram.selfadjointView<Eigen::Lower>();
}

std::vector<Vec3> ConfidenceSuns() {
  std::vector<Vec3> out;
  for (const double elevation : {30.0, 60.0})
    for (const double azimuth : {0.0, 60.0, 120.0, 180.0}) {
      const double el = elevation * kPi / 180, az = azimuth * kPi / 180;
      out.emplace_back(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    }
  return out;
}

Eigen::MatrixXd DirectionalImageGram(const TablesRef& tables, const MerlGrid& grid, const std::vector<Vec3>& suns,
                                     int sphere_pixels) {
  BRDFSHOT_CHECK(sphere_pixels >= 2 && !suns.empty());
  BRDFSHOT_CHECK(static_cast<size_t>(tables.rows()) == grid.size(), "tables and grid differ in bins");
  const Eigen::Index n = tables.cols();
  const Vec3 view(0, 0, 1);
  const double step = 2.0 / sphere_pixels, area = step * step;
  // Rows of radiance, one per (pixel, sun) that the sun lights, gathered in
  // blocks so that the Gram is a few matrix products, not thousands of
  // rank-one updates.
  constexpr Eigen::Index kBlock = 256;
  Eigen::MatrixXd rows(kBlock, n);
  Eigen::Index filled = 0;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  const auto flush = [&] {
    if (filled) gram.selfadjointView<Eigen::Lower>().rankUpdate(rows.topRows(filled).transpose(), area);
    filled = 0;
  };
  for (int py = 0; py < sphere_pixels; ++py)
    for (int px = 0; px < sphere_pixels; ++px) {
      const double x = -1 + (px + 0.5) * step, y = 1 - (py + 0.5) * step, r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const Vec3 normal(x, y, std::sqrt(1 - r2));
      // Any tangent frame serves: the tables are isotropic.
      const Frame frame = Frame::FromZX(normal, view);
      const Vec3 wo = frame.ToLocal(view);
      for (const Vec3& sun : suns) {
        const double cos_i = Dot(normal, sun);
        if (cos_i <= 0) continue;
        size_t idx[8];
        double w[8];
        const int k = grid.TrilinearCorners(ToHalfDiff(frame.ToLocal(sun), wo), idx, w);
        auto row = rows.row(filled);
        row.setZero();
        for (int c = 0; c < k; ++c) row += (cos_i * w[c]) * tables.row(static_cast<Eigen::Index>(idx[c])).cast<double>();
        if (++filled == kBlock) flush();
      }
    }
  flush();
  return gram.selfadjointView<Eigen::Lower>();
}

}  // namespace brdfshot
