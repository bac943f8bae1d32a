#include "fit/fit_previews.h"

#include <opencv2/core.hpp>

#include "normals/sphere_geometry.h"
#include "util/image_io.h"

namespace brdfshot {

std::string WritePhotoVersusFit(const BasisImages& basis, const Eigen::MatrixXd& photo,
                                const Eigen::MatrixXd& reconstruction, const std::string& dir,
                                const std::string& name) {
  const cv::Mat photo_img = PixelsToImage(basis.geometry, photo);
  const cv::Mat recon_img = PixelsToImage(basis.geometry, reconstruction);
  cv::Mat side;
  cv::hconcat(photo_img, recon_img, side);
  const std::string path = dir + "/" + name;
  WritePngTonemapped(path, side, AutoExposure(photo_img));
  return path;
}

std::vector<std::string> WriteRelitPreviews(const MerlBrdf& brdf, const std::vector<LatLongProbe>& probes,
                                            const RenderQuality& quality, const std::string& dir) {
  std::vector<std::string> paths;
  const PixelGeometry pg = OrthographicSphere(128, 89.5);
  for (const LatLongProbe& probe : probes) {
    const cv::Mat img = PixelsToImage(pg, TransportOperator::Build(pg, probe, brdf.grid(), quality).Render(brdf));
    paths.push_back(dir + "/relit_" + probe.name() + ".png");
    WritePngTonemapped(paths.back(), img, AutoExposure(img));
  }
  return paths;
}

}  // namespace brdfshot
