// The class-wise regularised solve (paper sec. 4, eq. 22 as corrected in
// DESIGN.md) and its baselines.
//
// Per scene and light channel c the basis images are factored once, Y_c = Q_c R_c
// (Householder QR, double). Any observation then enters only through
// z_c = Q_cᵀ y_c, and any subset J of bases through the columns R_c[:, J]:
//   ‖Y_J w − y‖² = ‖R_J w − z‖² + (‖y‖² − ‖z‖²).
// So a class solve is an (n + c_j) × c_j problem, independent of the pixel count,
// and leaving a material out is dropping columns — no refactorisation.
//
// Per class j (c_j members) and channel: minimise ‖R_J w − z‖² + λ_j ‖w − μ'‖²,
// μ' = 1/c_j, λ_j = λ ‖y‖²/c_j, by a complete orthogonal decomposition of the
// augmented matrix [R_J; √λ_j I] (never the normal equations). When that matrix
// is singular (λ = 0 and collinear bases) the COD returns the minimum-norm
// correction w − μ', which is finite; the condition number is reported (∞ then).
// The class is chosen by the data residual summed over R, G, B (sec. 4.6).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <array>
#include <vector>

#include "fit/nbrdf.h"

namespace brdfshot {

// Q R of one channel's basis images, plus its Gram matrix (for image metrics).
struct ChannelFactor {
  Eigen::HouseholderQR<Eigen::MatrixXd> qr;
  Eigen::MatrixXd R;     // n × n upper triangular (top of the QR's R)
  Eigen::MatrixXd gram;  // YᵀY = RᵀR, kept explicitly for metrics
  Eigen::VectorXd Project(const Eigen::VectorXd& y) const;  // first n entries of Qᵀy
};
std::array<ChannelFactor, 3> FactorBasisImages(const std::array<MatrixXfR, 3>& Y);

struct SolveOptions {
  double lambda = 0.5;
  bool condition = true;  // compute condition numbers (an SVD per class; skip in bulk eval)
};

struct Observation {          // what a solve needs of an image
  std::array<Eigen::VectorXd, 3> z;  // Q_cᵀ y_c
  std::array<double, 3> norm2{};     // ‖y_c‖²
};
Observation MakeObservation(const std::array<ChannelFactor, 3>& f, const Eigen::MatrixXd& y);  // y: pixels × 3

struct ClassSolution {
  int members = 0;
  double residual = 0;               // Σ_c ‖R_J w_c − z_c‖² (in-range part)
  std::array<double, 3> condition{};  // of [R_J; √λ_j I] per channel
  Eigen::MatrixXd weights;           // n × 3, zero outside the class
};

struct ClasswiseFit {
  int chosen = -1;
  std::vector<ClassSolution> classes;
  const Eigen::MatrixXd& weights() const { return classes.at(chosen).weights; }
};

// `members[j]`: basis indices of class j (empty classes are skipped).
ClasswiseFit SolveClasswise(const std::array<Eigen::MatrixXd, 3>& R, const Observation& obs,
                            const std::vector<std::vector<int>>& members, const SolveOptions& opt);

// One regularised solve: argmin ‖A w − z‖² + lambda ‖w − prior‖² via COD.
Eigen::VectorXd SolveRidge(const Eigen::MatrixXd& A, const Eigen::VectorXd& z, double lambda,
                           const Eigen::VectorXd& prior, double* condition = nullptr);

// Plain least squares over `columns` (minimum-norm): the paper's baseline.
Eigen::MatrixXd SolveLeastSquares(const std::array<Eigen::MatrixXd, 3>& R, const Observation& obs,
                                  const std::vector<int>& columns);

}  // namespace brdfshot
