// The recovered response curve as people draw it: relative exposure (log)
// against code, one line per channel, over the codes the frames actually
// contain. A code no pixel shows is only extrapolated by the smoothness term
// and would stretch the axis without telling anything; a kink shows at a glance.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "capture/response.h"
#include "util/plots.h"

namespace brdfshot {

// One series per channel (R, G, B): the codes 1 … levels−2 seen at least
// max(10, 1e-5 of the samples) times in a grid of about 250 000 pixels per
// frame (CV_8UC3), and the curve's relative exposure at each.
std::vector<XYSeries> ResponseSeries(const ResponseCurve& response, const std::vector<cv::Mat>& frames);

// The series drawn on log–log axes (BGR 8-bit picture).
cv::Mat ResponsePlot(const ResponseCurve& response, const std::vector<cv::Mat>& frames);

}  // namespace brdfshot
