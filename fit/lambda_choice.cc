#include "fit/lambda_choice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "fit/fit_confidence.h"
#include "fit/tridiagonal.h"
#include "util/check.h"

namespace brdfshot {

std::vector<int> WedgeFolds(const PixelGeometry& g, int folds) {
  BRDFSHOT_CHECK(folds >= 2);
  double cx = 0, cy = 0;
  for (size_t p = 0; p < g.size(); ++p) cx += g.x[p], cy += g.y[p];
  cx /= std::max<size_t>(1, g.size());
  cy /= std::max<size_t>(1, g.size());
  std::vector<int> fold(g.size());
  for (size_t p = 0; p < g.size(); ++p) {
    const double a = std::atan2(g.y[p] - cy, g.x[p] - cx) + M_PI;  // [0, 2π]
    fold[p] = std::min(folds - 1, static_cast<int>(a / (2 * M_PI) * folds));
  }
  return fold;
}

std::vector<std::vector<int>> RowsByFold(const std::vector<int>& fold_of_pixel, int folds) {
  std::vector<std::vector<int>> rows(folds);
  for (size_t p = 0; p < fold_of_pixel.size(); ++p) rows.at(fold_of_pixel[p]).push_back(static_cast<int>(p));
  return rows;
}

std::vector<std::array<Eigen::MatrixXd, 3>> FoldGrams(const std::array<MatrixXfR, 3>& Y,
                                                      const std::vector<int>& fold_of_pixel, int folds) {
  std::vector<std::array<Eigen::MatrixXd, 3>> out(folds);
  const std::vector<std::vector<int>> rows = RowsByFold(fold_of_pixel, folds);
#pragma omp parallel for schedule(dynamic, 1) collapse(2)
  for (int k = 0; k < folds; ++k)
    for (int c = 0; c < 3; ++c)
      out[k][c] = rows[k].empty() ? Eigen::MatrixXd::Zero(Y[c].cols(), Y[c].cols()) : GramOfRows(Y[c], rows[k]);
  return out;
}

std::array<ChannelFactor, 3> FactorOfFolds(const std::vector<std::array<Eigen::MatrixXd, 3>>& held_gram) {
  BRDFSHOT_CHECK(!held_gram.empty(), "FactorOfFolds: no folds");
  std::array<ChannelFactor, 3> f;
  for (int c = 0; c < 3; ++c) {
    f[c].gram = held_gram[0][c];
    for (size_t k = 1; k < held_gram.size(); ++k) f[c].gram += held_gram[k][c];
  }
  return f;
}

std::vector<Eigen::VectorXd> ProjectRowsByFold(const MatrixXfR& Y, const Eigen::VectorXd& y,
                                               const std::vector<int>& fold_of_pixel, int folds, Eigen::Index begin,
                                               Eigen::Index end) {
  if (end < 0) end = Y.rows();
  BRDFSHOT_CHECK(0 <= begin && begin <= end && end <= Y.rows() && y.size() == Y.rows() &&
                     static_cast<Eigen::Index>(fold_of_pixel.size()) == Y.rows(),
                 "ProjectRowsByFold: rows, photo and folds differ in size");
  for (Eigen::Index r = begin; r < end; ++r)
    BRDFSHOT_CHECK(fold_of_pixel[r] >= 0 && fold_of_pixel[r] < folds,
                   "a pixel's fold " << fold_of_pixel[r] << " is not one of " << folds);
  const Eigen::Index n = Y.cols();
  std::vector<Eigen::VectorXd> z(folds, Eigen::VectorXd::Zero(n));
  for (Eigen::Index r = begin; r < end; ++r) {
    double* zd = z[fold_of_pixel[r]].data();
    const float* src = Y.data() + r * n;  // Y is row-major: one contiguous row
    const double w = y[r];
    for (Eigen::Index j = 0; j < n; ++j) zd[j] += w * static_cast<double>(src[j]);
  }
  return z;
}

std::vector<Observation> FoldObservations(const std::array<MatrixXfR, 3>& Y, const Eigen::MatrixXd& y,
                                          const std::vector<int>& fold_of_pixel, int folds) {
  const Eigen::Index pixels = y.rows();
  BRDFSHOT_CHECK(static_cast<Eigen::Index>(fold_of_pixel.size()) == pixels && y.cols() == 3);
  // Checked here as well as in ProjectRowsByFold: a check that fails inside
  // the parallel loop below ends the program instead of throwing.
  for (int k : fold_of_pixel) BRDFSHOT_CHECK(k >= 0 && k < folds, "a pixel's fold " << k << " is not one of " << folds);
  for (int c = 0; c < 3; ++c) BRDFSHOT_CHECK(Y[c].rows() == pixels);
  // Each channel's rows are cut in halves, six tasks for the threads, whose
  // sums are added in order: the same result on any thread count.
  constexpr int kHalves = 2;
  std::array<std::array<std::vector<Eigen::VectorXd>, kHalves>, 3> part;  // [channel][half][fold]
#pragma omp parallel for schedule(dynamic, 1) collapse(2)
  for (int c = 0; c < 3; ++c)
    for (int h = 0; h < kHalves; ++h) {
      const Eigen::VectorXd yc = y.col(c);
      part[c][h] = ProjectRowsByFold(Y[c], yc, fold_of_pixel, folds, pixels * h / kHalves, pixels * (h + 1) / kHalves);
    }
  std::vector<Observation> out(folds);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> norm2(folds, 0.0);
    for (Eigen::Index p = 0; p < pixels; ++p) norm2[fold_of_pixel[p]] += y(p, c) * y(p, c);
    for (int k = 0; k < folds; ++k) {
      out[k].z[c] = part[c][0][k];
      for (int h = 1; h < kHalves; ++h) out[k].z[c] += part[c][h][k];
      out[k].norm2[c] = norm2[k];
    }
  }
  return out;
}

Observation SumObservations(const std::vector<Observation>& parts) {
  BRDFSHOT_CHECK(!parts.empty());
  Observation all = parts[0];
  for (size_t k = 1; k < parts.size(); ++k)
    for (int c = 0; c < 3; ++c) all.z[c] += parts[k].z[c], all.norm2[c] += parts[k].norm2[c];
  return all;
}

Eigen::MatrixXd FoldClassFactor::TimesQ(int c, const Eigen::MatrixXd& x) const {
  if (Q[c].size() > 0) return Q[c] * x;
  if (members.size() < 2) return x;  // no reflector: Q = I
  return reflectors[c].matrixQ() * x;
}

Eigen::VectorXd FoldClassFactor::TimesQt(int c, const Eigen::VectorXd& x) const {
  if (Q[c].size() > 0) return Q[c].transpose() * x;
  if (members.size() < 2) return x;
  return reflectors[c].matrixQ().adjoint() * x;
}

namespace {
// Whether `members` is `all` in order with at most kMostLeftOut of them
// left out; `left_out` gets their positions in `all`.
bool LeftOutOf(const std::vector<int>& members, const std::vector<int>& all, std::vector<int>* left_out) {
  left_out->clear();
  if (members.size() > all.size() || all.size() - members.size() > static_cast<size_t>(kMostLeftOut)) return false;
  size_t j = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    if (j < members.size() && members[j] == all[i])
      ++j;
    else
      left_out->push_back(static_cast<int>(i));
  }
  return j == members.size();
}
}  // namespace

CvSystem FactorFolds(const std::array<ChannelFactor, 3>& f, std::vector<std::array<Eigen::MatrixXd, 3>> held_gram,
                     const std::vector<std::vector<int>>& members, FoldQ q,
                     const std::vector<FoldClassFactor>* superset) {
  CvSystem cv;
  cv.held_gram = std::move(held_gram);
  const int K = static_cast<int>(cv.held_gram.size());
  cv.train.resize(K);
  cv.held_class.resize(K);
  if (superset) {
    // Checked here: no exception may leave the OpenMP loop below.
    BRDFSHOT_CHECK(static_cast<int>(superset->size()) == K, "FactorFolds: one superset factor per fold");
    for (const FoldClassFactor& s : *superset)
      BRDFSHOT_CHECK(s.Q[0].size() > 0 && s.Q[1].size() > 0 && s.Q[2].size() > 0,
                     "FactorFolds: a superset factor needs Q formed");
  }
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < K; ++k) {
    cv.train[k].resize(members.size());
    cv.held_class[k].resize(members.size());
    for (size_t j = 0; j < members.size(); ++j) {
      FoldClassFactor& t = cv.train[k][j];
      t.members = members[j];
      if (superset && members[j].size() >= static_cast<size_t>(kLeastBorderedMembers) &&
          LeftOutOf(members[j], (*superset)[static_cast<size_t>(k)].members, &t.left_out)) {
        t.superset = &(*superset)[static_cast<size_t>(k)];
        for (int c = 0; c < 3; ++c) {
          cv.held_class[k][j][c] = cv.held_gram[k][c](members[j], members[j]);
          t.gram_prior[c] =
              t.superset->gram[c](members[j], members[j]).rowwise().sum() / static_cast<double>(members[j].size());
        }
        continue;
      }
      t.left_out.clear();
      for (int c = 0; c < 3; ++c) {
        cv.held_class[k][j][c] = cv.held_gram[k][c](members[j], members[j]);
        t.gram[c] = f[c].gram(members[j], members[j]) - cv.held_class[k][j][c];
        if (members[j].empty()) continue;
        t.gram_prior[c] = t.gram[c].rowwise().sum() / static_cast<double>(members[j].size());
        Eigen::Tridiagonalization<Eigen::MatrixXd> tri(t.gram[c]);
        t.diagonal[c] = tri.diagonal();
        t.off_diagonal[c] = members[j].size() > 1 ? Eigen::VectorXd(tri.subDiagonal()) : Eigen::VectorXd();
        if (q == FoldQ::kFormed)
          t.Q[c] = tri.matrixQ();
        else
          t.reflectors[c] = std::move(tri);
      }
    }
  }
  return cv;
}

std::vector<FoldClassFactor> FactorFoldsOfAll(const std::array<ChannelFactor, 3>& f,
                                              const std::vector<std::array<Eigen::MatrixXd, 3>>& held_gram) {
  std::vector<int> all(static_cast<size_t>(f[0].gram.rows()));
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  CvSystem cv = FactorFolds(f, held_gram, {all}, FoldQ::kFormed);
  std::vector<FoldClassFactor> out;
  for (auto& fold : cv.train) out.push_back(std::move(fold[0]));
  return out;
}

namespace {
// The least share of the mean wedge a dark wedge counts as holding, where
// wedges count relative to their signal; -1 where they count as they are.
double WedgeFloorShare(const LambdaChoiceOptions& opt) {
  return opt.relative_wedges ? std::max(opt.min_wedge_share, kLeastWedgeShare) : -1;
}
}  // namespace

std::vector<double> WedgeWeights(const Observation& all, const std::vector<Observation>& held,
                                 const LambdaChoiceOptions& opt) {
  const double K = static_cast<double>(held.size());
  const double mean = (all.norm2[0] + all.norm2[1] + all.norm2[2]) / std::max(K, 1.0);
  std::vector<double> w(held.size(), 1.0);
  if (!opt.relative_wedges || !(mean > 0)) return w;
  const double floor = WedgeFloorShare(opt) * mean;
  for (size_t k = 0; k < held.size(); ++k)
    w[k] = mean / std::max(held[k].norm2[0] + held[k].norm2[1] + held[k].norm2[2], floor);
  return w;
}

namespace {
// The bordered solves of FoldClassFactor::superset, λ by λ: the superset's
// factor A = Q T Qᵀ, the left-out rows R, and per λ the pivots of T + λI's
// LDLᵀ recurrence (ShiftedTridiagonal), P = (T + λI)⁻¹ Qᵀ E (in T's frame) and S = Eᵀ Q P.
class BorderedSystem {
 public:
  BorderedSystem(const FoldClassFactor& cls, int c, const Eigen::VectorXd& lj)
      : Q_(cls.superset->Q[c]), dg_(cls.superset->diagonal[c]), e_(cls.superset->off_diagonal[c]),
        left_out_(cls.left_out), QR_(Q_(cls.left_out, Eigen::all)) {
    for (Eigen::Index l = 0; l < lj.size() && ok_; ++l) {
      shifted_.emplace_back(dg_, e_, lj[l]);
      ok_ = shifted_.back().ok();
      if (!ok_) break;
      P_.push_back(Tsolve(l, QR_.transpose()));
      S_.emplace_back(QR_ * P_.back());
      ok_ = S_.back().info() == Eigen::Success;
    }
  }
  // False where a pivot is not positive or S is not positive definite.
  bool ok() const { return ok_; }

  // Column l of X (n × L, T's frame, rows R of Q X ignored): the solution
  // in T's frame of (A + λ_l I) x = x_l with x pinned to zero at R.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& X) const {
    Eigen::MatrixXd out(X.rows(), X.cols());
    for (Eigen::Index l = 0; l < X.cols(); ++l) {
      const Eigen::VectorXd u = Tsolve(l, X.col(l));
      out.col(l) = u - P_[static_cast<size_t>(l)] * S_[static_cast<size_t>(l)].solve(QR_ * u);
    }
    return out;
  }
  // Q X with the rows R set to zero (they are zero to rounding).
  Eigen::MatrixXd ToBases(const Eigen::MatrixXd& Xh) const {
    Eigen::MatrixXd X = Q_ * Xh;
    X(left_out_, Eigen::all).setZero();
    return X;
  }
  const Eigen::MatrixXd& Q() const { return Q_; }

 private:
  // (T + λ_l I)⁻¹ B by the stored pivots.
  Eigen::MatrixXd Tsolve(Eigen::Index l, const Eigen::MatrixXd& B) const {
    return shifted_[static_cast<size_t>(l)].Solve(B);
  }
  const Eigen::MatrixXd& Q_;
  const Eigen::VectorXd &dg_, &e_;
  const std::vector<int>& left_out_;
  const Eigen::MatrixXd QR_;  // Eᵀ Q: the rows R of Q
  std::vector<ShiftedTridiagonal> shifted_;  // T + λ_l I's pivots, per λ
  std::vector<Eigen::MatrixXd> P_;
  std::vector<Eigen::LLT<Eigen::MatrixXd>> S_;
  bool ok_ = true;
};

// The most relative backward error a bordered solve may leave,
// ‖r − (A_JJ + λI) d‖ / (‖A_JJ + λI‖_F ‖d‖ + ‖r‖): a solve of the class's
// own tridiagonal factor leaves about 10⁻¹⁵. The bordered correction
// subtracts (A + λI)⁻¹E S⁻¹Eᵀu from the superset's solution u, which is
// large wherever the others nearly span a left-out basis (the superset's
// system is worse conditioned than the class's own there), and loses digits
// to the subtraction: on MERL's bases up to 10⁻⁷ of backward error. One step
// of iterative refinement, its residual computed from A itself, brings every
// one there to 10⁻¹³ or less (docs/benchmarks.md); past this bound the class
// is factored on its own.
constexpr double kMostBackwardError = 1e-12;

// The bordered solves of FoldClassFactor::superset: for every λ_l of `lj`,
// the class's (A_JJ + λ_l I) d = r (columns of `D`, k × L), from the
// superset's A = Q T Qᵀ. With u = (A + λI)⁻¹ r̃ (r̃: r with zeros at the
// left-out rows R) and P = (A + λI)⁻¹ E, d = u − P S⁻¹ Eᵀu, S = Eᵀ P: the
// weights at R pinned to zero, the rest the smaller system's solution; then
// one step of refinement. False where a pivot of T + λI is not positive, S
// is not positive definite, or the backward error exceeds
// kMostBackwardError: the caller factors the class.
bool BorderedFoldSolves(const FoldClassFactor& cls, int c, const Eigen::VectorXd& r, const Eigen::VectorXd& lj,
                        Eigen::MatrixXd* D) {
  const BorderedSystem sys(cls, c, lj);
  if (!sys.ok()) return false;
  const Eigen::MatrixXd& A = cls.superset->gram[c];
  const Eigen::Index n = A.rows(), L = lj.size();
  std::vector<int> J;
  Eigen::VectorXd rt = Eigen::VectorXd::Zero(n);
  {
    std::vector<char> kept(static_cast<size_t>(n), 1);
    for (int i : cls.left_out) kept[static_cast<size_t>(i)] = 0;
    for (Eigen::Index i = 0, j = 0; i < n; ++i)
      if (kept[static_cast<size_t>(i)]) rt[i] = r[j++], J.push_back(static_cast<int>(i));
  }
  // r̃ − (A + λI) X per column, zero at R.
  auto residual = [&](const Eigen::MatrixXd& X) {
    Eigen::MatrixXd res = -(A * X);
    res.colwise() += rt;
    for (Eigen::Index l = 0; l < L; ++l) res.col(l) -= lj[l] * X.col(l);
    res(cls.left_out, Eigen::all).setZero();
    return res;
  };
  const Eigen::MatrixXd B = (sys.Q().transpose() * rt).replicate(1, L);
  Eigen::MatrixXd Xh = sys.Solve(B);
  Eigen::MatrixXd X = sys.ToBases(Xh);
  Xh += sys.Solve(sys.Q().transpose() * residual(X));
  X = sys.ToBases(Xh);
  const Eigen::MatrixXd res = residual(X);
  const double a_norm = A(J, J).norm(), r_norm = r.norm();
  for (Eigen::Index l = 0; l < L; ++l) {
    const double scale = (a_norm + lj[l] * std::sqrt(static_cast<double>(J.size()))) * X.col(l).norm() + r_norm;
    if (!(res.col(l).norm() <= kMostBackwardError * scale)) return false;
  }
  *D = X(J, Eigen::all);
  return true;
}

// Held-out squared error of class `cls` (its fold factor) for every λ of
// `grid` that `scored` marks (all when empty), times `weight`, added into
// `score`.
void AddFoldScores(const FoldClassFactor& cls, const std::array<Eigen::MatrixXd, 3>& held_class_gram,
                   const Observation& all, const Observation& held, const std::vector<double>& all_grid, double weight,
                   std::vector<double>* score, const std::vector<bool>& scored = {}) {
  // Only the scored λ are solved and projected: the products with Q and the
  // held-out Gram matrix are most of a choice's cost.
  std::vector<double> grid;
  std::vector<size_t> at;
  for (size_t l = 0; l < all_grid.size(); ++l)
    if (scored.empty() || scored[l]) grid.push_back(all_grid[l]), at.push_back(l);
  const std::vector<int>& J = cls.members;
  const Eigen::Index k = static_cast<Eigen::Index>(J.size());
  const double cj = static_cast<double>(k);
  const Eigen::Index L = static_cast<Eigen::Index>(grid.size());
  if (L == 0) return;
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(k, 1.0 / cj);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd z_train = (all.z[c] - held.z[c])(J);
    const double n2_train = all.norm2[c] - held.norm2[c];
    const Eigen::VectorXd r = z_train - cls.gram_prior[c];
    Eigen::VectorXd lj(L);
    for (Eigen::Index l = 0; l < L; ++l) lj[l] = grid[l] * n2_train / cj;
    // k × L: each λ's deviation from the prior. A λ whose recurrence meets a
    // pivot that is not positive (a singular system at λ = 0) keeps the
    // prior alone: the eigendecomposition's pseudo-inverse would keep only
    // part of the data there, and such a λ is beyond any condition bound, so
    // it is never chosen either way.
    Eigen::MatrixXd W;
    if (!cls.bordered() || !BorderedFoldSolves(cls, c, r, lj, &W)) {
      if (cls.bordered()) {
        // Factored on the spot: the bordered solve could not be trusted.
        const Eigen::MatrixXd A = cls.superset->gram[c](J, J);
        const Eigen::Tridiagonalization<Eigen::MatrixXd> tri(A);
        const Eigen::VectorXd e = k > 1 ? Eigen::VectorXd(tri.subDiagonal()) : Eigen::VectorXd();
        W = tri.matrixQ() * TridiagonalSolves(tri.diagonal(), e, tri.matrixQ().adjoint() * r, lj);
      } else {
        W = cls.TimesQ(c, TridiagonalSolves(cls.diagonal[c], cls.off_diagonal[c], cls.TimesQt(c, r), lj));
      }
    }
    W.colwise() += prior;
    const Eigen::MatrixXd GW = held_class_gram[c] * W;
    const Eigen::VectorXd zh = held.z[c](J);
    for (Eigen::Index l = 0; l < L; ++l)
      (*score)[at[l]] += weight * std::max(0.0, W.col(l).dot(GW.col(l)) - 2 * W.col(l).dot(zh) + held.norm2[c]);
  }
}

// In-sample residual ‖y_c − A_J w‖² and effective parameter count tr(H) of
// one class, per channel, for every λ of `grid`, from the class's
// eigendecomposition: all λ at once.
struct ChannelResidual {
  double rss = 0, dof = 0;
};
std::vector<std::array<ChannelResidual, 3>> ResidualCurve(const ClassSpectrum& cls, const Observation& obs,
                                                          const std::vector<double>& grid) {
  const std::vector<int>& J = cls.members;
  const Eigen::Index k = static_cast<Eigen::Index>(J.size());
  const double cj = static_cast<double>(k);
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(k, 1.0 / cj);
  std::vector<std::array<ChannelResidual, 3>> out(grid.size());
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd zJ = obs.z[c](J);
    const Eigen::VectorXd r = zJ - cls.gram_prior[c];
    const double r0 = prior.dot(cls.gram_prior[c]) - 2 * prior.dot(zJ) + obs.norm2[c];
    const Eigen::VectorXd& e = cls.e[c];
    // Directions with no eigenvalue left (a singular system at λ = 0) are
    // dropped: the pseudo-inverse's residual.
    const double floor = 1e-13 * std::max(k ? e[k - 1] : 0.0, 1e-300);
    if (cls.tridiagonal()) {
      // No eigenvectors to project on: each λ's solve v = (G + λ_j I)⁺ r
      // gives ‖y − Y(μ' + v)‖² = r0 − 2 vᵀr + vᵀG v, and the effective
      // parameter count needs the eigenvalues alone.
      Eigen::VectorXd lj(static_cast<Eigen::Index>(grid.size()));
      for (size_t l = 0; l < grid.size(); ++l) lj[static_cast<Eigen::Index>(l)] = grid[l] * obs.norm2[c] / cj;
      const Eigen::MatrixXd v = SolveClassSystem(cls, c, r, lj);
      const Eigen::MatrixXd Gv = cls.gram[c] * v;
      for (size_t l = 0; l < grid.size(); ++l) {
        const Eigen::Index li = static_cast<Eigen::Index>(l);
        ChannelResidual& out_c = out[l][c];
        out_c.rss = std::max(0.0, r0 - 2 * v.col(li).dot(r) + v.col(li).dot(Gv.col(li)));
        for (Eigen::Index i = 0; i < k; ++i)
          if (e[i] + lj[li] > floor) out_c.dof += e[i] / (e[i] + lj[li]);
      }
      continue;
    }
    const Eigen::VectorXd b = cls.V[c].transpose() * r;
    for (size_t l = 0; l < grid.size(); ++l) {
      const double lj = grid[l] * obs.norm2[c] / cj;
      ChannelResidual& out_c = out[l][c];
      out_c.rss = r0;
      for (Eigen::Index i = 0; i < k; ++i) {
        const double den = e[i] + lj;
        if (den <= floor) continue;
        out_c.rss -= b[i] * b[i] * (2 / den - e[i] / (den * den));
        out_c.dof += e[i] / den;
      }
      out_c.rss = std::max(0.0, out_c.rss);
    }
  }
  return out;
}

// Whether class `cls` at grid value `lambda` stays within the condition bound
// in every channel: κ(G_JJ + λ_j I) ≤ max_condition (λ_j = λ‖y_c‖²/c_j).
bool WithinConditionBound(const ClassSpectrum& cls, const Observation& obs, double lambda, double max_condition) {
  const double cj = static_cast<double>(cls.members.size());
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd& e = cls.e[c];
    const double lj = lambda * obs.norm2[c] / cj;
    if (e.size() && !((e[e.size() - 1] + lj) <= max_condition * (e[0] + lj))) return false;
  }
  return true;
}

// GCV's n·RSS/(n − dof)² per channel, summed, for every λ of `grid`.
std::vector<double> GcvScores(const ClassSpectrum& cls, const Observation& obs, double n,
                              const std::vector<double>& grid) {
  std::vector<double> score(grid.size(), 0.0);
  const auto curve = ResidualCurve(cls, obs, grid);
  for (size_t l = 0; l < grid.size(); ++l)
    for (const ChannelResidual& r : curve[l]) {
      const double free = std::max(1.0, n - r.dof);
      score[l] += n * r.rss / (free * free);
    }
  return score;
}

// The in-sample residual summed over RGB, for every λ of `grid`.
std::vector<double> ResidualScores(const ClassSpectrum& cls, const Observation& obs, const std::vector<double>& grid) {
  std::vector<double> score(grid.size(), 0.0);
  const auto curve = ResidualCurve(cls, obs, grid);
  for (size_t l = 0; l < grid.size(); ++l)
    for (const ChannelResidual& r : curve[l]) score[l] += r.rss;
  return score;
}

// The sensitivity the penalty computed for class j at grid value `lambda`; NaN where it did not.
double SensitivityAt(const LambdaChoice& c, int j, double lambda) {
  if (c.sensitivity.empty()) return std::nan("");
  for (size_t l = 0; l < c.grid.size(); ++l)
    if (c.grid[l] == lambda) return c.sensitivity.at(j).at(l);
  return std::nan("");
}
}  // namespace

std::vector<std::vector<int>> CandidateMembers(const std::vector<std::vector<int>>& classes,
                                               const std::vector<int>& all, const LambdaChoiceOptions& opt) {
  std::vector<std::vector<int>> out = classes;
  // Not for the rules that pick by in-sample residual: every basis spans each
  // class, so it would always win there.
  if (opt.all_bases_candidate && opt.rule != "fixed" && opt.rule != "residual") out.push_back(all);
  return out;
}

bool WithinStandardErrors(const std::vector<double>& d, double z) {
  const double K = static_cast<double>(d.size());
  if (d.size() < 2) return true;
  double mean = 0;
  for (double v : d) mean += v;
  mean /= K;
  double ss = 0;
  for (double v : d) ss += (v - mean) * (v - mean);
  return mean <= z * std::sqrt(ss / (K - 1) / K);
}

LambdaChoice ChooseLambda(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                          const CvSystem* cv, const Observation& obs, const std::vector<Observation>& held,
                          size_t pixels, const LambdaChoiceOptions& opt, const std::vector<Eigen::MatrixXd>* metrics) {
  LambdaChoice out;
  out.rule = opt.rule;
  out.condition_bound = opt.max_condition;
  if (cv && !held.empty()) out.min_wedge_share = WedgeFloorShare(opt);
  const double total = obs.norm2[0] + obs.norm2[1] + obs.norm2[2];
  if (opt.rule == "fixed") {
    const ClasswiseFit fit = SolveClasswise(f, classes, obs, SolveOptions{opt.fixed});
    out.chosen_class = fit.chosen;
    out.lambda = opt.fixed;
    out.grid = {opt.fixed};
    for (const auto& s : fit.classes) out.score.push_back({s.residual});
    double predicted = fit.classes[fit.chosen].residual;  // in-sample, when no folds are given
    if (cv) {
      BRDFSHOT_CHECK(cv->train.size() == held.size() && !held.empty());
      std::vector<double> s(1, 0.0);
      const std::vector<double> weight = WedgeWeights(obs, held, opt);
      for (size_t k = 0; k < held.size(); ++k)
        AddFoldScores(cv->train[k][fit.chosen], cv->held_class[k][fit.chosen], obs, held[k], out.grid, weight[k], &s);
      predicted = s[0];
    }
    out.held_out_error = out.predicted_error = std::sqrt(predicted / std::max(total, 1e-300));
    out.parts = {{out.chosen_class, out.lambda, 1.0, out.predicted_error, std::nan(""), out.held_out_error}};
    return out;
  }
  BRDFSHOT_CHECK(opt.rule == "cv" || opt.rule == "gcv" || opt.rule == "residual", "unknown λ rule " << opt.rule);
  BRDFSHOT_CHECK(opt.max_condition >= 1, "the condition bound is not resolved (ResolveConditionBound)");
  BRDFSHOT_CHECK(!opt.grid.empty());
  out.grid = opt.grid;
  const double inf = std::numeric_limits<double>::infinity();
  const size_t last = opt.grid.size() - 1;
  // within[j][l]: grid value l keeps class j within the condition bound in
  // every channel. Only those, and the grid's largest λ (the fallback below
  // needs its score), are scored at all.
  std::vector<std::vector<bool>> within(classes.size(), std::vector<bool>(opt.grid.size(), false));
  std::vector<std::vector<bool>> scored = within;
  for (size_t j = 0; j < classes.size(); ++j) {
    if (classes[j].members.empty()) continue;
    for (size_t l = 0; l < opt.grid.size(); ++l) {
      within[j][l] = WithinConditionBound(classes[j], obs, opt.grid[l], opt.max_condition);
      scored[j][l] = within[j][l] || l == last;
    }
  }
  std::vector<std::vector<double>> unbounded(classes.size(), std::vector<double>(opt.grid.size(), inf));
  std::vector<std::vector<double>> per_fold;  // rule cv: [class · K + wedge][λ], each wedge's weighed error
  if (cv) BRDFSHOT_CHECK(cv->train.size() == held.size() && !held.empty() && cv->train[0].size() == classes.size());
  if (opt.rule == "cv") {
    // The wedges' held-out error of every class at its scored λ: one task per
    // class and wedge, all in one parallel loop, so that the small classes'
    // tasks fill in beside the large ones'.
    BRDFSHOT_CHECK(cv, "rule cv needs the folds");
    const int K = static_cast<int>(held.size()), J = static_cast<int>(classes.size());
    per_fold.assign(static_cast<size_t>(J) * K, std::vector<double>(opt.grid.size(), 0.0));
    const std::vector<double> weight = WedgeWeights(obs, held, opt);
    // Largest classes first: a task's cost grows with the square of its
    // members, and the every-basis candidate's tasks, coming last, would
    // leave a thread idle while another finishes them.
    std::vector<int> tasks(static_cast<size_t>(J) * K);
    for (int q = 0; q < J * K; ++q) tasks[q] = q;
    std::stable_sort(tasks.begin(), tasks.end(),
                     [&](int a, int b) { return classes[a / K].members.size() > classes[b / K].members.size(); });
#pragma omp parallel for schedule(dynamic, 1)
    for (int t = 0; t < J * K; ++t) {
      const int q = tasks[t], j = q / K, k = q % K;
      if (!classes[j].members.empty())
        AddFoldScores(cv->train[k][j], cv->held_class[k][j], obs, held[k], opt.grid, weight[k], &per_fold[q],
                      scored[j]);
    }
    for (int j = 0; j < J; ++j) {
      if (classes[j].members.empty()) continue;
      for (size_t l = 0; l < opt.grid.size(); ++l) {
        if (!scored[j][l]) continue;
        unbounded[j][l] = 0;
        for (int k = 0; k < K; ++k)
          unbounded[j][l] += per_fold[j * K + k][l];  // in fold order: the same on any thread count
      }
    }
  }
  for (size_t j = 0; j < classes.size(); ++j) {
    if (classes[j].members.empty()) continue;
    if (opt.rule == "gcv")
      unbounded[j] = GcvScores(classes[j], obs, opt.gcv_pixel_fraction * static_cast<double>(pixels), opt.grid);
    if (opt.rule == "residual") unbounded[j] = ResidualScores(classes[j], obs, opt.grid);
  }
  out.score = unbounded;
  for (size_t j = 0; j < classes.size(); ++j)
    for (size_t l = 0; l < opt.grid.size(); ++l)
      if (!within[j][l]) out.score[j][l] = inf;
  double best = inf;
  // A group's best candidate under the penalty: its penalised and raw
  // held-out scores, class and λ (+inf scores: none).
  struct Best {
    double penalised = std::numeric_limits<double>::infinity(), score = penalised;
    size_t cls = 0, l = 0;
  };
  Best chosen, other;  // the pick, and with the blend the other group's best
  if (opt.rule == "cv" && opt.sensitivity_penalty > 0 && metrics) {
    BRDFSHOT_CHECK(metrics->size() == classes.size(), "one BRDF metric per class");
    // Group 1 is every basis (the last candidate) where the blend asks for
    // it, group 0 the model's classes; each keeps its best penalised
    // candidate. Candidates in order of held-out error: the factor (1 + a s)²
    // is at least 1, so once a candidate's error alone is no better than its
    // group's best penalised score, no later one of that group can win.
    const bool blend = opt.blend_every_basis && opt.all_bases_candidate && classes.size() >= 2;
    const size_t every = classes.size() - 1;
    const int groups = blend ? 2 : 1;
    std::vector<std::pair<double, std::pair<size_t, size_t>>> order;
    for (size_t j = 0; j < classes.size(); ++j)
      for (size_t l = 0; l < opt.grid.size(); ++l)
        if (out.score[j][l] < inf) order.push_back({out.score[j][l], {j, l}});
    std::sort(order.begin(), order.end());
    out.sensitivity.assign(classes.size(), std::vector<double>(opt.grid.size(), std::nan("")));
    out.sensitivity_penalty = opt.sensitivity_penalty;
    out.penalty_gate = opt.penalty_gate >= 0 ? opt.penalty_gate : -1;
    std::array<Best, 2> of;
    // Each group's least held-out error comes first in `order`: the gate's reference.
    std::array<std::pair<size_t, size_t>, 2> least{};
    std::array<bool, 2> seen{false, false};
    const size_t K = held.size();
    for (const auto& [score, at] : order) {
      if (score >= std::max(of[0].penalised, groups == 2 ? of[1].penalised : 0.0)) break;
      const auto [j, l] = at;
      const int g = blend && j == every ? 1 : 0;
      Best& group = of[g];
      if (score >= group.penalised) continue;
      if (!seen[g]) {
        seen[g] = true, least[g] = at;
      } else if (opt.penalty_gate >= 0 && K >= 2) {
        std::vector<double> d(K);
        for (size_t k = 0; k < K; ++k)
          d[k] = per_fold[j * K + k][l] - per_fold[least[g].first * K + k][least[g].second];
        if (!WithinStandardErrors(d, opt.penalty_gate)) continue;
      }
      const double s = PriorSensitivity(classes[j], obs, opt.grid[l], (*metrics)[j]);
      out.sensitivity[j][l] = s;
      const double factor = 1 + opt.sensitivity_penalty * s;
      const double penalised = score * factor * factor;
      if (penalised < group.penalised) group = {penalised, score, j, l};
    }
    const int won = of[1].penalised < of[0].penalised ? 1 : 0;
    chosen = of[won];
    if (blend) other = of[1 - won];
    if (chosen.penalised < inf)
      best = chosen.score, out.chosen_class = static_cast<int>(chosen.cls), out.lambda = opt.grid[chosen.l];
  } else {
    for (size_t j = 0; j < classes.size(); ++j)
      for (size_t l = 0; l < opt.grid.size(); ++l)
        if (out.score[j][l] < best)
          best = out.score[j][l], out.chosen_class = static_cast<int>(j), out.lambda = opt.grid[l];
  }
  if (out.chosen_class < 0) {
    // No λ of the grid keeps any class within the condition bound — a
    // channel of the photo that is black (λ_j = λ‖y_c‖²/c_j is then 0 at
    // every λ) with ill-conditioned classes. The most regularised fit is the
    // safe one: the grid's largest λ, the class the criterion scores best there.
    for (size_t j = 0; j < classes.size(); ++j) {
      if (classes[j].members.empty()) continue;
      const double s = unbounded[j][last];
      if (out.chosen_class < 0 || s < best) best = s, out.chosen_class = static_cast<int>(j);
    }
    out.lambda = opt.grid[last];
    out.beyond_condition_bound = true;
    if (out.chosen_class >= 0) out.score[out.chosen_class][last] = best;
  }
  BRDFSHOT_CHECK(out.chosen_class >= 0, "no non-empty class to choose");
  size_t chosen_l = 0;
  while (opt.grid[chosen_l] != out.lambda) ++chosen_l;
  const double n = opt.gcv_pixel_fraction * static_cast<double>(pixels);
  // Held-out error where the folds are given; else GCV·n = RSS/(1 − dof/n)²,
  // the residual inflated to a prediction error, or the in-sample residual.
  double predicted = opt.rule == "gcv" ? best * n : best;
  if (cv) {
    // The other rules' picks are scored on the wedges alone: one class, one λ.
    std::vector<bool> at(opt.grid.size(), false);
    at[chosen_l] = true;
    if (opt.rule == "cv") {
      predicted = best;
    } else {
      predicted = 0;
      const std::vector<double> weight = WedgeWeights(obs, held, opt);
      for (size_t k = 0; k < held.size(); ++k) {
        std::vector<double> s(opt.grid.size(), 0.0);
        AddFoldScores(cv->train[k][out.chosen_class], cv->held_class[k][out.chosen_class], obs, held[k], opt.grid,
                      weight[k], &s, at);
        predicted += s[chosen_l];  // in fold order, as the cv rule sums
      }
    }
  }
  // With the penalty, a part's predicted error is its held-out error weighed
  // as the pick weighs it, times (1 + a·s): the score the pick compared. The
  // error a fit reports is its FitConfidence, in the image metric.
  auto weighed = [&](double held_out, double sensitivity) {
    return std::isfinite(sensitivity) ? held_out * (1 + out.sensitivity_penalty * sensitivity) : held_out;
  };
  const double chosen_sensitivity = SensitivityAt(out, out.chosen_class, out.lambda);
  out.held_out_error = std::sqrt(predicted / std::max(total, 1e-300));
  out.predicted_error = weighed(out.held_out_error, chosen_sensitivity);
  out.parts = {{out.chosen_class, out.lambda, 1.0, out.predicted_error, chosen_sensitivity, out.held_out_error}};
  // Weights ∝ 1 / penalised score: inverse-variance weights, each score read
  // as its part's squared error; written so that a zero score (a photo the
  // part fits exactly) takes the whole weight.
  if (other.penalised < inf && chosen.penalised < inf && chosen.penalised > 0 &&
      chosen.penalised / (chosen.penalised + other.penalised) >= opt.min_blend_weight) {
    const double lambda = opt.grid[other.l];
    LambdaChoice::Part part{static_cast<int>(other.cls),
                            lambda,
                            0,
                            0,
                            SensitivityAt(out, static_cast<int>(other.cls), lambda),
                            std::sqrt(other.score / std::max(total, 1e-300))};
    part.predicted_error = weighed(part.held_out_error, part.sensitivity);
    part.weight = chosen.penalised / (chosen.penalised + other.penalised);
    out.parts[0].weight = 1 - part.weight;
    out.parts.push_back(part);
    out.predicted_error = out.parts[0].weight * out.parts[0].predicted_error + part.weight * part.predicted_error;
    out.held_out_error = out.parts[0].weight * out.parts[0].held_out_error + part.weight * part.held_out_error;
  }
  return out;
}

namespace {
// Σ a_j b_j in double, a widened as it is read. Eight running sums, added in
// a fixed order, so the compiler can keep them in one vector register: a
// single sum waits on each addition before the next.
double WidenedDot(const float* a, const double* b, Eigen::Index n) {
  constexpr int kLanes = 8;
  double lane[kLanes] = {0, 0, 0, 0, 0, 0, 0, 0};
  Eigen::Index j = 0;
  for (; j + kLanes <= n; j += kLanes)
    for (int l = 0; l < kLanes; ++l) lane[l] += static_cast<double>(a[j + l]) * b[j + l];
  double sum = 0;
  for (; j < n; ++j) sum += static_cast<double>(a[j]) * b[j];
  for (int l = 0; l < kLanes; ++l) sum += lane[l];
  return sum;
}

// The candidate with the most members (every basis, where it is one): the
// fit whose residual bounds the noise. The first of equals.
const ClassSpectrum& LargestClass(const std::vector<ClassSpectrum>& classes) {
  const ClassSpectrum* largest = &classes.at(0);
  for (const ClassSpectrum& c : classes)
    if (c.members.size() > largest->members.size()) largest = &c;
  return *largest;
}

// The least λ of `grid` that keeps `cls` within `max_condition`; −1 when none
// does.
double LeastLambdaWithin(const ClassSpectrum& cls, const Observation& obs, const std::vector<double>& grid,
                         double max_condition) {
  double least = -1;
  for (double lambda : grid)
    if ((least < 0 || lambda < least) && WithinConditionBound(cls, obs, lambda, max_condition)) least = lambda;
  return least;
}
}  // namespace

double FitResidualNoise(const ClassSpectrum& cls, const Observation& obs, size_t pixels,
                        const std::vector<double>& grid, double max_condition) {
  const double total = obs.norm2[0] + obs.norm2[1] + obs.norm2[2];
  const double n = static_cast<double>(pixels);
  if (cls.members.empty() || !cls.solvable() || !(total > 0) || pixels == 0) return -1;
  const double lambda = LeastLambdaWithin(cls, obs, grid, max_condition);
  if (lambda < 0) return -1;
  const auto curve = ResidualCurve(cls, obs, {lambda});
  double rss = 0, free = 0;
  for (const ChannelResidual& r : curve[0]) rss += r.rss, free += std::max(1.0, n - r.dof);
  return std::sqrt(rss / free) / std::sqrt(total / (3 * n));
}

Eigen::MatrixXd LeastRegularisedWeights(const ClassSpectrum& cls, const Observation& obs,
                                        const std::vector<double>& grid, double max_condition) {
  if (cls.members.empty() || !cls.solvable()) return {};
  const double lambda = LeastLambdaWithin(cls, obs, grid, max_condition);
  if (lambda < 0) return {};
  const double cj = static_cast<double>(cls.members.size());
  Eigen::MatrixXd w(cls.members.size(), 3);
  for (int c = 0; c < 3; ++c) w.col(c) = SolveFromSpectrum(cls, c, obs.z[c](cls.members), lambda * obs.norm2[c] / cj);
  return w;
}

double FitPixelNoise(const PixelGeometry& g, const std::array<MatrixXfR, 3>& Y, const Eigen::MatrixXd& y,
                     const std::vector<ClassSpectrum>& classes, const Observation& obs,
                     const LambdaChoiceOptions& opt) {
  if (classes.empty()) return kUnknownNoise;
  const ClassSpectrum& largest = LargestClass(classes);
  const Eigen::MatrixXd w = LeastRegularisedWeights(largest, obs, opt.grid, opt.noise_bound.max_bound);
  if (w.size() == 0) return kUnknownNoise;
  // The weights over every column (zero outside the class), so that a
  // pixel's fitted value is one contiguous dot product with its row, widened
  // to double as it is read; the rows are spread over the threads. The fit is
  // one pass over the basis images, as the projection is.
  const std::vector<int>& J = largest.members;
  Eigen::MatrixXd w_full = Eigen::MatrixXd::Zero(Y[0].cols(), 3);
  for (size_t k = 0; k < J.size(); ++k) w_full.row(J[k]) = w.row(static_cast<Eigen::Index>(k));
  Eigen::MatrixXd fitted(y.rows(), 3);
  const Eigen::Index pixels = y.rows();
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < 3 * pixels; ++i) {
    const int c = static_cast<int>(i / pixels);
    const Eigen::Index p = i % pixels;
    fitted(p, c) = WidenedDot(Y[c].row(p).data(), w_full.col(c).data(), w_full.rows());
  }
  return ResidualPixelNoise(g, y, fitted);
}

double BoundPixelNoise(double pixel_noise, const PixelGeometry& g, const std::array<MatrixXfR, 3>& Y,
                       const Eigen::MatrixXd& y, const std::vector<ClassSpectrum>& classes, const Observation& obs,
                       const LambdaChoiceOptions& opt) {
  if (!(pixel_noise > 0) || opt.max_condition > 0 || !opt.noise_bound.read_fit_residual) return pixel_noise;
  const double residual = FitPixelNoise(g, Y, y, classes, obs, opt);
  return residual >= 0 ? std::min(pixel_noise, residual) : pixel_noise;
}

double BoundNoise(double pixel_noise, const std::vector<ClassSpectrum>& classes, const Observation& obs, size_t pixels,
                  const LambdaChoiceOptions& opt) {
  if (!(pixel_noise > 0) || opt.max_condition > 0 || classes.empty()) return pixel_noise;
  const double fit_noise = FitResidualNoise(LargestClass(classes), obs, pixels, opt.grid, opt.noise_bound.max_bound);
  return fit_noise >= 0 ? std::min(pixel_noise, fit_noise) : pixel_noise;
}

LambdaChoiceOptions ResolveConditionBound(const LambdaChoiceOptions& opt, double relative_noise) {
  LambdaChoiceOptions out = opt;
  if (out.max_condition <= 0) out.max_condition = ConditionBoundForNoise(relative_noise, opt.noise_bound);
  // A wedge's noise holds ε² of the mean wedge's ‖y‖² (ε relative to the
  // photo's RMS, wedges of equal size): no darker wedge is weighed as darker.
  if (out.min_wedge_share < 0) out.min_wedge_share = relative_noise >= 0 ? relative_noise * relative_noise : 0.1;
  return out;
}

LambdaChoiceOptions ResolveConditionBound(const LambdaChoiceOptions& opt, double pixel_noise,
                                          const std::vector<ClassSpectrum>& classes, const Observation& obs,
                                          size_t pixels) {
  return ResolveConditionBound(opt, BoundNoise(pixel_noise, classes, obs, pixels, opt));
}

}  // namespace brdfshot
