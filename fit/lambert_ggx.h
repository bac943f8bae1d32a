// The analytic baseline users would otherwise reach for: Lambert + GGX,
//   ρ_c(ω_i, ω_o) = kd_c / π + q · [F0_c (1 − s) + s] · D_α G_α / (4 cos θ_i cos θ_o),
// s = (1 − cos θ_d)⁵ (Schlick's Fresnel), D_α the GGX distribution, G_α
// Smith's height-correlated shadowing, q the specular scale shared by the
// channels (1 for an energy-normalised microfacet surface; it absorbs an
// exposure the calibration left open).
//
// Why a grid of roughness and a linear solve, not a non-linear optimiser from
// a few starts: for a fixed α the model is linear in (kd_c, q F0_c, q), so each
// α on the grid is solved exactly and globally (non-negative least squares on
// seven unknowns); the one non-linear parameter is searched exhaustively. The
// α grid is a set of tabulated lobes — every lobe is rendered through the same
// transport as the database's bases (fit/transport.h), so the comparison with
// the data-driven fits is on equal terms.
#pragma once

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <vector>

#include "fit/merl_grid.h"
#include "fit/nbrdf.h"

namespace brdfshot {

struct LambertGgxLobes {
  // GGX α (not the "perceptual" roughness √α of Blender or Unreal): 24
  // values in steps of 1.25× from a near-mirror (0.005) to a broad sheen
  // (0.8). A step of 1.5× costs metals that are exactly GGX half again of
  // their relit error (0.072 against 0.038 in `eval --targets standin`): a
  // highlight's peak goes as 1/α².
  std::vector<double> alphas = GeometricAlphas(0.005, 0.8, 24);
  static std::vector<double> GeometricAlphas(double first, double last, int count);

  // Lobe columns: 0 is Lambert (1/π); 1 + 2r and 2 + 2r are the GGX lobe of
  // alphas[r] times (1 − s) and times s.
  int columns() const { return 1 + 2 * static_cast<int>(alphas.size()); }
  // The lobes tabulated on `grid` in 1/sr (bins × columns), 0 where either
  // direction is below the horizon (as the database's tables).
  MatrixXfR Tables(const MerlGrid& grid) const;
  nlohmann::json ToJson() const;
  // Error naming `source` when `j` is not a lobe description.
  static LambertGgxLobes FromJson(const nlohmann::json& j, const std::string& source);
  bool operator==(const LambertGgxLobes& o) const { return alphas == o.alphas; }
};

// What a fit to one image needs of the lobe images L_c (pixels × columns):
// per channel LᵀL, Lᵀy and ‖y‖² — so a fit and its score under another
// lighting are quadratic forms, whatever the pixel count.
struct LobeSystem {
  std::array<Eigen::MatrixXd, 3> gram;
  std::array<Eigen::VectorXd, 3> z;
  std::array<double, 3> norm2{};
};

// From the lobe images (pixels × columns per channel) and the image (pixels × 3).
LobeSystem MakeLobeSystem(const std::array<MatrixXfR, 3>& L, const Eigen::MatrixXd& y);

struct LambertGgxFit {
  int alpha_index = -1;
  double alpha = 0;
  std::array<double, 3> diffuse_albedo{};  // kd
  double specular_scale = 0;               // q
  std::array<double, 3> scaled_f0{};       // q F0 as solved (what the weights hold, also when q = 0)
  Eigen::MatrixXd weights;                 // columns × 3: the fit as weights on the lobe columns
  double relative_residual = 0;            // ‖L w − y‖ / ‖y‖ at the chosen α
  std::vector<double> residual_by_alpha;   // the same at every α of the grid

  // F0 = (q F0) / q per channel (0 when q = 0); ≤ 1 not enforced.
  std::array<double, 3> SpecularF0() const;

  // Base colour, specular, roughness as a renderer takes them, the model and
  // the residual at every α; FromJson reads it back (weights rebuilt), an
  // Error naming `source` when it is not that or its α is not of `lobes`.
  nlohmann::json ToJson(const LambertGgxLobes& lobes) const;
  static LambertGgxFit FromJson(const nlohmann::json& j, const LambertGgxLobes& lobes, const std::string& source);
};

// The best α of the grid and its non-negative (kd, q F0, q). A singular
// system (a lobe that lights no pixel) is solved by the non-negative solver's
// ridge (fit/nonneg.h): one of the equally good answers.
LambertGgxFit FitLambertGgx(const LambertGgxLobes& lobes, const LobeSystem& s);

// ‖L w − y‖ / ‖y‖ over the three channels for weights `w` (columns × 3).
double LobeRelativeError(const LobeSystem& s, const Eigen::MatrixXd& w);

}  // namespace brdfshot
