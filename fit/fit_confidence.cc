#include "fit/fit_confidence.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"

namespace brdfshot {

double PriorSensitivity(const ClassSpectrum& cls, const Observation& obs, double lambda,
                        const Eigen::MatrixXd& metric) {
  const std::vector<int>& J = cls.members;
  BRDFSHOT_CHECK(!J.empty() && lambda >= 0, "a prior sensitivity needs a class and λ ≥ 0");
  BRDFSHOT_CHECK(metric.rows() == metric.cols() && *std::max_element(J.begin(), J.end()) < metric.rows(),
                 "the BRDF metric does not cover the class's bases");
  const Eigen::MatrixXd M = metric(J, J);
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

}  // namespace brdfshot
