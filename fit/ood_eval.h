// Evaluation on materials that are not in the database (evaluation set b):
// each target material is rendered under every probe, fitted from its image
// under probe A with all the database's bases, and scored relit under every
// probe B ≠ A. As in leave-one-out, everything is a quadratic form: with the
// bases' Gram matrices G_b, the cross products X_b = Y_bᵀ y_b of the bases'
// and the target's images and the targets' ‖y_b‖², the relit error of weights
// w is √(Σ_c w_cᵀG_b w_c − 2 w_cᵀX_b + ‖y_b‖²) / ‖y_b‖.
// Methods: "auto", "auto-signed", "ours", "paper", "lsq" as in leave-one-out,
// and "relit-oracle": the weights that minimise the relit error summed over
// the other fitted probes themselves — the floor no fit from one photo can beat
// there (scoring-only scenes are not part of its objective).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "fit/loo_eval.h"

namespace brdfshot {

// The targets' images against one scene's basis images.
struct TargetScene {
  std::array<Eigen::MatrixXd, 3> cross;                    // n × T: Y_cᵀ (target t's channel-c image)
  std::array<Eigen::MatrixXd, 3> cross_qr;                 // n × T: first n entries of Q_cᵀ (target image)
  std::array<Eigen::VectorXd, 3> self;                     // T: ‖target image‖²
  std::vector<std::array<Eigen::MatrixXd, 3>> fold_cross;  // per wedge
  std::vector<std::array<Eigen::VectorXd, 3>> fold_self;
  // The scene's basis images and the targets' images (as MakeTargetScene's Y
  // and Yt), for the noise a fit leaves (BoundPixelNoise); null: not read.
  const std::array<MatrixXfR, 3>* images = nullptr;
  const std::array<MatrixXfR, 3>* target_images = nullptr;
};

// Y: the scene's basis images (pixels × n per channel), Yt: the targets' images
// (pixels × 3T, column 3t + c is target t's channel c); cross_qr only when `f`
// holds the QR (scenes fits are made from).
TargetScene MakeTargetScene(const std::array<ChannelFactor, 3>& f, const std::array<MatrixXfR, 3>& Y,
                            const std::array<MatrixXfR, 3>& Yt, const std::vector<int>& fold_of_pixel, int folds);

// `bases`: the database's scenes (with folds and QR) and Gram matrix; `scenes`
// parallel to bases.scenes; `targets` the target names.
LooResult RunOutOfDatabase(const LooInputs& bases, const std::vector<TargetScene>& scenes,
                           const std::vector<std::string>& targets, const LooOptions& opt);

}  // namespace brdfshot
