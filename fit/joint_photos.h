// Several photos of one material fitted as one: the same sphere under other
// probes, or turned, each photo with its own basis images. A photo lit from
// one side says little about the BRDF at the angles another photo sees well;
// stacking their pixels gives one least-squares problem over all of them.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/basis_images.h"

namespace brdfshot {

struct JointPhotos {
  BasisImages basis;               // every photo's basis images, rows stacked in photo order
  Eigen::MatrixXd y;               // every photo's pixels (pixels × 3), stacked and scaled
  std::vector<size_t> pixels;      // pixels per photo
  std::vector<double> scale;       // each photo's factor: 1 / its RMS pixel value
  std::vector<int> fold_of_pixel;  // cross-validation wedges, each photo's own (WedgeFolds)
  // RelativePixelNoise of the stack: each photo's own, pooled over the
  // photos' pixels (each is scaled to RMS 1, so their noise adds as ε²);
  // kUnknownNoise where any photo's cannot be measured.
  double relative_noise = 0;
};

// Stacks the photos. Each is scaled by the inverse of its RMS pixel value, its
// basis images by the same factor (so the model stays exact), so that every
// photo weighs the same in the fit whatever its exposure and lighting. The
// basis images must be of the same bases, in the same order, from the same
// database and grid: FileError naming the file otherwise.
JointPhotos StackPhotos(const std::vector<BasisImages>& bases, const std::vector<Eigen::MatrixXd>& pixels,
                        const std::vector<std::string>& basis_paths, int folds);

}  // namespace brdfshot
