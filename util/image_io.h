// Image files in and out. In memory every image is a cv::Mat of CV_32FC3 in RGB
// order (not OpenCV's BGR): the radiometric code never has to remember which
// reader produced a picture.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace brdfshot {

// Linear HDR image from .exr (OpenEXR, any compression incl. DWA), .hdr (Radiance)
// or .pfm. Error naming the file on unreadable data, unknown extension, or any
// NaN/Inf pixel (a probe with NaN would silently poison every basis image).
cv::Mat ReadHdrImage(const std::string& path);

// An RGB image of any kind the stages take: HDR files (EXR/HDR/PFM) as float
// radiance, other images (8/16-bit PNG, TIFF, JPEG) at their own depth.
// FileError "<path>: cannot decode <what>" when the decoder fails.
cv::Mat ReadImageRgb(const std::string& path, const std::string& what = "image");

// An 8/16-bit image file as OpenCV decodes it with `imread_flags` (BGR order).
// A JPEG is read once, its markers walked (util/jpeg_structure.h: a cut frame
// would otherwise decode with grey rows) and the same bytes decoded.
// FileError "<path>: cannot decode <what>" when the decoder fails.
cv::Mat DecodeImageFile(const std::string& path, int imread_flags, const std::string& what = "image");

// ".exr" of "a/B.EXR": the extension, lower-cased, with its dot ("" when none).
std::string LowerExtension(const std::string& path);

// RGB EXR (ZIP compressed), written atomically. Half floats halve the file and
// keep 11 bits of mantissa over ~30 stops (6e-5 to 65504): enough for a merged
// photo, not for values outside that range (they saturate to ±inf, so the
// caller scales first), hence float by default.
enum class ExrPixel { kFloat, kHalf };
void WriteExr(const std::string& path, const cv::Mat& rgb, ExrPixel pixel = ExrPixel::kFloat);

// 8-bit sRGB-ish PNG for people: scale by `exposure`, gamma 1/2.2, clip.
void WritePngTonemapped(const std::string& path, const cv::Mat& rgb, double exposure = 1.0);
// The same picture in memory (BGR, 8-bit), to draw on before writing.
cv::Mat TonemapToBgr8(const cv::Mat& rgb, double exposure);

// Any 8-bit BGR picture (plots, overlays), written atomically.
void WritePng(const std::string& path, const cv::Mat& bgr8);

// Exposure that maps the 99th percentile of luminance to 0.9 (for previews).
double AutoExposure(const cv::Mat& rgb, const cv::Mat& mask = cv::Mat());

}  // namespace brdfshot
