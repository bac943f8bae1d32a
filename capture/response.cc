#include "capture/response.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "util/check.h"

namespace brdfshot {

double ResponseCurve::Linear(int c, int z) const {
  if (kind == "linear") return static_cast<double>(z) / (levels - 1);
  return std::exp(g[c][z]);
}

nlohmann::json ResponseCurve::ToJson() const {
  nlohmann::json j = {{"format", "brdfshot-response-1"}, {"kind", kind}, {"levels", levels}};
  if (kind == "debevec") j["ln_exposure"] = {g[0], g[1], g[2]};
  return j;
}

ResponseCurve ResponseCurve::FromJson(const nlohmann::json& j, const std::string& source) {
  ResponseCurve r;
  try {
    if (j.at("format") != "brdfshot-response-1") throw FileError(source, "not a brdfshot response curve");
    r.kind = j.at("kind");
    r.levels = j.at("levels");
    if (r.kind == "debevec") {
      for (int c = 0; c < 3; ++c) r.g[c] = j.at("ln_exposure").at(c).get<std::vector<double>>();
      for (int c = 0; c < 3; ++c)
        if (static_cast<int>(r.g[c].size()) != r.levels) throw FileError(source, "response curve length differs from levels");
    } else if (r.kind != "linear") {
      throw FileError(source, "unknown response kind '" + r.kind + "'");
    }
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("bad response curve: ") + e.what());
  }
  return r;
}

ResponseCurve RecoverResponseDebevec(const std::vector<cv::Mat>& frames, const std::vector<double>& times,
                                     const DebevecOptions& opt) {
  if (frames.size() < 2) throw Error("response recovery needs at least two frames");
  BRDFSHOT_CHECK(frames.size() == times.size());
  for (const cv::Mat& f : frames) {
    BRDFSHOT_CHECK(f.type() == CV_8UC3, "response recovery takes 8-bit RGB frames");
    BRDFSHOT_CHECK(f.size() == frames[0].size());
  }
  const int Z = 256, N = static_cast<int>(frames.size());
  auto weight = [](int z) { return z <= 0 || z >= 255 ? 0.0 : (z <= 127 ? z : 255 - z); };
  // Sample locations spread over the middle frame's intensities (a random grid
  // would under-sample the rare bright and dark codes the curve's ends need).
  const cv::Mat& mid = frames[N / 2];
  std::mt19937 rng(opt.seed);
  std::vector<cv::Point> locs;
  {
    std::vector<std::vector<cv::Point>> by_code(Z);
    for (int y = 0; y < mid.rows; y += std::max(1, mid.rows / 200))
      for (int x = 0; x < mid.cols; x += std::max(1, mid.cols / 200)) {
        const cv::Vec3b v = mid.at<cv::Vec3b>(y, x);
        by_code[(v[0] + v[1] + v[2]) / 3].push_back({x, y});
      }
    for (int k = 0; k < opt.samples; ++k) {
      const int z = (k * Z) / opt.samples;
      for (int d = 0; d < Z; ++d) {  // nearest code bucket that has pixels
        const int zz = (z + d) % Z;
        if (by_code[zz].empty()) continue;
        locs.push_back(by_code[zz][rng() % by_code[zz].size()]);
        break;
      }
    }
  }
  const int S = static_cast<int>(locs.size());
  ResponseCurve r;
  r.kind = "debevec";
  r.levels = Z;
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(S * N + Z - 1, Z + S);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(A.rows());
    int row = 0;
    for (int i = 0; i < S; ++i)
      for (int j = 0; j < N; ++j) {
        const int z = frames[j].at<cv::Vec3b>(locs[i])[c];
        const double w = weight(z);
        A(row, z) = w;
        A(row, Z + i) = -w;
        b(row) = w * std::log(times[j]);
        ++row;
      }
    A(row, 128) = 1;  // g(128) = 0 fixes the scale
    ++row;
    for (int z = 1; z < Z - 1; ++z, ++row) {
      const double w = opt.lambda * std::max(1.0, weight(z));
      A(row, z - 1) = w;
      A(row, z) = -2 * w;
      A(row, z + 1) = w;
    }
    const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
    std::vector<double> g(x.data(), x.data() + Z);
    // Codes no sample reached are set by smoothness alone; a response must not
    // decrease, so any wiggle is flattened (running maximum).
    for (int z = 1; z < Z; ++z) g[z] = std::max(g[z], g[z - 1] + 1e-6);
    r.g[c] = g;
  }
  return r;
}

}  // namespace brdfshot
