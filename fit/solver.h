// The class-wise regularised solve (paper sec. 4, eq. 22 with the corrected
// M-step, docs/method.md) and its baselines.
//
// Per scene and light channel c the basis images Y_c (pixels × n) enter through
// their Gram matrix G_c = Y_cᵀY_c (double), and an observation y_c through
// z_c = Y_cᵀy_c and ‖y_c‖². Per class j (members J, c_j of them) the solve is
//   minimise ‖Y_J w − y‖² + λ_j ‖w − μ'‖²,  μ' = 1/c_j,  λ_j = λ ‖y‖²/c_j,
// i.e. (G_JJ + λ_j I) v = z_J − G_JJ μ', w = μ' + v. G_JJ = V diag(e) Vᵀ is
// decomposed once per scene and class (it does not depend on the photo), so a
// solve is two c_j × c_j products for any λ — which is what lets the
// regularisation be chosen per capture (fit/lambda_choice.h) at almost no cost.
//
// Normal equations square the conditioning: their error is about κ·ε with
// κ = (e_max + λ_j)/(e_min + λ_j). When κ > kMaxNormalCondition (λ near 0 with
// nearly collinear bases) the solve falls back to a complete orthogonal
// decomposition of the augmented system [R_J; √λ_j I] built on the Householder
// QR of Y (never squared), which returns the minimum-norm correction w − μ'
// when the system is singular. Without a QR (FactorBasisImages(.., false)) the
// fallback is the eigen-solve with eigenvalues below 1e-13 e_max dropped
// (minimum-norm, truncated); ClassSolution::path says which ran.
// The class is chosen by the data residual summed over R, G, B (sec. 4.6).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fit/bin_constraints.h"
#include "util/eigen_types.h"

namespace brdfshot {

// Beyond this condition of G_JJ + λ_j I the normal equations lose more than
// ~1e-8 of relative accuracy: the QR path is taken.
constexpr double kMaxNormalCondition = 1e8;

// One channel's basis images, factored.
struct ChannelFactor {
  Eigen::MatrixXd gram;  // YᵀY (n × n)
  // Householder QR of Y and its n × n R (zero rows padded when pixels < n);
  // null / empty unless asked for.
  std::shared_ptr<const Eigen::HouseholderQR<Eigen::MatrixXd>> qr;
  Eigen::MatrixXd R;
  bool has_qr() const { return qr != nullptr; }
};
std::array<ChannelFactor, 3> FactorBasisImages(const std::array<MatrixXfR, 3>& Y, bool with_qr = false);
void AddQr(const std::array<MatrixXfR, 3>& Y, std::array<ChannelFactor, 3>* f);

struct Observation {                    // what a solve needs of an image
  std::array<Eigen::VectorXd, 3> z;     // Y_cᵀ y_c
  std::array<Eigen::VectorXd, 3> z_qr;  // first n entries of Q_cᵀ y_c (only with a QR)
  std::array<double, 3> norm2{};        // ‖y_c‖²
};
// y: pixels × 3, the same pixels as Y's rows.
Observation MakeObservation(const std::array<ChannelFactor, 3>& f, const std::array<MatrixXfR, 3>& Y,
                            const Eigen::MatrixXd& y);
// YᵀY over `rows` (all rows when empty) in double. Not GramMatrix (database.h):
// its float sums within 8192-row blocks are good to ~1e-4, and the normal
// equations here are solved at condition numbers up to 1e8.
Eigen::MatrixXd GramOfRows(const MatrixXfR& Y, const std::vector<int>& rows = {});

// Y_cᵀ y over `rows` (all rows when empty), in double: float rows are widened
// as they are read, so neither the sum over thousands of pixels nor a copy of
// Y in double costs precision or memory.
Eigen::VectorXd ProjectRows(const MatrixXfR& Y, const Eigen::VectorXd& y, const std::vector<int>& rows = {});

// The observation of basis columns `col[c]` themselves (y_c = Y_c e_col): exact
// from the factors, as leave-one-out needs.
Observation BasisObservation(const std::array<ChannelFactor, 3>& f, const std::array<int, 3>& col);

// G_JJ = V diag(e) Vᵀ per channel for one class (e ascending, clamped at 0),
// or, factored with SpectrumParts::kTridiagonal, G_JJ = Q T Qᵀ with its
// eigenvalues e and no V.
struct ClassSpectrum {
  std::vector<int> members;
  std::array<Eigen::VectorXd, 3> e;
  std::array<Eigen::MatrixXd, 3> V;     // empty unless factored with SpectrumParts::kValuesAndVectors
  std::array<Eigen::MatrixXd, 3> gram;  // G_JJ
  // G_JJ μ', μ' the class prior (1/|J| for each member): every solve,
  // residual and sensitivity starts from z_J − G_JJ μ', so it is formed once
  // per class, not once per photo and λ.
  std::array<Eigen::VectorXd, 3> gram_prior;
  // SpectrumParts::kTridiagonal: Q formed, T's diagonal and off-diagonal.
  std::array<Eigen::MatrixXd, 3> Q;
  std::array<Eigen::VectorXd, 3> diagonal, off_diagonal;
  bool has_vectors() const { return members.empty() || V[0].size() > 0; }
  bool tridiagonal() const { return !members.empty() && Q[0].size() > 0; }
  // Whether it solves at any λ through its factor (SolveClassSystem).
  bool solvable() const { return has_vectors() || tridiagonal(); }
};
// What FactorClasses computes. The eigenvalues give the condition numbers and
// the λ search's bound; the eigenvectors or the tridiagonal form are what
// makes a solve at any λ two small products, which the chosen class's solve,
// GCV, the prior sensitivity and the bin constraint use. A class solved once
// at one fixed λ needs only the eigenvalues — about a fifth of the whole
// decomposition's time (4.7 against 22 ms at 297 bases) — and SolveClass then
// takes a Cholesky factor of G_JJ + λ_j I where it is well conditioned (the
// QR route where not). The tridiagonal form with Q formed and T's eigenvalues
// costs about half of the eigenvectors (the QR iteration's rotations
// accumulated into V are most of their cost) and serves every λ whose
// e_min + λ_j stays above SolveClassSystem's floor (10⁻¹³ e_max), as a
// condition bound of at most 10¹³ keeps every λ the search may pick (the
// default's is at most 10¹²); below it, the eigenvectors of T are computed
// for that solve.
enum class SpectrumParts { kValuesAndVectors, kEigenvalues, kTridiagonal };
std::vector<ClassSpectrum> FactorClasses(const std::array<ChannelFactor, 3>& f,
                                         const std::vector<std::vector<int>>& members,
                                         SpectrumParts parts = SpectrumParts::kValuesAndVectors);

// (G_JJ + λ_l I)⁺ r for every λ_l of `lj`, channel c of a solvable class:
// column l. Directions with e + λ_l at or below 10⁻¹³ e_max are left out (the
// minimum-norm correction). Through V where the class holds it; through
// Q and T's recurrence (fit/tridiagonal.h) where it is held tridiagonal and
// e_min + λ_l is above that floor, else through T's eigenvectors, computed
// for that call.
Eigen::MatrixXd SolveClassSystem(const ClassSpectrum& cls, int c, const Eigen::VectorXd& r, const Eigen::VectorXd& lj);

struct SolveOptions {
  double lambda = 0.5;
};

struct ClassSolution {
  int members = 0;
  double residual = 0;                // Σ_c ‖Y_J w_c − y_c‖²
  std::array<double, 3> condition{};  // of the least-squares matrix [Y_J; √λ_j I] per channel
  std::array<double, 3> lambda_j{};   // the weight actually applied per channel
  std::string path;                   // "normal", "qr", "normal-truncated" (worst over channels), or the constraint's
  Eigen::MatrixXd weights;            // n × 3, zero outside the class
  // n × 3: the same solve without the constraint (`weights` where there is
  // none), so the signed fit beside a constrained one costs no second solve.
  // Empty under WeightConstraint::kWeights, whose solve has no unconstrained
  // step.
  Eigen::MatrixXd unconstrained_weights;
};

struct ClasswiseFit {
  int chosen = -1;
  std::vector<ClassSolution> classes;
  const Eigen::MatrixXd& weights() const { return classes.at(chosen).weights; }
};

// `lambda[j]` per class (empty classes are skipped).
ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                            const Observation& obs, const std::vector<double>& lambda);
ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                            const Observation& obs, const SolveOptions& opt);
// Convenience: factors the classes first.
ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const Observation& obs,
                            const std::vector<std::vector<int>>& members, const SolveOptions& opt);

// What a class's solve keeps non-negative.
struct WeightConstraint {
  enum class Kind {
    kNone,
    kWeights,  // w ≥ 0 (fit/nonneg.h): the BRDF is non-negative everywhere, but only sums of bases fit
    kBins,     // Σ w_i b_i ≥ 0 at sampled bins (fit/bin_constraints.h)
  };
  Kind kind = Kind::kNone;
  // kBins: the tables' rows at the sampled bins, restricted to the class's
  // members in their order (bins × members).
  const BinRows* bins = nullptr;
};

// One class's solve over R, G, B at weight λ (λ_j = λ‖y_c‖²/c_j per channel),
// under `constraint` (path "nonneg-weights" / "nonneg-bins" when one applies).
// A class neither with eigenvectors nor tridiagonal is solved by Cholesky (path "normal") while
// κ ≤ kMaxNormalCondition, else by the QR route; without either (no QR) or
// under the bin constraint it is an internal error.
ClassSolution SolveClass(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls, const Observation& obs,
                         double lambda, const WeightConstraint& constraint = {});
// Σ_c ‖Y_J w_c − y_c‖² of weights wJ over the class's members (members × 3),
// from its Gram matrices: ClassSolution::residual.
double ClassResidual(const ClassSpectrum& cls, const Observation& obs, const Eigen::MatrixXd& wJ);

// w_J = μ' + V diag(1/(e + λ_j)) Vᵀ (z_J − G_JJ μ') for channel c of a class:
// the normal equations through the class's spectrum, any λ_j ≥ 0 (directions
// with e + λ_j below 1e-13 e_max keep the prior); SolveClassSystem for a
// class held tridiagonal.
Eigen::VectorXd SolveFromSpectrum(const ClassSpectrum& cls, int c, const Eigen::VectorXd& zJ, double lambda_j);

// One regularised solve: argmin ‖A w − z‖² + lambda ‖w − prior‖², by a QR of
// [A; √λ I] (λ > 0), or, at λ = 0, its complete orthogonal decomposition: the
// minimum-norm correction of the prior where A's columns are dependent.
Eigen::VectorXd SolveRidge(const Eigen::MatrixXd& A, const Eigen::VectorXd& z, double lambda,
                           const Eigen::VectorXd& prior, double* condition = nullptr);

// Plain least squares over `columns` (minimum-norm, by COD on the QR's R; the
// factors must have a QR): the paper's baseline.
Eigen::MatrixXd SolveLeastSquares(const std::array<ChannelFactor, 3>& f, const Observation& obs,
                                  const std::vector<int>& columns);

}  // namespace brdfshot
