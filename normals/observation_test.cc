#include "normals/observation.h"

#include <gtest/gtest.h>

#include "util/check.h"

namespace brdfshot {
namespace {

TEST(ObservePixels, RadianceAtEachPixelDividedByTheScale) {
  cv::Mat photo(8, 10, CV_32FC3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 10; ++x) photo.at<cv::Vec3f>(y, x) = cv::Vec3f(x, y, x + 10 * y);
  PixelGeometry g;
  g.width = 10;
  g.height = 8;
  for (int k = 0; k < 20; ++k) {
    g.x.push_back(k % 10);
    g.y.push_back(k / 10 + 3);
    g.normal.push_back(Vec3(0, 0, 1));
    g.view.push_back(Vec3(0, 0, 1));
  }
  const Observations obs = ObservePixels(photo, g, cv::Vec3d(2, 4, 8), "s.json");
  ASSERT_EQ(obs.rgb.rows(), 20);
  for (int k = 0; k < 20; ++k) {
    const double x = k % 10, y = k / 10 + 3;
    EXPECT_DOUBLE_EQ(obs.rgb(k, 0), x / 2);
    EXPECT_DOUBLE_EQ(obs.rgb(k, 1), y / 4);
    EXPECT_DOUBLE_EQ(obs.rgb(k, 2), (x + 10 * y) / 8);
  }
  EXPECT_EQ(obs.geometry.x, g.x);
  // Fewer than 16 pixels cannot support a fit: refused, naming the geometry's file.
  PixelGeometry few = g;
  few.x.resize(15), few.y.resize(15), few.normal.resize(15), few.view.resize(15);
  try {
    ObservePixels(photo, few, cv::Vec3d(1, 1, 1), "s.json");
    ADD_FAILURE() << "15 pixels accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: leaves 15 usable pixels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace brdfshot
