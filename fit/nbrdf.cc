#include "fit/nbrdf.h"

#include <cmath>
#include <filesystem>

#include "fit/npy.h"
#include "util/check.h"

namespace brdfshot {

namespace {
Eigen::MatrixXf LoadMatrix(const std::string& path, size_t rows, size_t cols) {
  const NpyArray a = ReadNpyFloat32(path);
  const bool ok = cols == 0 ? (a.shape.size() == 1 && a.shape[0] == rows)
                            : (a.shape.size() == 2 && a.shape[0] == rows && a.shape[1] == cols);
  if (!ok)
    throw FileError(path, "unexpected shape, expected (" + std::to_string(rows) +
                              (cols ? ", " + std::to_string(cols) : std::string(",")) + ")");
  const size_t c = cols ? cols : 1;
  Eigen::MatrixXf m(rows, c);
  for (size_t i = 0; i < rows; ++i)
    for (size_t j = 0; j < c; ++j) m(i, j) = a.data[i * c + j];  // C order
  return m;
}
}  // namespace

NbrdfNetwork NbrdfNetwork::Load(const std::string& dir, const std::string& name) {
  auto p = [&](const char* suffix) { return (std::filesystem::path(dir) / (name + suffix)).string(); };
  NbrdfNetwork n;
  n.name_ = name;
  n.w1_ = LoadMatrix(p("_fc1.npy"), 6, 21);
  n.b1_ = LoadMatrix(p("_b1.npy"), 21, 0).transpose();
  n.w2_ = LoadMatrix(p("_fc2.npy"), 21, 21);
  n.b2_ = LoadMatrix(p("_b2.npy"), 21, 0).transpose();
  n.w3_ = LoadMatrix(p("_fc3.npy"), 21, 3);
  n.b3_ = LoadMatrix(p("_b3.npy"), 3, 0).transpose();
  return n;
}

MatrixXfR NbrdfNetwork::Eval(const MatrixXfR& x) const {
  BRDFSHOT_CHECK(x.cols() == 6);
  MatrixXfR out(x.rows(), 3);
  constexpr Eigen::Index kBlock = 4096;  // keeps the hidden layers in L2
  for (Eigen::Index r0 = 0; r0 < x.rows(); r0 += kBlock) {
    const Eigen::Index n = std::min(kBlock, x.rows() - r0);
    Eigen::MatrixXf h1 = ((x.middleRows(r0, n) * w1_).rowwise() + b1_).cwiseMax(0.0f);
    Eigen::MatrixXf h2 = ((h1 * w2_).rowwise() + b2_).cwiseMax(0.0f);
    Eigen::MatrixXf o = (h2 * w3_).rowwise() + b3_;
    out.middleRows(r0, n) = (o.array().exp() - 1.0f).cwiseMax(0.0f).matrix();
  }
  return out;
}

Rgb NbrdfNetwork::EvalHalfDiff(const HalfDiff& hd) const {
  MatrixXfR x(1, 6);
  const double st = std::sin(hd.theta_d);
  x << std::sin(hd.theta_h), 0, std::cos(hd.theta_h), st * std::cos(hd.phi_d), st * std::sin(hd.phi_d),
      std::cos(hd.theta_d);
  const MatrixXfR o = Eval(x);
  return {o(0, 0), o(0, 1), o(0, 2)};
}

MatrixXfR NbrdfInputs(const MerlGrid& grid) {
  MatrixXfR x(grid.size(), 6);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < grid.n_th; ++i)
    for (int j = 0; j < grid.n_td; ++j)
      for (int k = 0; k < grid.n_pd; ++k) {
        const HalfDiff hd = grid.LatticePoint(i, j, k);
        const double st = std::sin(hd.theta_d);
        x.row(grid.Index(i, j, k)) << std::sin(hd.theta_h), 0, std::cos(hd.theta_h), st * std::cos(hd.phi_d),
            st * std::sin(hd.phi_d), std::cos(hd.theta_d);
      }
  return x;
}

MerlBrdf NbrdfToMerl(const NbrdfNetwork& net, const MerlGrid& grid) {
  const MatrixXfR rho = net.Eval(NbrdfInputs(grid));
  MerlBrdf m(grid);
  const std::vector<float> cosw = grid.CosineWeightTable();  // > 0 where measurable
  for (size_t idx = 0; idx < grid.size(); ++idx) {
    if (!(cosw[idx] > 0)) continue;
    for (int c = 0; c < 3; ++c) m.set_raw(c, idx, rho(idx, c) / kMerlScale[c]);
  }
  return m;
}

}  // namespace brdfshot
