// MERL's materials as the neural BRDFs of Sztrajman et al. 2021 (shared/merl-nbrdf):
// a 6-21-21-3 MLP per material over Rusinkiewicz coordinates with φ_h = 0,
//   x = (sinθ_h, 0, cosθ_h, sinθ_d cosφ_d, sinθ_d sinφ_d, cosθ_d),
//   ρ = max(0, exp(relu(relu(x W1 + b1) W2 + b2) W3 + b3) − 1)   (1/sr, scales applied).
// Evaluated in batches with Eigen so a whole MERL grid is a few matrix products.
#pragma once

#include <Eigen/Core>
#include <string>

#include "fit/merl_brdf.h"
#include "util/eigen_types.h"

namespace brdfshot {

class NbrdfNetwork {
 public:
  // Loads <dir>/<name>_{fc1,b1,fc2,b2,fc3,b3}.npy; errors name the file and the
  // expected shape.
  static NbrdfNetwork Load(const std::string& npy_dir, const std::string& name);

  // Rows of `x` are inputs (N × 6); returns N × 3 RGB ρ, clamped at 0.
  MatrixXfR Eval(const MatrixXfR& x) const;
  Rgb EvalHalfDiff(const HalfDiff& hd) const;

  const std::string& name() const { return name_; }

 private:
  std::string name_;
  Eigen::MatrixXf w1_, w2_, w3_;  // [input, output]
  Eigen::RowVectorXf b1_, b2_, b3_;
};

// Network inputs for every lattice point of `grid` (row = grid index).
MatrixXfR NbrdfInputs(const MerlGrid& grid);

// Samples a network onto a grid as the merl-nbrdf README specifies (unmeasured
// below the horizon, values divided by the channel scales).
MerlBrdf NbrdfToMerl(const NbrdfNetwork& net, const MerlGrid& grid);

}  // namespace brdfshot
