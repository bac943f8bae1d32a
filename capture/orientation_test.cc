#include "capture/orientation.h"

#include <gtest/gtest.h>

#include <exiv2/exiv2.hpp>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

namespace brdfshot {
namespace {

// OpenCV's decoder applies the EXIF orientation itself unless told not to: an
// independent implementation to compare ours with, for all eight values.
TEST(Orientation, MatchesOpenCvsOwnExifHandling) {
  const auto dir = std::filesystem::temp_directory_path() / ("brdfshot_orient_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  cv::Mat img(6, 10, CV_8UC3);  // not square, asymmetric: every turn and flip differs
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) img.at<cv::Vec3b>(y, x) = cv::Vec3b(20 * x, 40 * y, 100);
  for (int o = 1; o <= 8; ++o) {
    const std::string f = (dir / ("o" + std::to_string(o) + ".jpg")).string();
    ASSERT_TRUE(cv::imwrite(f, img));
    auto meta = Exiv2::ImageFactory::open(f);
    Exiv2::ExifData exif;
    exif["Exif.Image.Orientation"] = uint16_t(o);
    meta->setExifData(exif);
    meta->writeMetadata();
    const cv::Mat stored = cv::imread(f, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
    const cv::Mat upright = cv::imread(f, cv::IMREAD_COLOR);
    ASSERT_EQ(stored.size(), img.size());
    const cv::Mat ours = ApplyExifOrientation(stored, o);
    ASSERT_EQ(ours.size(), upright.size()) << "orientation " << o;
    EXPECT_EQ(cv::norm(ours, upright, cv::NORM_INF), 0) << "orientation " << o;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace brdfshot
