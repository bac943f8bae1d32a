// A fit scored on a photo it was not fitted to.
//
// The question a BRDF must answer is how the material looks under lighting
// the fit never saw. Where the same object was photographed under more than
// one light (a second probe, a light stage, DiLiGenT's 96 lights), a photo
// held out of the fit answers it on real data: the fit's weights applied to
// that photo's basis images (its lighting, its pixels) predict the photo, and
// the prediction is compared with the pixels. No render, alignment or mask is
// involved: the basis images are rendered on the held-out photo's own pixels.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "fit/basis_images.h"
#include "fit/photo_fit.h"

namespace brdfshot {

struct PredictionError {
  double relative_rmse = 0;         // ‖p − y‖ / ‖y‖ over every pixel and channel
  double relative_rmse_scaled = 0;  // ‖s·p − y‖ / ‖y‖ at the best s (an HDR photo's scale may be unknown)
  double scale = 1;                 // that s, ⟨p, y⟩ / ⟨p, p⟩ (1 where p is zero)
};

// y and p: pixels × 3 of one photo. Error when they differ in size or y is black.
PredictionError ComparePrediction(const Eigen::MatrixXd& y, const Eigen::MatrixXd& p);

struct PhotoScore {
  size_t pixels = 0;
  PredictionError fit;                         // the fit's weights on the photo's basis images
  std::optional<PredictionError> lambert_ggx;  // the record's analytic baseline on the photo's lobes
};

// Scores `fit` (read from `fit_source`) against photo `y` (read from
// `photo_source`; pixels × 3 in the order of `basis`'s geometry), `basis`
// (read from `basis_source`) rendered under the photo's lighting. The fit's
// bases are found in the basis images by name; FileError naming
// `basis_source` where one is missing or the grid differs, or where y's rows
// are not the basis images' pixels, and naming `photo_source` where y is black. The Lambert +
// GGX baseline is scored where the record holds one and the basis images
// hold the same lobes.
PhotoScore ScoreFitOnPhoto(const FitRecord& fit, const std::string& fit_source, const BasisImages& basis,
                           const std::string& basis_source, const Eigen::MatrixXd& y, const std::string& photo_source);

}  // namespace brdfshot
