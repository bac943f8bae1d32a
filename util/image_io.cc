#include "util/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/jpeg_structure.h"

namespace brdfshot {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

cv::Mat DecodeImageFile(const std::string& path, int imread_flags, const std::string& what) {
  const std::string ext = LowerExtension(path);
  cv::Mat bgr;
  if (ext == ".jpg" || ext == ".jpeg") {
    const std::string bytes = ReadFileBytes(path);
    const std::string problem = JpegStructureProblem(bytes);
    if (!problem.empty()) throw FileError(path, problem);
    bgr = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())),
                       imread_flags);
  } else {
    bgr = cv::imread(path, imread_flags);
  }
  if (bgr.empty()) throw FileError(path, "cannot decode " + what);
  return bgr;
}

cv::Mat ReadImageRgb(const std::string& path, const std::string& what) {
  const std::string ext = LowerExtension(path);
  if (ext == ".exr" || ext == ".hdr" || ext == ".pfm") return ReadHdrImage(path);
  const cv::Mat bgr = DecodeImageFile(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR, what);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

namespace {

// The data window's size, or a FileError when no real image has it: any
// compression keeps well under 4096 pixels per byte, so past 16 MP a window
// larger than that is a corrupt header, not a picture to allocate gigabytes
// for. Sides are computed in 64 bits (max − min of two int32 can overflow).
cv::Size CheckedDataWindowSize(const std::string& path, const Imath::Box2i& dw, int64_t file_bytes) {
  const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, h = int64_t{dw.max.y} - dw.min.y + 1;
  if (w <= 0 || h <= 0 || w > (1 << 20) || h > (1 << 20) || (w * h > (1 << 24) && w * h / 4096 > file_bytes))
    throw FileError(path, "bad data window " + std::to_string(w) + "x" + std::to_string(h) + " for a " +
                              std::to_string(file_bytes) + "-byte file");
  return cv::Size(static_cast<int>(w), static_cast<int>(h));
}

// Walks the first header's attribute list (name\0 type\0 int32 size, value)
// and refuses a size the file cannot hold. OpenEXR allocates each attribute at
// its declared size before reading it, so a corrupt 1 KB file could otherwise
// ask for 2 GB (found by fuzz_probe: it made every bad input take ~30 ms).
// OpenEXR reads a channel list and a preview by their content, not their
// declared size, and goes on from where that content ends: a list whose size
// disagrees with its content desynchronises the two walks, and OpenEXR then
// takes arbitrary bytes for the next attribute's size (fuzz_probe: 1.9 GB
// asked for by a 382-byte file). So those sizes must match their content.
// Returns the file's size.
int64_t CheckExrHeaderSizes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const auto file_size = static_cast<int64_t>(std::filesystem::file_size(path, ec));
  unsigned char magic[8];
  if (ec || !in.read(reinterpret_cast<char*>(magic), 8))
    throw FileError(path, "not a readable OpenEXR file: too short");
  if (magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 || magic[3] != 0x01)
    throw FileError(path, "not a readable OpenEXR file: bad magic number");
  const size_t max_name = (magic[5] & 0x04) ? 255 : 31;  // "long names" flag
  auto read_string = [&](std::string* out) {
    out->clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (out->size() == max_name) return false;
      out->push_back(c);
    }
    return false;
  };
  for (std::string name, type;;) {
    if (!read_string(&name)) throw FileError(path, "not a readable OpenEXR file: bad attribute name");
    if (name.empty()) return file_size;  // end of header
    int32_t size = 0;
    if (!read_string(&type) || !in.read(reinterpret_cast<char*>(&size), 4))
      throw FileError(path, "not a readable OpenEXR file: truncated header");
    const int64_t here = static_cast<int64_t>(in.tellg());
    if (size < 0 || here < 0 || size > file_size - here)
      throw FileError(path, "not a readable OpenEXR file: attribute '" + name + "' claims " + std::to_string(size) +
                                " bytes, the file has " + std::to_string(std::max<int64_t>(0, file_size - here)) +
                                " left (truncated or corrupt)");
    auto mismatch = [&](int64_t content) {
      throw FileError(path, "not a readable OpenEXR file: attribute '" + name + "' declares " + std::to_string(size) +
                                " bytes, its content takes " + std::to_string(content) + " (corrupt)");
    };
    if (type == "chlist") {
      // name\0, then pixel type, pLinear + 3 reserved, x and y sampling: 16 bytes.
      std::string channel;
      for (;;) {
        if (!read_string(&channel)) mismatch(static_cast<int64_t>(in.tellg()) - here);
        if (channel.empty()) break;
        in.seekg(16, std::ios::cur);
        if (static_cast<int64_t>(in.tellg()) - here > size) mismatch(static_cast<int64_t>(in.tellg()) - here);
      }
      if (static_cast<int64_t>(in.tellg()) - here != size) mismatch(static_cast<int64_t>(in.tellg()) - here);
    } else if (type == "box2i") {
      // OpenEXR reads a box's 16 bytes whatever size is declared, so a window
      // declared longer would pass unseen here (fuzz_probe: a 247-byte
      // dataWindow, 30 s under ASan).
      if (size != 16) mismatch(16);
      int32_t box[4];
      if (!in.read(reinterpret_cast<char*>(box), 16)) mismatch(16);
      // OpenEXR sizes its line buffers from the window when it opens the file:
      // a corrupt window is refused here, before that (fuzz_probe: 6 M-pixel
      // wide lines from a 191-byte file).
      if (name == "dataWindow")
        CheckedDataWindowSize(path, Imath::Box2i(Imath::V2i(box[0], box[1]), Imath::V2i(box[2], box[3])), file_size);
    } else if (type == "preview") {
      uint32_t wh[2] = {0, 0};
      if (size < 8 || !in.read(reinterpret_cast<char*>(wh), 8)) mismatch(8);
      const int64_t content = 8 + int64_t{wh[0]} * wh[1] * 4;
      if (content != size) mismatch(content);
    }
    in.seekg(here + size, std::ios::beg);
  }
}

// Read as 32-bit float whatever the file stores: the RGBA interface would hand
// back half floats, which lose precision and turn a sun above 65504 into inf.
cv::Mat ReadExr(const std::string& path) {
  const int64_t bytes = CheckExrHeaderSizes(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    // Checked again from OpenEXR's own parse: the walk above sees the window
    // only when its attribute has the type box2i.
    const cv::Size size = CheckedDataWindowSize(path, dw, bytes);
    const long w = size.width, h = size.height;
    const Imf::ChannelList& ch = file.header().channels();
    const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
    if (!rgb && !ch.findChannel("Y")) throw FileError(path, "has neither R, G, B nor Y channels");
    cv::Mat out(static_cast<int>(h), static_cast<int>(w), CV_32FC3);
    // Slice::Make places the data window's corner at our buffer's start; the
    // usual "base − (min.x + min.y·w)·stride" pointer is undefined behaviour
    // in C++ when the window does not start at 0,0 (UBSan, fuzz_probe).
    const size_t xs = 3 * sizeof(float), ys = xs * w;
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (rgb ? 3 : 1); ++c)
      fb.insert(rgb ? names[c] : "Y", Imf::Slice::Make(Imf::FLOAT, out.ptr<float>() + c, dw, xs, ys, 1, 1, 0.0));
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
// cv::imread decodes whatever the bytes are, whatever the extension says: an
// OpenEXR file named .hdr went through OpenCV's own EXR path, which skips the
// data-window check ReadExr makes and allocated line buffers for a
// 10-million-pixel-wide window from a 358-byte file (fuzz_probe). So the magic
// must match the extension, and a PFM's pixel count must fit the file.
void CheckRadianceOrPfmHeader(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (ext == ".pfm") {
    if (head.size() < 3 || head[0] != 'P' || (head[1] != 'F' && head[1] != 'f') ||
        !std::isspace(static_cast<unsigned char>(head[2])))
      throw FileError(path, "not a PFM file (it does not start with 'PF' or 'Pf')");
    long long w = 0, h = 0;
    if (std::sscanf(head.c_str() + 2, " %lld %lld", &w, &h) != 2 || w <= 0 || h <= 0)
      throw FileError(path, "PFM header has no valid width and height");
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    // Sides bounded before they are multiplied (no overflow).
    const bool too_wide = w > (1 << 20) || h > (1 << 20);
    const long long need = too_wide ? 0 : w * h * (head[1] == 'F' ? 3 : 1) * 4;
    if (ec || too_wide || static_cast<long long>(bytes) < need)
      throw FileError(path, "PFM header says " + std::to_string(w) + "x" + std::to_string(h) +
                                " pixels, more than its " + std::to_string(ec ? 0 : bytes) + " bytes hold (truncated)");
  } else if (head.size() < 2 || head[0] != '#' || head[1] != '?') {
    throw FileError(path, "not a Radiance HDR file (it does not start with '#?')");
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
    CheckRadianceOrPfmHeader(path, ext);
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
  if (!cv::checkRange(rgb, true, nullptr, -1e30, 1e30)) throw FileError(path, "contains NaN or Inf pixels");
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
