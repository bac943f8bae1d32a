#include "capture/response.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "capture/clipping.h"
#include "util/check.h"
#include "util/json_int.h"

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
    r.levels = static_cast<int>(JsonInt(j, "levels", 2, 65536, source));
    if (r.kind == "debevec") {
      for (int c = 0; c < 3; ++c) r.g[c] = j.at("ln_exposure").at(c).get<std::vector<double>>();
      for (int c = 0; c < 3; ++c)
        if (static_cast<int>(r.g[c].size()) != r.levels)
          throw FileError(source, "response curve length differs from levels");
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
    const int grid = std::max(200, static_cast<int>(2 * std::sqrt(static_cast<double>(opt.samples))));
    for (int y = 0; y < mid.rows; y += std::max(1, mid.rows / grid))
      for (int x = 0; x < mid.cols; x += std::max(1, mid.cols / grid)) {
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
  // Samples clipped nearby in a frame (clipping.h), for all channels at once.
  std::vector<std::vector<bool>> clipped(S, std::vector<bool>(N, false));
  if (opt.clip_reach >= 0)
    for (int i = 0; i < S; ++i)
      for (int j = 0; j < N; ++j)
        clipped[i][j] = IsClippedNearby(frames[j], locs[i].x, locs[i].y, kClippedCode8, opt.clip_reach);
  ResponseCurve r;
  r.kind = "debevec";
  r.levels = Z;
  for (int c = 0; c < 3; ++c) {
    // Debevec & Malik's least squares, Σ w² (g(z_ij) − ln E_i − ln t_j)² + smoothness,
    // with each ln E_i eliminated in closed form (its optimum is the weighted
    // mean of g(z_ij) − ln t_j): what remains is a 256×256 system in g whose
    // size does not grow with the samples, so thousands of them cost nothing
    // (the full QR over 200 samples took longer and averaged less noise).
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(Z, Z);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(Z);
    std::vector<int> zs(N);
    std::vector<double> w2(N), lt(N);
    for (int j = 0; j < N; ++j) lt[j] = std::log(times[j]);
    for (int i = 0; i < S; ++i) {
      double W = 0, dl = 0;
      for (int j = 0; j < N; ++j) {
        zs[j] = frames[j].at<cv::Vec3b>(locs[i])[c];
        w2[j] = clipped[i][j] ? 0.0 : weight(zs[j]) * weight(zs[j]);
        W += w2[j], dl += w2[j] * lt[j];
      }
      if (W == 0) continue;
      // Q = diag(w²) − w² w²ᵀ / W, acting on u = g(z) − ln t.
      for (int j = 0; j < N; ++j) {
        if (w2[j] == 0) continue;
        H(zs[j], zs[j]) += w2[j];
        rhs(zs[j]) += w2[j] * lt[j] - w2[j] * dl / W;
        for (int k = 0; k < N; ++k) H(zs[j], zs[k]) -= w2[j] * w2[k] / W;
      }
    }
    // λ is stated per 200 samples (Debevec & Malik's scale); the data term grows
    // with the samples, so the smoothness grows with it to keep their balance.
    const double lambda = opt.lambda * std::sqrt(S / 200.0);
    for (int z = 1; z < Z - 1; ++z) {
      const double w = lambda * std::max(1.0, weight(z));
      const int idx[3] = {z - 1, z, z + 1};
      const double coef[3] = {w, -2 * w, w};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) H(idx[a], idx[b]) += coef[a] * coef[b];
    }
    // g(128) = 0 fixes the scale: drop that unknown. What remains is positive
    // definite once the samples reach two codes; otherwise the bracket holds no
    // information about the curve's slope, and LDLT reports it.
    Eigen::MatrixXd Hr(Z - 1, Z - 1);
    Eigen::VectorXd br(Z - 1);
    auto keep = [](int z) { return z < 128 ? z : z - 1; };
    for (int a = 0; a < Z; ++a) {
      if (a == 128) continue;
      br(keep(a)) = rhs(a);
      for (int b = 0; b < Z; ++b)
        if (b != 128) Hr(keep(a), keep(b)) = H(a, b);
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(Hr);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff())
      throw Error(
          "cannot recover a response curve: the frames do not constrain it (identical frames, or too few codes)");
    const Eigen::VectorXd xr = ldlt.solve(br);
    Eigen::VectorXd x(Z);
    for (int z = 0; z < Z; ++z) x(z) = z == 128 ? 0.0 : xr(keep(z));
    std::vector<double> g(x.data(), x.data() + Z);
    // Codes no sample reached are set by smoothness alone; a response must not
    // decrease, so any wiggle is flattened (running maximum).
    for (int z = 1; z < Z; ++z) g[z] = std::max(g[z], g[z - 1] + 1e-6);
    r.g[c] = g;
  }
  return r;
}

}  // namespace brdfshot
