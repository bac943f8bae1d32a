#include "normals/observation.h"

#include <cmath>
#include <cstring>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/json_int.h"
#include "util/tagged_file.h"

namespace brdfshot {
namespace {
constexpr char kMagic[8] = {'B', 'S', 'H', 'O', 'T', 'O', 'B', '1'};
constexpr size_t kRecord = 8 + 12 + 48;
}  // namespace

void Observations::Write(const std::string& path) const {
  const size_t P = geometry.size();
  BRDFSHOT_CHECK(static_cast<size_t>(rgb.rows()) == P && rgb.cols() == 3);
  nlohmann::json h = header;
  h["format"] = "brdfshot-observations-1";
  h["pixels"] = P;
  h["width"] = geometry.width;
  h["height"] = geometry.height;
  WriteTaggedFile(path, kMagic, h, [&](std::ostream& out) {
    for (size_t p = 0; p < P; ++p) {
      char rec[kRecord];
      const int32_t xy[2] = {geometry.x[p], geometry.y[p]};
      const float c[3] = {static_cast<float>(rgb(p, 0)), static_cast<float>(rgb(p, 1)), static_cast<float>(rgb(p, 2))};
      const double d[6] = {geometry.normal[p].x, geometry.normal[p].y, geometry.normal[p].z,
                           geometry.view[p].x,   geometry.view[p].y,   geometry.view[p].z};
      std::memcpy(rec, xy, 8);
      std::memcpy(rec + 8, c, 12);
      std::memcpy(rec + 20, d, 48);
      out.write(rec, kRecord);
    }
  });
}

Observations Observations::Read(const std::string& path) { return Parse(ReadFileBytes(path), path); }

Observations Observations::Parse(const std::string& bytes, const std::string& name) {
  TaggedHeader t = ParseTaggedHeader(bytes, kMagic, "observation file", name);
  Observations o;
  o.header = std::move(t.header);
  uint64_t P;
  try {
    if (o.header.at("format") != "brdfshot-observations-1") throw FileError(name, "unknown observation format");
    P = static_cast<uint64_t>(JsonInt(o.header, "pixels", 0, 1 << 28, name));
    o.geometry.width = static_cast<int>(JsonInt(o.header, "width", 1, 1 << 20, name));
    o.geometry.height = static_cast<int>(JsonInt(o.header, "height", 1, 1 << 20, name));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(name, std::string("incomplete header: ") + e.what());
  }
  if (P == 0) throw FileError(name, "holds no pixels");
  if (bytes.size() != t.body_offset + P * kRecord)
    throw FileError(name, "size " + std::to_string(bytes.size()) + " does not match its " + std::to_string(P) +
                              " pixels: truncated or corrupt");
  o.rgb.resize(P, 3);
  const char* p = bytes.data() + t.body_offset;
  for (size_t i = 0; i < P; ++i, p += kRecord) {
    int32_t xy[2];
    float c[3];
    double d[6];
    std::memcpy(xy, p, 8);
    std::memcpy(c, p + 8, 12);
    std::memcpy(d, p + 20, 48);
    if (xy[0] < 0 || xy[1] < 0 || xy[0] >= o.geometry.width || xy[1] >= o.geometry.height)
      throw FileError(name, "pixel " + std::to_string(i) + " lies outside the image");
    const Vec3 n(d[0], d[1], d[2]), v(d[3], d[4], d[5]);
    if (!(std::abs(Length(n) - 1) < 1e-6) || !(std::abs(Length(v) - 1) < 1e-6))
      throw FileError(name, "pixel " + std::to_string(i) + " has a non-unit normal or view direction");
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
      throw FileError(name, "pixel " + std::to_string(i) + " has non-finite radiance");
    o.geometry.x.push_back(xy[0]);
    o.geometry.y.push_back(xy[1]);
    o.geometry.normal.push_back(n);
    o.geometry.view.push_back(v);
    for (int k = 0; k < 3; ++k) o.rgb(i, k) = c[k];
  }
  return o;
}

Observations ObservePixels(const cv::Mat& photo_rgb32f, PixelGeometry geometry, const cv::Vec3d& scale,
                           const std::string& geometry_source) {
  BRDFSHOT_CHECK(photo_rgb32f.type() == CV_32FC3);
  if (geometry.size() < 16)
    throw FileError(geometry_source, "leaves " + std::to_string(geometry.size()) + " usable pixels");
  Observations obs;
  obs.geometry = std::move(geometry);
  obs.rgb.resize(static_cast<Eigen::Index>(obs.geometry.size()), 3);
  for (size_t p = 0; p < obs.geometry.size(); ++p) {
    const cv::Vec3f v = photo_rgb32f.at<cv::Vec3f>(obs.geometry.y[p], obs.geometry.x[p]);
    for (int c = 0; c < 3; ++c) obs.rgb(static_cast<Eigen::Index>(p), c) = v[c] / scale[c];
  }
  return obs;
}

}  // namespace brdfshot
