// Material classes (paper sec. 3): project the bases onto the first N left
// singular vectors of B, then fit a K-component full-covariance GMM by EM.
//
// Corrections to the paper, each measured in the leave-one-out table:
//  * M-step (eqs. 11–12) divides by N_j = Σ_i γ_j(b_i), not by π_j (the paper's
//    typo scales every mean and covariance by n). `paper_mstep` keeps the typo
//    for the "paper as written" baseline.
//  * Responsibilities in the log domain (log-sum-exp): the paper reports
//    numerical instability, which is underflow of exp(−½ Mahalanobis²).
//  * Covariances get `reg` × (mean variance of the data) on the diagonal, so a
//    class of a few collinear metals stays invertible.
#pragma once

#include <array>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace brdfshot {

// Coordinates of every basis on the first `dims` left singular vectors of B,
// computed from G = BᵀB alone: G = V S² Vᵀ, coordinates = S_N V_Nᵀ (dims × n).
Eigen::MatrixXd ProjectFromGram(const Eigen::MatrixXd& gram, int dims, Eigen::VectorXd* singular_values = nullptr);

// Lloyd's k-means with k-means++ seeding, best of `restarts` (fixed seed).
std::vector<int> KMeans(const Eigen::MatrixXd& points, int k, uint32_t seed, int restarts = 10);

struct GmmOptions {
  int dims = 4;
  int classes = 4;
  int max_iterations = 1000;
  double tolerance = 1e-9;  // relative change of the log-likelihood
  double reg = 1e-6;        // covariance ridge, relative to the data's mean variance
  uint32_t seed = 1;
  bool paper_mstep = false;  // reproduce eqs. 11–12 as printed (divide by π_j)
};

struct ClassModel {
  Eigen::MatrixXd coords;           // dims × n
  Eigen::VectorXd singular_values;  // first dims
  Eigen::VectorXd mix;              // K
  std::vector<Eigen::VectorXd> means;
  std::vector<Eigen::MatrixXd> covs;
  Eigen::MatrixXd resp;    // n × K, rows sum to one
  std::vector<int> label;  // argmax_j γ_j(b_i)
  double log_likelihood = 0;
  int iterations = 0;
  bool converged = false;
  bool paper_mstep = false;
  // What the bases are: their names in column order, and the database they
  // came from (label, grid). A fit checks the names against its basis images.
  std::vector<std::string> basis_names;
  std::string database;
  std::array<int, 3> grid{};

  int classes() const { return static_cast<int>(mix.size()); }
  std::vector<int> Members(int j) const;
  nlohmann::json ToJson() const;  // internal check: a name for every basis
  static ClassModel FromJson(const nlohmann::json& j, const std::string& source);
  void Write(const std::string& path) const;  // atomic
  static ClassModel Read(const std::string& path);
};

// EM on the columns of `coords` (dims × n), initialised from k-means.
ClassModel FitGmm(const Eigen::MatrixXd& coords, const GmmOptions& opt);

// Convenience: project (from the Gram matrix) and fit.
ClassModel BuildClassModel(const Eigen::MatrixXd& gram, const GmmOptions& opt);

// log N(x | μ, Σ) for each column of X (used by EM and by tests).
Eigen::VectorXd LogGaussian(const Eigen::MatrixXd& X, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov);

// "a / b / c / d": the number of bases in each class, in class order (reports).
std::string ClassSizes(const ClassModel& m);

}  // namespace brdfshot
