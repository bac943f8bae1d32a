// Camera response: code value → relative linear exposure, per channel.
//
// 8-bit frames: recovered from the bracket itself by Debevec & Malik's weighted
// least squares (g(z) = ln E + ln t, smoothness λ, g(128) = 0), solved in double
// with ln E eliminated (a 256×256 LDLT, however many samples). OpenCV's CalibrateDebevec does the same but takes 8-bit
// only and gives clipped codes weight; ours gives codes 0 and 255 zero weight and forces the result monotone. 16-bit
// frames (RAW or linear TIFF/PNG): linear, no curve.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace brdfshot {

struct ResponseCurve {
  std::string kind = "linear";           // linear | debevec
  int levels = 256;                      // code values
  std::array<std::vector<double>, 3> g;  // ln exposure per code (debevec), levels each
  // Linear exposure of code z in channel c (linear: z / (levels − 1)).
  double Linear(int c, int z) const;
  nlohmann::json ToJson() const;
  static ResponseCurve FromJson(const nlohmann::json& j, const std::string& source);
  static ResponseCurve Linear16() {
    ResponseCurve r;
    r.levels = 65536;
    return r;
  }
};

struct DebevecOptions {
  int samples = 5000;  // pixel locations (ln E eliminated: cost does not grow with them)
  double lambda = 30;  // smoothness, per 200 samples (scaled by √(samples/200))
  uint32_t seed = 7;
  int clip_reach = -1;  // ≥ 0 (JPEG light probes): samples clipped nearby in a frame are left out (clipping.h)
};

// `frames`: CV_8UC3, same size; `times`: relative exposures. Error when fewer
// than two frames or sizes differ.
ResponseCurve RecoverResponseDebevec(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                                     const DebevecOptions& opt = {});

}  // namespace brdfshot
