// Solves with a symmetric tridiagonal matrix T shifted by λ, by the LDLᵀ
// recurrence without pivoting: T + λI is positive definite wherever it is
// solved here (a Gram matrix's tridiagonal form, λ ≥ 0), and for a positive
// definite tridiagonal matrix that recurrence is backward stable. A system
// held as Q T Qᵀ (Householder tridiagonalisation) is then solved at any λ in
// O(k) after one product with Qᵀ, with no eigenvectors computed.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace brdfshot {

// (T + λ_l I) x_l = b for every λ_l of `lj`, T of diagonal `d` and
// off-diagonal `e`: column l of the result. A pivot at or below
// 10⁻¹³ max|d| stops λ_l's recurrence and leaves its column zero (a singular
// system at λ = 0); `solved`, where given, gets 1 for each λ solved, 0 for
// each stopped.
Eigen::MatrixXd TridiagonalSolves(const Eigen::VectorXd& d, const Eigen::VectorXd& e, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& lj, std::vector<char>* solved = nullptr);

// The LDLᵀ factor of T + λI at one λ: its pivots, computed once, from which
// any number of right sides are solved. It refers to `d` and `e`, which must
// outlive it.
class ShiftedTridiagonal {
 public:
  ShiftedTridiagonal(const Eigen::VectorXd& d, const Eigen::VectorXd& e, double lambda);
  // False where a pivot is at or below 10⁻¹³ max|d| (the recurrence stops
  // there): Solve is then an internal error.
  bool ok() const { return ok_; }
  // (T + λI)⁻¹ B, every column.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& B) const;

 private:
  const Eigen::VectorXd& d_;
  const Eigen::VectorXd& e_;
  Eigen::VectorXd piv_;
  bool ok_ = true;
};

}  // namespace brdfshot
