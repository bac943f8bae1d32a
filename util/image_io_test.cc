#include "util/image_io.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace brdfshot {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("brdfshot_image_io_" + name)).string();
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// Where the size of an EXR's first attribute sits: after the 8-byte
// magic/version and "channels\0chlist\0".
constexpr size_t kChannelsSizeAt = 8 + sizeof("channels") + sizeof("chlist");

cv::Mat HdrRamp() {
  // 1e-4 … 1e6: a dark corner to a sun, beyond half's 65504.
  cv::Mat m(7, 9, CV_32FC3);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < 3; ++c) m.at<cv::Vec3f>(y, x)[c] = std::pow(10.0f, -4.0f + (x + 9 * y + c) * 10.0f / 65);
  return m;
}

TEST(ImageIo, FloatExrRoundTripIsExactIncludingSuns) {
  const cv::Mat m = HdrRamp();
  const std::string path = TempPath("float.exr");
  WriteExr(path, m);
  const cv::Mat r = ReadHdrImage(path);
  ASSERT_EQ(r.size(), m.size());
  EXPECT_EQ(cv::norm(r, m, cv::NORM_INF), 0.0);
  std::filesystem::remove(path);
}

TEST(ImageIo, OurExrMatchesOpenCvsDecoder) {
  setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 1);
  const cv::Mat m = HdrRamp();
  const std::string path = TempPath("cv.exr");
  WriteExr(path, m);
  cv::Mat bgr;
  try {
    bgr = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
  }
  if (bgr.empty()) GTEST_SKIP() << "this OpenCV build reads no EXR";
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  EXPECT_EQ(cv::norm(rgb, m, cv::NORM_INF), 0.0);
  std::filesystem::remove(path);
}

TEST(ImageIo, HalfExrKeepsElevenBitsAndSaturatesAboveItsRange) {
  cv::Mat m = HdrRamp();
  const std::string path = TempPath("half.exr");
  WriteExr(path, m, ExrPixel::kHalf);
  EXPECT_LT(std::filesystem::file_size(path), 7 * 9 * 3 * 4);
  // Half's largest finite value is 65504: larger ones become inf, which the
  // reader refuses, naming the file.
  EXPECT_THROW(ReadHdrImage(path), Error);
  m = cv::min(m, 6e4);
  WriteExr(path, m, ExrPixel::kHalf);
  const cv::Mat r = ReadHdrImage(path);
  for (int i = 0; i < static_cast<int>(m.total()) * 3; ++i) {
    const float a = m.ptr<float>()[i], b = r.ptr<float>()[i];
    if (a > 6.1e-5f) {  // normal halves: 11-bit mantissa
      EXPECT_LE(std::abs(b / a - 1), 1.0 / 2048) << a;
    }
  }
  std::filesystem::remove(path);
}

TEST(ImageIo, LuminanceOnlyExrReadsAsGrey) {
  const std::string path = TempPath("y.exr");
  std::vector<float> y = {0.5f, 2.0f, 1e5f, 3.0f, 4.0f, 5.0f};
  {
    Imf::Header h(3, 2);
    h.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile f(path.c_str(), h);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), 3 * sizeof(float)));
    f.setFrameBuffer(fb);
    f.writePixels(2);
  }
  const cv::Mat r = ReadHdrImage(path);
  ASSERT_EQ(r.cols, 3);
  ASSERT_EQ(r.rows, 2);
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(r.at<cv::Vec3f>(i / 3, i % 3)[c], y[i]);
    }
  std::filesystem::remove(path);
}

TEST(ImageIo, ErrorsNameTheFile) {
  const std::string path = TempPath("junk.exr");
  { std::ofstream(path) << "not an exr"; }
  try {
    ReadHdrImage(path);
    FAIL() << "junk accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  std::filesystem::remove(path);
  EXPECT_THROW(ReadHdrImage(TempPath("missing.exr")), Error);
  EXPECT_THROW(ReadHdrImage(std::filesystem::temp_directory_path().string()), Error);
}

// A data window that does not start at 0,0 (negative here, as crops and
// overscan renders write): its corner is the image's first pixel.
TEST(ImageIo, ExrDataWindowOffTheOriginReadsInPlace) {
  const std::string path = TempPath("window.exr");
  const Imath::Box2i window(Imath::V2i(-3, -2), Imath::V2i(1, 0));  // 5 × 3
  std::vector<float> y(15);
  for (int i = 0; i < 15; ++i) y[i] = 1.0f + i;
  {
    Imf::Header h(Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(9, 9)), window);
    h.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile f(path.c_str(), h);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), window, sizeof(float), 5 * sizeof(float)));
    f.setFrameBuffer(fb);
    f.writePixels(3);
  }
  const cv::Mat r = ReadHdrImage(path);
  ASSERT_EQ(r.cols, 5);
  ASSERT_EQ(r.rows, 3);
  for (int i = 0; i < 15; ++i) EXPECT_EQ(r.at<cv::Vec3f>(i / 5, i % 5)[1], y[i]) << "pixel " << i;
  std::filesystem::remove(path);
}

// A corrupt attribute size is refused before OpenEXR allocates it; the file is
// otherwise our own valid EXR, so the check is also shown not to refuse one.
TEST(ImageIo, ExrAttributeSizeBeyondTheFileIsRefused) {
  const std::string path = TempPath("attr.exr");
  WriteExr(path, HdrRamp());
  ASSERT_NO_THROW(ReadHdrImage(path));
  std::string bytes = ReadBytes(path);
  ASSERT_EQ(bytes.compare(8, 8, "channels"), 0);
  const int32_t huge = 1 << 30;
  bytes.replace(kChannelsSizeAt, 4, reinterpret_cast<const char*>(&huge), 4);
  WriteBytes(path, bytes);
  try {
    ReadHdrImage(path);
    FAIL() << "corrupt attribute size accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("attribute 'channels' claims 1073741824 bytes"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  std::filesystem::remove(path);
}

// A channel list whose declared size disagrees with its content (OpenEXR
// reads the content and goes on from its end, so the rest of the header is
// then read from the wrong place) is refused before OpenEXR parses it.
TEST(ImageIo, ExrChannelListSizeMustMatchItsContent) {
  const std::string path = TempPath("chlist.exr");
  WriteExr(path, HdrRamp());
  std::string bytes = ReadBytes(path);
  ASSERT_EQ(bytes.compare(8, 8, "channels"), 0);
  int32_t size;
  std::memcpy(&size, bytes.data() + kChannelsSizeAt, 4);
  ASSERT_EQ(size, 3 * (2 + 16) + 1);  // "B\0", "G\0", "R\0" + 16 bytes each, and the closing \0
  const int32_t wrong = size + 40;
  bytes.replace(kChannelsSizeAt, 4, reinterpret_cast<const char*>(&wrong), 4);
  WriteBytes(path, bytes);
  try {
    ReadHdrImage(path);
    FAIL() << "inconsistent channel list accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("attribute 'channels' declares 95 bytes, its content takes 55"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// A box attribute (the data window) declared longer than its 16 bytes is
// refused: OpenEXR would read the 16 and skip the rest, and the window would
// escape the size check (fuzz_probe: a 247-byte dataWindow).
TEST(ImageIo, ExrBoxAttributeMustBeSixteenBytes) {
  const std::string path = TempPath("box.exr");
  WriteExr(path, HdrRamp());
  std::string bytes = ReadBytes(path);
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  int32_t size;
  std::memcpy(&size, bytes.data() + at + key.size(), 4);
  ASSERT_EQ(size, 16);
  const int32_t longer = 40;
  bytes.replace(at + key.size(), 4, reinterpret_cast<const char*>(&longer), 4);
  WriteBytes(path, bytes);
  try {
    ReadHdrImage(path);
    FAIL() << "40-byte box2i accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("attribute 'dataWindow' declares 40 bytes, its content takes 16"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// Radiance HDR and PFM go through OpenCV, which decodes whatever the bytes
// are: the magic must match the extension (an EXR named .hdr is refused, not
// decoded by another path), a PFM's pixels must fit its file, and files
// OpenCV writes still read back (to RGBE's precision, PFM's exactly).
TEST(ImageIo, RadianceAndPfmMustBeWhatTheirExtensionSays) {
  const cv::Mat ramp = HdrRamp();
  cv::Mat bgr;
  cv::cvtColor(ramp, bgr, cv::COLOR_RGB2BGR);
  const std::string hdr = TempPath("ok.hdr"), pfm = TempPath("ok.pfm");
  ASSERT_TRUE(cv::imwrite(hdr, bgr));
  ASSERT_TRUE(cv::imwrite(pfm, bgr));
  const cv::Mat a = ReadHdrImage(hdr), b = ReadHdrImage(pfm);
  for (int i = 0; i < static_cast<int>(ramp.total()); ++i) {
    // RGBE: one shared exponent, 8-bit mantissas: each channel is exact to
    // 2⁻⁷ of the pixel's largest channel.
    const cv::Vec3f t = ramp.at<cv::Vec3f>(i);
    const float largest = std::max({t[0], t[1], t[2]});
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.at<cv::Vec3f>(i)[c], t[c], largest / 128);
      EXPECT_EQ(b.at<cv::Vec3f>(i)[c], t[c]);
    }
  }
  auto message = [](const std::string& path) {
    try {
      ReadHdrImage(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string exr_as_hdr = TempPath("exr.hdr");
  WriteExr(exr_as_hdr, ramp);
  EXPECT_NE(message(exr_as_hdr).find("not a Radiance HDR file"), std::string::npos) << message(exr_as_hdr);
  const std::string big = TempPath("big.pfm");
  { std::ofstream(big, std::ios::binary) << "PF\n100000 100000\n-1.0\nabcd"; }
  EXPECT_NE(message(big).find("more than its 26 bytes hold"), std::string::npos) << message(big);
  const std::string short_pfm = TempPath("short.pfm");
  const std::string pfm_bytes = ReadBytes(pfm);
  WriteBytes(short_pfm, pfm_bytes.substr(0, pfm_bytes.size() - 4));
  EXPECT_NE(message(short_pfm).find("truncated"), std::string::npos) << message(short_pfm);
  for (const std::string& p : {hdr, pfm, exr_as_hdr, big, short_pfm}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace brdfshot
