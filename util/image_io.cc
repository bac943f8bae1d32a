#include "util/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {

namespace {
std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

// Read as 32-bit float whatever the file stores: the RGBA interface would hand
// back half floats, which lose precision and turn a sun above 65504 into inf.
cv::Mat ReadExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > (1L << 31)) throw FileError(path, "bad data window");
    const Imf::ChannelList& ch = file.header().channels();
    const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
    if (!rgb && !ch.findChannel("Y")) throw FileError(path, "has neither R, G, B nor Y channels");
    cv::Mat out(static_cast<int>(h), static_cast<int>(w), CV_32FC3);
    char* origin = reinterpret_cast<char*>(out.ptr<float>()) -
                   (static_cast<long>(dw.min.x) + static_cast<long>(dw.min.y) * w) * 3 * sizeof(float);
    const size_t xs = 3 * sizeof(float), ys = xs * w;
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (rgb ? 3 : 1); ++c)
      fb.insert(rgb ? names[c] : "Y", Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xs, ys, 1, 1, 0.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (!rgb) {  // luminance-only file: grey
      cv::Mat y;
      cv::extractChannel(out, y, 0);
      cv::merge(std::vector<cv::Mat>{y, y, y}, out);
    }
    return out;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw FileError(path, std::string("not a readable OpenEXR file: ") + e.what());
  }
}
}  // namespace

cv::Mat ReadHdrImage(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError(path, "is a folder, expected an image");
  if (!std::filesystem::exists(path, ec)) throw FileError(path, "no such file");
  const std::string ext = LowerExtension(path);
  cv::Mat rgb;
  if (ext == ".exr") {
    rgb = ReadExr(path);
  } else if (ext == ".hdr" || ext == ".pic" || ext == ".pfm") {
    cv::Mat bgr;
    try {
      bgr = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
    } catch (const cv::Exception& e) {
      throw FileError(path, std::string("cannot decode: ") + e.what());
    }
    if (bgr.empty()) throw FileError(path, "cannot decode as " + ext + " (truncated or not that format)");
    bgr.convertTo(bgr, CV_32FC3);
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  } else {
    throw FileError(path, "unknown HDR extension '" + ext + "' (expected .exr, .hdr or .pfm)");
  }
  if (!cv::checkRange(rgb, true, nullptr, -1e30, 1e30))
    throw FileError(path, "contains NaN or Inf pixels");
  return rgb;
}

void WriteExr(const std::string& path, const cv::Mat& rgb, ExrPixel pixel) {
  BRDFSHOT_CHECK(rgb.type() == CV_32FC3, "WriteExr wants CV_32FC3 RGB");
  const cv::Mat img = rgb.isContinuous() ? rgb : rgb.clone();
  std::vector<half> halves;
  if (pixel == ExrPixel::kHalf) {
    halves.resize(img.total() * 3);
    const float* f = img.ptr<float>();
    for (size_t i = 0; i < halves.size(); ++i) halves[i] = half(f[i]);
  }
  WriteFileAtomicByName(path, [&](const std::string& tmp) {
    const Imf::PixelType type = pixel == ExrPixel::kHalf ? Imf::HALF : Imf::FLOAT;
    const size_t bytes = pixel == ExrPixel::kHalf ? sizeof(half) : sizeof(float);
    Imf::Header header(img.cols, img.rows);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(type));
    Imf::OutputFile file(tmp.c_str(), header);
    Imf::FrameBuffer fb;
    char* base = pixel == ExrPixel::kHalf ? reinterpret_cast<char*>(halves.data())
                                          : reinterpret_cast<char*>(const_cast<float*>(img.ptr<float>()));
    const size_t xs = 3 * bytes, ys = xs * img.cols;
    fb.insert("R", Imf::Slice(type, base, xs, ys));
    fb.insert("G", Imf::Slice(type, base + bytes, xs, ys));
    fb.insert("B", Imf::Slice(type, base + 2 * bytes, xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(img.rows);
  });
}

void WritePng(const std::string& path, const cv::Mat& bgr8) {
  WriteFileAtomicByName(path, [&](const std::string& tmp) {
    if (!cv::imwrite(tmp, bgr8)) throw Error("OpenCV could not encode PNG");
  });
}

void WritePngTonemapped(const std::string& path, const cv::Mat& rgb, double exposure) {
  WritePng(path, TonemapToBgr8(rgb, exposure));
}

cv::Mat TonemapToBgr8(const cv::Mat& rgb, double exposure) {
  cv::Mat scaled = rgb * exposure, out8(rgb.size(), CV_8UC3);
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x) {
      const cv::Vec3f p = scaled.at<cv::Vec3f>(y, x);
      cv::Vec3b& q = out8.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double v = std::pow(std::clamp(static_cast<double>(p[c]), 0.0, 1.0), 1.0 / 2.2);
        q[2 - c] = static_cast<uchar>(std::lround(255.0 * v));  // RGB -> BGR
      }
    }
  return out8;
}

double AutoExposure(const cv::Mat& rgb, const cv::Mat& mask) {
  std::vector<float> lum;
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x) {
      if (!mask.empty() && !mask.at<uchar>(y, x)) continue;
      const cv::Vec3f p = rgb.at<cv::Vec3f>(y, x);
      lum.push_back(0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2]);
    }
  if (lum.empty()) return 1.0;
  const size_t k = static_cast<size_t>(0.99 * (lum.size() - 1));
  std::nth_element(lum.begin(), lum.begin() + k, lum.end());
  return lum[k] > 0 ? 0.9 / lum[k] : 1.0;
}

}  // namespace brdfshot
