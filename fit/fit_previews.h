// The pictures `fit` leaves beside fit.json: the photo beside its
// reconstruction, and the fitted BRDF relit under other probes — what a user
// looks at before reading any number.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/latlong_probe.h"
#include "fit/basis_images.h"
#include "fit/merl_brdf.h"
#include "fit/transport.h"

namespace brdfshot {

// `dir`/`name`: the photo's pixels | the fit's reconstruction, one exposure.
std::string WritePhotoVersusFit(const BasisImages& basis, const Eigen::MatrixXd& photo,
                                const Eigen::MatrixXd& reconstruction, const std::string& dir,
                                const std::string& name = "photo_vs_fit.png");

// `dir`/relit_<probe>.png per probe: the BRDF on a 128-pixel sphere.
std::vector<std::string> WriteRelitPreviews(const MerlBrdf& brdf, const std::vector<LatLongProbe>& probes,
                                            const RenderQuality& quality, const std::string& dir);

}  // namespace brdfshot
