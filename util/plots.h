// Pictures people would rather look at than read: the class map (paper fig. 1)
// and leave-one-out error plots. Plain OpenCV drawing, returned as BGR images.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace brdfshot {

// Classical MDS of the columns of `coords` to 2-D (= PCA for Euclidean data).
Eigen::MatrixXd ClassicalMds2(const Eigen::MatrixXd& coords);

// Scatter of 2-D points coloured by class, with optional labels.
cv::Mat ScatterPlot(const Eigen::MatrixXd& xy, const std::vector<int>& cls, const std::vector<std::string>& labels,
                    const std::string& title);

// One line per series over a shared x index (sorted by the first series),
// log-scaled y: e.g. per-material relit error of each method.
cv::Mat LinePlotLog(const std::vector<std::vector<double>>& series, const std::vector<std::string>& names,
                    const std::string& title, const std::string& xlabel);

// Grouped bars (groups × series), linear y.
cv::Mat BarPlot(const std::vector<std::vector<double>>& values, const std::vector<std::string>& groups,
                const std::vector<std::string>& series, const std::string& title);

// Series of (x, y) points joined by lines on log-log axes, with an optional
// horizontal goal line (0: none): e.g. time against error per setting.
struct XYSeries {
  std::string name;
  std::vector<double> x, y;
  cv::Scalar color = cv::Scalar(-1, 0, 0);  // BGR; negative: the palette's k-th colour
  int marker = 0;                           // 0 disc, 1 square, 2 triangle
};
// Log-log axes with one polyline per series, the legend in a column on the
// right, and `goal_y` (if > 0) as a red line labelled `goal_label`.
cv::Mat LogLogPlot(const std::vector<XYSeries>& series, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel, double goal_y = 0, const std::string& goal_label = "");

cv::Scalar ClassColor(int k);

}  // namespace brdfshot
