#include "util/plots.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>

namespace brdfshot {

cv::Scalar ClassColor(int k) {
  static const cv::Scalar kColors[] = {{200, 110, 30}, {40, 130, 240}, {60, 170, 60},
                                       {50, 50, 210},  {170, 80, 170}, {120, 120, 120}};
  return k < 0 ? cv::Scalar(0, 0, 0) : kColors[k % 6];
}

Eigen::MatrixXd ClassicalMds2(const Eigen::MatrixXd& coords) {
  const Eigen::MatrixXd c = coords.colwise() - coords.rowwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(c, Eigen::ComputeThinU);
  Eigen::MatrixXd xy = svd.matrixU().leftCols(std::min<Eigen::Index>(2, c.rows())).transpose() * c;
  if (xy.rows() < 2) xy.conservativeResize(2, Eigen::NoChange), xy.row(1).setZero();
  return xy;
}

namespace {
void Frame(cv::Mat& img, const std::string& title) {
  cv::putText(img, title, {20, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {0, 0, 0}, 1, cv::LINE_AA);
}
}  // namespace

cv::Mat ScatterPlot(const Eigen::MatrixXd& xy, const std::vector<int>& cls, const std::vector<std::string>& labels,
                    const std::string& title) {
  cv::Mat img(800, 1000, CV_8UC3, cv::Scalar::all(255));
  Frame(img, title);
  const double x0 = xy.row(0).minCoeff(), x1 = xy.row(0).maxCoeff();
  const double y0 = xy.row(1).minCoeff(), y1 = xy.row(1).maxCoeff();
  auto px = [&](Eigen::Index i) {
    const double u = x1 > x0 ? (xy(0, i) - x0) / (x1 - x0) : 0.5;
    const double v = y1 > y0 ? (xy(1, i) - y0) / (y1 - y0) : 0.5;
    return cv::Point(static_cast<int>(60 + u * 880), static_cast<int>(740 - v * 660));
  };
  for (Eigen::Index i = 0; i < xy.cols(); ++i) cv::circle(img, px(i), 4, ClassColor(cls[i]), cv::FILLED, cv::LINE_AA);
  for (Eigen::Index i = 0; i < xy.cols() && i < static_cast<Eigen::Index>(labels.size()); ++i)
    if (!labels[i].empty())
      cv::putText(img, labels[i], px(i) + cv::Point(5, -3), cv::FONT_HERSHEY_PLAIN, 0.7, {90, 90, 90}, 1, cv::LINE_AA);
  return img;
}

cv::Mat LinePlotLog(const std::vector<std::vector<double>>& series, const std::vector<std::string>& names,
                    const std::string& title, const std::string& xlabel) {
  cv::Mat img(600, 1000, CV_8UC3, cv::Scalar::all(255));
  Frame(img, title);
  if (series.empty() || series[0].empty()) return img;
  const size_t n = series[0].size();
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return series[0][a] < series[0][b]; });
  double lo = 1e300, hi = -1e300;
  for (const auto& s : series)
    for (double v : s)
      if (v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
  lo = std::pow(10, std::floor(std::log10(lo)));
  hi = std::pow(10, std::ceil(std::log10(hi)));
  auto py = [&](double v) {
    const double t = (std::log10(std::max(v, lo)) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    return static_cast<int>(540 - t * 480);
  };
  for (double d = lo; d <= hi * 1.01; d *= 10) {
    cv::line(img, {70, py(d)}, {980, py(d)}, {220, 220, 220});
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", d);
    cv::putText(img, buf, {5, py(d) + 4}, cv::FONT_HERSHEY_PLAIN, 0.9, {0, 0, 0});
  }
  cv::putText(img, xlabel, {400, 585}, cv::FONT_HERSHEY_PLAIN, 1.0, {0, 0, 0});
  for (size_t s = 0; s < series.size(); ++s) {
    for (size_t i = 1; i < n; ++i) {
      const int xa = static_cast<int>(70 + (i - 1) * 900.0 / std::max<size_t>(1, n - 1));
      const int xb = static_cast<int>(70 + i * 900.0 / std::max<size_t>(1, n - 1));
      cv::line(img, {xa, py(series[s][order[i - 1]])}, {xb, py(series[s][order[i]])}, ClassColor(static_cast<int>(s)),
               1, cv::LINE_AA);
    }
    cv::putText(img, names[s], {90 + 160 * static_cast<int>(s), 50}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                ClassColor(static_cast<int>(s)), 1, cv::LINE_AA);
  }
  return img;
}

cv::Mat BarPlot(const std::vector<std::vector<double>>& values, const std::vector<std::string>& groups,
                const std::vector<std::string>& series, const std::string& title) {
  cv::Mat img(500, 1000, CV_8UC3, cv::Scalar::all(255));
  Frame(img, title);
  double hi = 0;
  for (const auto& g : values)
    for (double v : g) hi = std::max(hi, v);
  if (hi <= 0) return img;
  const int G = static_cast<int>(groups.size()), Sn = static_cast<int>(series.size());
  const double gw = 900.0 / std::max(1, G), bw = gw * 0.8 / std::max(1, Sn);
  for (int g = 0; g < G; ++g) {
    for (int s = 0; s < Sn; ++s) {
      const int x = static_cast<int>(70 + g * gw + s * bw);
      const int h = static_cast<int>(values[g][s] / hi * 380);
      cv::rectangle(img, {x, 440 - h}, {static_cast<int>(x + bw - 2), 440}, ClassColor(s), cv::FILLED);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.3f", values[g][s]);
      cv::putText(img, buf, {x, 435 - h}, cv::FONT_HERSHEY_PLAIN, 0.8, {0, 0, 0});
    }
    cv::putText(img, groups[g], {static_cast<int>(70 + g * gw), 470}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
  }
  for (int s = 0; s < Sn; ++s)
    cv::putText(img, series[s], {90 + 140 * s, 50}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ClassColor(s), 1, cv::LINE_AA);
  return img;
}

namespace {
// Decade-aligned log range covering every positive value.
void LogRange(const std::vector<double>& v, double* lo, double* hi) {
  *lo = 1e300, *hi = -1e300;
  for (double x : v)
    if (x > 0) *lo = std::min(*lo, x), *hi = std::max(*hi, x);
  if (*lo > *hi) *lo = 1, *hi = 10;
  *lo = std::pow(10, std::floor(std::log10(*lo)));
  *hi = std::pow(10, std::ceil(std::log10(*hi)));
  if (*hi <= *lo) *hi = *lo * 10;
}
}  // namespace

namespace {
void Marker(cv::Mat& img, cv::Point p, int kind, const cv::Scalar& col) {
  if (kind == 1) {
    cv::rectangle(img, p - cv::Point(3, 3), p + cv::Point(3, 3), col, cv::FILLED, cv::LINE_AA);
  } else if (kind == 2) {
    const std::vector<cv::Point> tri = {p + cv::Point(0, -5), p + cv::Point(-4, 3), p + cv::Point(4, 3)};
    cv::fillConvexPoly(img, tri, col, cv::LINE_AA);
  } else {
    cv::circle(img, p, 3, col, cv::FILLED, cv::LINE_AA);
  }
}
}  // namespace

cv::Mat LogLogPlot(const std::vector<XYSeries>& series, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel, double goal_y, const std::string& goal_label) {
  // Plot area [left, right] × [top, bottom]; the legend column sits right of it
  // so that it never hides data or the axis labels.
  const int left = 80, right = 760, top = 70, bottom = 530, legend_x = 780;
  cv::Mat img(600, 1000, CV_8UC3, cv::Scalar::all(255));
  Frame(img, title);
  std::vector<double> xs, ys;
  for (const auto& s : series) xs.insert(xs.end(), s.x.begin(), s.x.end()), ys.insert(ys.end(), s.y.begin(), s.y.end());
  if (goal_y > 0) ys.push_back(goal_y);
  double x0, x1, y0, y1;
  LogRange(xs, &x0, &x1);
  LogRange(ys, &y0, &y1);
  auto px = [&](double v) {
    return static_cast<int>(left + (std::log10(std::max(v, x0)) - std::log10(x0)) / (std::log10(x1) - std::log10(x0)) *
                                       (right - left));
  };
  auto py = [&](double v) {
    return static_cast<int>(bottom - (std::log10(std::max(v, y0)) - std::log10(y0)) /
                                         (std::log10(y1) - std::log10(y0)) * (bottom - top));
  };
  char buf[32];
  for (double d = y0; d <= y1 * 1.01; d *= 10) {
    cv::line(img, {left, py(d)}, {right, py(d)}, {220, 220, 220});
    std::snprintf(buf, sizeof buf, "%g", d);
    cv::putText(img, buf, {5, py(d) + 4}, cv::FONT_HERSHEY_PLAIN, 0.9, {0, 0, 0});
  }
  for (double d = x0; d <= x1 * 1.01; d *= 10) {
    cv::line(img, {px(d), top}, {px(d), bottom}, {220, 220, 220});
    std::snprintf(buf, sizeof buf, "%g", d);
    cv::putText(img, buf, {px(d) - 10, bottom + 20}, cv::FONT_HERSHEY_PLAIN, 0.9, {0, 0, 0});
  }
  if (goal_y > 0) {
    cv::line(img, {left, py(goal_y)}, {right, py(goal_y)}, {0, 0, 200}, 1, cv::LINE_AA);
    if (!goal_label.empty())
      cv::putText(img, goal_label, {right - 8 * static_cast<int>(goal_label.size()), py(goal_y) - 5},
                  cv::FONT_HERSHEY_PLAIN, 0.9, {0, 0, 200}, 1, cv::LINE_AA);
  }
  cv::putText(img, xlabel, {(left + right) / 2 - 4 * static_cast<int>(xlabel.size()), bottom + 50},
              cv::FONT_HERSHEY_PLAIN, 1.0, {0, 0, 0});
  cv::putText(img, ylabel, {5, top - 12}, cv::FONT_HERSHEY_PLAIN, 1.0, {0, 0, 0});
  for (size_t s = 0; s < series.size(); ++s) {
    const cv::Scalar col = series[s].color[0] >= 0 ? series[s].color : ClassColor(static_cast<int>(s));
    const auto& S = series[s];
    for (size_t i = 0; i < S.x.size(); ++i) {
      Marker(img, {px(S.x[i]), py(S.y[i])}, S.marker, col);
      if (i > 0) cv::line(img, {px(S.x[i - 1]), py(S.y[i - 1])}, {px(S.x[i]), py(S.y[i])}, col, 1, cv::LINE_AA);
    }
    const int ly = top + 8 + 20 * static_cast<int>(s);
    cv::line(img, {legend_x, ly}, {legend_x + 24, ly}, col, 1, cv::LINE_AA);
    Marker(img, {legend_x + 12, ly}, S.marker, col);
    cv::putText(img, S.name, {legend_x + 32, ly + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.42, col, 1, cv::LINE_AA);
  }
  return img;
}

}  // namespace brdfshot
