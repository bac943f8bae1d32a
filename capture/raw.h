// Camera RAW through libraw: linear sensor data, black and white levels
// subtracted and scaled, demosaiced, white-balanced (camera's or given), no
// gamma and no auto-brightening — so the 16-bit result needs no response curve.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>

namespace brdfshot {

struct RawFrame {
  cv::Mat rgb16;                      // CV_16UC3, linear
  double black = 0, white = 0;        // sensor levels libraw reported
  std::array<double, 3> wb{1, 1, 1};  // multipliers applied (R, G, B)
  double exposure_time = 0, f_number = 0, iso = 0;
  double focal_35mm = 0;  // 35 mm-equivalent focal length, mm (0: the file does not say)
  std::string camera;
};

// `wb` empty: the camera's white balance; else R,G,B multipliers. Error naming
// the file when libraw cannot open or decode it.
RawFrame ReadRaw(const std::string& path, const std::array<double, 3>* wb = nullptr);

}  // namespace brdfshot
