// How much light each frame of a bracket collected, relative to the others:
// from EXIF (exiv2) or from a times file when EXIF is missing or wrong.
#pragma once

#include <string>
#include <vector>

namespace brdfshot {

struct ExifInfo {
  double exposure_time = 0;  // s (0: absent)
  double f_number = 0;       // (0: absent)
  double iso = 0;            // (0: absent)
  int orientation = 1;       // EXIF orientation 1..8
  double focal_35mm = 0;     // FocalLengthIn35mmFilm, mm (0: absent); normals' perspective model
  std::string camera;        // "Make Model"
  // t · ISO/100 / N², with absent ISO or N taken as 100 and 1 (they cancel in a
  // bracket shot with one ISO and aperture). 0 when the exposure time is absent.
  double RelativeExposure() const;
};

// EXIF of an image file; fields stay at their defaults when absent. Error
// naming the file when it cannot be opened or parsed as an image.
ExifInfo ReadExif(const std::string& path);

// Writes `info` (exposure time, f-number, ISO, orientation, 35 mm focal
// length rounded to the whole mm EXIF stores, camera as Make)
// into an existing JPEG/PNG/TIFF `path` with exiv2, as a camera would. The time
// is stored as the exact rational 1/n or n/1 when it is one, else to 1 µs.
// Error naming the file on failure.
void WriteExif(const std::string& path, const ExifInfo& info);

// "1/250", "0.004", "2", "2s" → seconds; Error naming `where` otherwise.
double ParseExposureTime(const std::string& text, const std::string& where);

// One exposure time per non-empty, non-# line. Error naming the file if the
// count differs from `expected` (when > 0) or a line does not parse.
std::vector<double> ReadTimesFile(const std::string& path, size_t expected = 0);

}  // namespace brdfshot
