#include "capture/exposure.h"

#include <cmath>
#include <exiv2/exiv2.hpp>
#include <fstream>
#include <sstream>

#include "util/check.h"

namespace brdfshot {

double ExifInfo::RelativeExposure() const {
  if (exposure_time <= 0) return 0;
  const double n = f_number > 0 ? f_number : 1.0, s = iso > 0 ? iso / 100.0 : 1.0;
  return exposure_time * s / (n * n);
}

ExifInfo ReadExif(const std::string& path) {
  ExifInfo info;
  try {
    Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path);
    image->readMetadata();
    const Exiv2::ExifData& exif = image->exifData();
    auto number = [&](const char* key) -> double {
      const auto it = exif.findKey(Exiv2::ExifKey(key));
      if (it == exif.end() || it->count() == 0) return 0;
      const Exiv2::Rational r = it->toRational(0);
      return r.second != 0 ? static_cast<double>(r.first) / r.second : it->toFloat(0);
    };
    info.exposure_time = number("Exif.Photo.ExposureTime");
    info.f_number = number("Exif.Photo.FNumber");
    info.iso = number("Exif.Photo.ISOSpeedRatings");
    info.focal_35mm = number("Exif.Photo.FocalLengthIn35mmFilm");
    const double o = number("Exif.Image.Orientation");
    if (o >= 1 && o <= 8) info.orientation = static_cast<int>(o);
    auto text = [&](const char* key) {
      const auto it = exif.findKey(Exiv2::ExifKey(key));
      return it == exif.end() ? std::string() : it->toString();
    };
    info.camera = text("Exif.Image.Make");
    const std::string model = text("Exif.Image.Model");
    if (!model.empty()) info.camera += (info.camera.empty() ? "" : " ") + model;
  } catch (const Exiv2::AnyError& e) {
    throw FileError(path, std::string("cannot read image metadata: ") + e.what());
  }
  return info;
}

namespace {

Exiv2::URational ExactRational(double v) {
  if (v >= 1 && std::abs(v - std::round(v)) < 1e-9 * v) return {static_cast<uint32_t>(std::round(v)), 1};
  if (v > 0 && v < 1 && std::abs(1 / v - std::round(1 / v)) < 1e-9 / v)
    return {1, static_cast<uint32_t>(std::round(1 / v))};
  return {static_cast<uint32_t>(std::round(v * 1e6)), 1000000};
}

}  // namespace

void WriteExif(const std::string& path, const ExifInfo& info) {
  try {
    Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path);
    image->readMetadata();
    Exiv2::ExifData exif = image->exifData();
    if (info.exposure_time > 0) exif["Exif.Photo.ExposureTime"] = ExactRational(info.exposure_time);
    if (info.f_number > 0) exif["Exif.Photo.FNumber"] = ExactRational(info.f_number);
    if (info.iso > 0) exif["Exif.Photo.ISOSpeedRatings"] = static_cast<uint16_t>(std::lround(info.iso));
    if (info.focal_35mm > 0)
      exif["Exif.Photo.FocalLengthIn35mmFilm"] = static_cast<uint16_t>(std::lround(info.focal_35mm));
    exif["Exif.Image.Orientation"] = static_cast<uint16_t>(info.orientation);
    if (!info.camera.empty()) exif["Exif.Image.Make"] = info.camera;
    image->setExifData(exif);
    image->writeMetadata();
  } catch (const Exiv2::AnyError& e) {
    throw FileError(path, std::string("cannot write image metadata: ") + e.what());
  }
}

double ParseExposureTime(const std::string& text, const std::string& where) {
  std::string t = text;
  while (!t.empty() && (t.back() == 's' || isspace(static_cast<unsigned char>(t.back())))) t.pop_back();
  size_t start = t.find_first_not_of(" \t");
  t = start == std::string::npos ? "" : t.substr(start);
  double v = 0;
  try {
    size_t used = 0;
    const size_t slash = t.find('/');
    if (slash != std::string::npos) {
      const double a = std::stod(t.substr(0, slash), &used);
      const double b = std::stod(t.substr(slash + 1));
      v = a / b;
    } else {
      v = std::stod(t, &used);
      if (used != t.size()) v = -1;
    }
  } catch (const std::exception&) {
    v = -1;
  }
  if (!(v > 0) || !std::isfinite(v))
    throw Error(where + ": bad exposure time '" + text + "' (expected e.g. 1/250 or 0.5)");
  return v;
}

std::vector<double> ReadTimesFile(const std::string& path, size_t expected) {
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot open times file");
  std::vector<double> times;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const size_t s = line.find_first_not_of(" \t\r");
    if (s == std::string::npos || line[s] == '#') continue;
    times.push_back(ParseExposureTime(line.substr(s), path + ":" + std::to_string(n)));
  }
  if (times.empty()) throw FileError(path, "no exposure times in times file");
  if (expected > 0 && times.size() != expected)
    throw FileError(
        path, "has " + std::to_string(times.size()) + " exposure times for " + std::to_string(expected) + " frames");
  return times;
}

}  // namespace brdfshot
