#include "util/jpeg_structure.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace brdfshot {
namespace {

std::string Encode(const cv::Mat& img, std::vector<int> params = {}) {
  std::vector<uchar> buf;
  EXPECT_TRUE(cv::imencode(".jpg", img, buf, params));
  return std::string(buf.begin(), buf.end());
}

cv::Mat Noise(int w, int h) {
  cv::Mat img(h, w, CV_8UC3);
  cv::randu(img, cv::Scalar::all(0), cv::Scalar::all(255));
  return img;
}

}  // namespace

// OpenCV's own encoder, in its baseline, progressive and restart-marker forms,
// writes files the walk finds complete; every one of them cut short anywhere
// is found truncated — while OpenCV still decodes the cut file into an image,
// which is why the check exists.
TEST(JpegStructure, CompleteFilesPassAndEveryCutIsFound) {
  const cv::Mat img = Noise(96, 64);
  const std::vector<std::vector<int>> forms = {
      {}, {cv::IMWRITE_JPEG_PROGRESSIVE, 1}, {cv::IMWRITE_JPEG_RST_INTERVAL, 2}};
  for (const auto& params : forms) {
    const std::string full = Encode(img, params);
    EXPECT_EQ(JpegStructureProblem(full), "") << "form " << (params.empty() ? 0 : params[0]);
    for (size_t cut = 4; cut < full.size(); cut += full.size() / 23 + 1)
      EXPECT_NE(JpegStructureProblem(full.substr(0, cut)), "") << "cut at " << cut << " of " << full.size();
    EXPECT_NE(JpegStructureProblem(full.substr(0, full.size() - 1)), "") << "only the last byte missing";
  }
  const std::string half = Encode(img).substr(0, Encode(img).size() / 2);
  const cv::Mat decoded = cv::imdecode(std::vector<uchar>(half.begin(), half.end()), cv::IMREAD_COLOR);
  EXPECT_FALSE(decoded.empty()) << "OpenCV decodes a JPEG cut in half without an error";
}

// A camera's trailer after the end marker is allowed; a thumbnail inside an
// EXIF segment, with its own end marker, does not make a cut main image pass.
TEST(JpegStructure, TrailersPassAndAThumbnailsEndMarkerIsNotTheImages) {
  const std::string full = Encode(Noise(96, 64));
  EXPECT_EQ(JpegStructureProblem(full + std::string(1000, '\x55')), "");
  const std::string thumb = Encode(Noise(16, 16));
  std::string app1 = "Exif" + std::string(2, '\0') + thumb;
  const size_t len = app1.size() + 2;
  app1 = std::string("\xFF\xE1", 2) + static_cast<char>(len >> 8) + static_cast<char>(len & 0xFF) + app1;
  const std::string with_thumb = full.substr(0, 2) + app1 + full.substr(2);
  EXPECT_EQ(JpegStructureProblem(with_thumb), "");
  EXPECT_NE(JpegStructureProblem(with_thumb.substr(0, with_thumb.size() - 200)), "");
  EXPECT_NE(JpegStructureProblem("P6\n2 2\n255\n"), "") << "not a JPEG";
  EXPECT_NE(JpegStructureProblem(""), "");
}

}  // namespace brdfshot
