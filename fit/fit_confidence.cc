#include "fit/fit_confidence.h"

#include <algorithm>
#include <cmath>

#include "fit/database.h"
#include "util/check.h"

namespace brdfshot {

double PriorSensitivity(const ClassSpectrum& cls, const Observation& obs, double lambda,
                        const Eigen::MatrixXd& metric) {
  const std::vector<int>& J = cls.members;
  BRDFSHOT_CHECK(!J.empty() && lambda >= 0, "a prior sensitivity needs a class and λ ≥ 0");
  BRDFSHOT_CHECK(metric.rows() == static_cast<Eigen::Index>(J.size()) && metric.cols() == metric.rows(),
                 "the BRDF metric is not over the class's bases");
  const Eigen::MatrixXd& M = metric;
  const double cj = static_cast<double>(J.size());
  double norm2 = 0, down2 = 0, up2 = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd zJ = obs.z[c](J);
    const double scale = obs.norm2[c] / cj;  // λ_j = λ ‖y_c‖² / c_j, as SolveClass
    const Eigen::VectorXd w = SolveFromSpectrum(cls, c, zJ, lambda * scale);
    const Eigen::VectorXd down = SolveFromSpectrum(cls, c, zJ, lambda / 10 * scale) - w;
    const Eigen::VectorXd up = SolveFromSpectrum(cls, c, zJ, std::max(10 * lambda, 1e-4) * scale) - w;
    norm2 += w.dot(M * w);
    down2 += down.dot(M * down);
    up2 += up.dot(M * up);
  }
  if (!(norm2 > 0)) return 0;
  return std::sqrt(std::max(0.0, down2) / norm2 + std::max(0.0, up2) / norm2);
}

Eigen::MatrixXd SampledCosineGram(const MatrixXfR& tables, const MerlGrid& grid, const std::vector<int>& members,
                                  int stride) {
  BRDFSHOT_CHECK(stride >= 1 && !members.empty());
  const std::vector<float> weight = CosineWeights(grid);
  BRDFSHOT_CHECK(static_cast<Eigen::Index>(weight.size()) == tables.rows(), "tables and grid differ in bins");
  const Eigen::Index rows = (tables.rows() + stride - 1) / stride, k = static_cast<Eigen::Index>(members.size());
  Eigen::MatrixXd S(rows, k);  // cos θ_i cos θ_o · b_J per sampled bin: SᵀS weighs each by cos²
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index bin = r * stride;
    for (Eigen::Index i = 0; i < k; ++i) S(r, i) = static_cast<double>(weight[bin]) * tables(bin, members[i]);
  }
  return S.transpose() * S;
}

}  // namespace brdfshot
