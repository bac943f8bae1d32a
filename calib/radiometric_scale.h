// The radiometric scale between a photo and its light probe: how many photo
// units one probe unit of radiance becomes (per channel). Merged brackets are
// in relative units (code / exposure), and a probe from another camera, another
// white balance or the web is in units of its own, so a BRDF fitted without this
// factor is off by it: albedo × k.
//
// From a reference card: a flat diffuse target of known albedo a (a grey card,
// Spectralon) in the photo, lit by the same environment. Its radiance is
// a/π · E(n), E the probe's irradiance on the card's normal n, so
//   scale_c = photo_c(card) / (a/π · E_c(R n)),
// R the camera → probe rotation. Only the card's albedo is assumed; exposure,
// ISO, aperture, white balance and the probe's units all cancel.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "calib/latlong_probe.h"
#include "util/rotation.h"
#include "util/vec3.h"

namespace brdfshot {

// E(n) = Σ_texels L(ω) max(0, n·ω) dω over the whole probe (exact for the
// probe as piecewise constant; no sampling). `normal` need not be unit.
cv::Vec3d Irradiance(const LatLongProbe& probe, const Vec3& normal);

struct ReferenceCard {
  cv::Rect region;              // pixels of the card in the photo
  double albedo = 0.18;         // diffuse reflectance (a photographer's grey card)
  Vec3 normal_camera{0, 0, 1};  // card normal in the camera frame (+Z: facing the camera)
};

struct RadiometricScale {
  cv::Vec3d scale{1, 1, 1};  // photo radiance per probe radiance, per channel
  cv::Vec3d measured;        // mean photo radiance over the card
  cv::Vec3d predicted;       // a/π · E in probe units
  double spread = 0;         // card: std / mean of its luminance (> 0.1: not evenly lit);
                             // merges: max/min − 1 of the response ratio over mid codes
  int pixels = 0;            // card: finite pixels averaged
};

// `photo`: CV_32FC3 linear RGB. Error (naming the problem) when the region is
// empty or leaves the photo, holds no finite pixel, the mean is not positive,
// or the card receives no light from the probe (E = 0 in some channel).
RadiometricScale ScaleFromReferenceCard(const cv::Mat& photo, const ReferenceCard& card, const LatLongProbe& probe,
                                        const Rotation& camera_to_probe);

}  // namespace brdfshot

namespace brdfshot {

// From exposure metadata: the sidecars `brdfshot merge` wrote for the sample's
// photo and for the probe. Merged radiance is code-linear value / (t · ISO/100
// / N²), so with one camera the exposure settings already cancel; what is left
// is each merge's own normalisation:
//  * RAW both: the white-balance multipliers applied, scale_c = wb_photo / wb_probe;
//  * 8/16-bit both: the two response curves, scale_c = their ratio over the
//    middle codes (1 exactly when the photo reused the probe's response, as the
//    Makefile does); `spread` is how far the ratio varies over those codes.
// Error (naming `photo_source` or `probe_source`) for a sidecar that is not a
// merge's, for two different cameras (their sensitivities differ: use a card)
// or for RAW mixed with developed frames.
RadiometricScale ScaleFromMergeSidecars(const nlohmann::json& photo, const std::string& photo_source,
                                        const nlohmann::json& probe, const std::string& probe_source);

}  // namespace brdfshot
