#include "fit/solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "fit/bin_constraints.h"
#include "fit/nonneg.h"
#include "fit/tridiagonal.h"
#include "util/check.h"

namespace brdfshot {

Eigen::MatrixXd GramOfRows(const MatrixXfR& Y, const std::vector<int>& rows) {
  const Eigen::Index n = Y.cols(), count = rows.empty() ? Y.rows() : static_cast<Eigen::Index>(rows.size());
  constexpr Eigen::Index kBlock = 2048;  // rows widened to double at a time
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index r0 = 0; r0 < count; r0 += kBlock) {
    const Eigen::Index m = std::min(kBlock, count - r0);
    const Eigen::MatrixXd blk =
        rows.empty()
            ? Eigen::MatrixXd(Y.middleRows(r0, m).cast<double>())
            : Eigen::MatrixXd(Y(std::vector<int>(rows.begin() + r0, rows.begin() + r0 + m), Eigen::all).cast<double>());
    g.selfadjointView<Eigen::Lower>().rankUpdate(blk.transpose());
  }
  return g.selfadjointView<Eigen::Lower>();
}

std::array<ChannelFactor, 3> FactorBasisImages(const std::array<MatrixXfR, 3>& Y, bool with_qr) {
  std::array<ChannelFactor, 3> f;
#pragma omp parallel for schedule(static, 1)
  for (int c = 0; c < 3; ++c) f[c].gram = GramOfRows(Y[c]);
  if (with_qr) AddQr(Y, &f);
  return f;
}

void AddQr(const std::array<MatrixXfR, 3>& Y, std::array<ChannelFactor, 3>* f) {
  for (int c = 0; c < 3; ++c) {
    auto& fc = (*f)[c];
    if (fc.has_qr()) continue;
    const Eigen::Index n = Y[c].cols();
    auto qr = std::make_shared<Eigen::HouseholderQR<Eigen::MatrixXd>>(Y[c].cast<double>());
    // With fewer pixels than bases R is short and wide: pad with zero rows so
    // every column subset has the same n rows.
    fc.R = Eigen::MatrixXd::Zero(n, n);
    const Eigen::Index rows = std::min(n, Y[c].rows());
    fc.R.topRows(rows) = qr->matrixQR().topRows(rows).triangularView<Eigen::Upper>();
    fc.qr = std::move(qr);
  }
}

Eigen::VectorXd ProjectRows(const MatrixXfR& Y, const Eigen::VectorXd& y, const std::vector<int>& rows) {
  // One pass over the float rows, each widened and added to z in double as it
  // is read (z stays in L1): no widened copy is written and read back, and one
  // row at a time reads one contiguous stream. Sweeps of several rows at once
  // keep z in registers but are slower here (docs/benchmarks.md).
  const Eigen::Index n = Y.cols(), count = rows.empty() ? Y.rows() : static_cast<Eigen::Index>(rows.size());
  Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
  double* zd = z.data();
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Index r = rows.empty() ? i : static_cast<Eigen::Index>(rows[i]);
    const float* src = Y.data() + r * n;  // Y is row-major: one contiguous row
    const double w = y[r];
    for (Eigen::Index j = 0; j < n; ++j) zd[j] += w * static_cast<double>(src[j]);
  }
  return z;
}

Observation MakeObservation(const std::array<ChannelFactor, 3>& f, const std::array<MatrixXfR, 3>& Y,
                            const Eigen::MatrixXd& y) {
  Observation o;
  for (int c = 0; c < 3; ++c) BRDFSHOT_CHECK(y.rows() == Y[c].rows());
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd yc = y.col(c);
    o.z[c] = ProjectRows(Y[c], yc);
    o.norm2[c] = yc.squaredNorm();
    if (f[c].has_qr()) {
      Eigen::VectorXd full = yc;
      full.applyOnTheLeft(f[c].qr->householderQ().adjoint());
      o.z_qr[c] = Eigen::VectorXd::Zero(f[c].R.cols());
      const Eigen::Index k = std::min<Eigen::Index>(f[c].R.cols(), full.size());
      o.z_qr[c].head(k) = full.head(k);
    }
  }
  return o;
}

Observation BasisObservation(const std::array<ChannelFactor, 3>& f, const std::array<int, 3>& col) {
  Observation o;
  for (int c = 0; c < 3; ++c) {
    o.z[c] = f[c].gram.col(col[c]);
    o.norm2[c] = f[c].gram(col[c], col[c]);
    if (f[c].has_qr()) o.z_qr[c] = f[c].R.col(col[c]);  // Qᵀ(Y e) = R e
  }
  return o;
}

std::vector<ClassSpectrum> FactorClasses(const std::array<ChannelFactor, 3>& f,
                                         const std::vector<std::vector<int>>& members, SpectrumParts parts) {
  const bool vectors = parts == SpectrumParts::kValuesAndVectors;
  std::vector<ClassSpectrum> out(members.size());
  const bool tridiagonal = parts == SpectrumParts::kTridiagonal;
  for (size_t j = 0; j < members.size(); ++j) {
    out[j].members = members[j];
    if (members[j].empty()) continue;
    for (int c = 0; c < 3; ++c) {
      out[j].gram[c] = f[c].gram(members[j], members[j]);
      out[j].gram_prior[c] = out[j].gram[c].rowwise().sum() / static_cast<double>(members[j].size());
      if (tridiagonal) {
        const Eigen::Tridiagonalization<Eigen::MatrixXd> tri(out[j].gram[c]);
        out[j].diagonal[c] = tri.diagonal();
        out[j].off_diagonal[c] = members[j].size() > 1 ? Eigen::VectorXd(tri.subDiagonal()) : Eigen::VectorXd();
        out[j].Q[c] = tri.matrixQ();
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
        eig.computeFromTridiagonal(out[j].diagonal[c], out[j].off_diagonal[c], Eigen::EigenvaluesOnly);
        out[j].e[c] = eig.eigenvalues().cwiseMax(0.0);
        continue;
      }
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(out[j].gram[c],
                                                         vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
      out[j].e[c] = eig.eigenvalues().cwiseMax(0.0);  // rounding can leave a singular G slightly negative
      if (vectors) out[j].V[c] = eig.eigenvectors();
    }
  }
  return out;
}

Eigen::VectorXd SolveRidge(const Eigen::MatrixXd& A, const Eigen::VectorXd& z, double lambda,
                           const Eigen::VectorXd& prior, double* condition) {
  BRDFSHOT_CHECK(lambda >= 0 && A.rows() == z.size() && A.cols() == prior.size());
  const Eigen::Index m = A.rows(), k = A.cols();
  // Solve for v = w − prior: min ‖A v − (z − A prior)‖² + λ‖v‖².
  Eigen::MatrixXd aug(m + k, k);
  aug.topRows(m) = A;
  aug.bottomRows(k) = std::sqrt(lambda) * Eigen::MatrixXd::Identity(k, k);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + k);
  rhs.head(m) = z - A * prior;
  if (condition) {
    const Eigen::VectorXd s = Eigen::BDCSVD<Eigen::MatrixXd>(A).singularValues();
    const double smax = s.size() ? s[0] : 0, smin = s.size() == k ? s[k - 1] : 0;
    const double den = smin * smin + lambda;
    *condition = den > 0 ? std::sqrt((smax * smax + lambda) / den) : std::numeric_limits<double>::infinity();
  }
  // λ > 0 makes the augmented matrix full rank (its singular values are at
  // least √λ), so a plain Householder QR, blocked, solves it as accurately as
  // a rank-revealing one; at λ = 0 the columns may be dependent and the
  // complete orthogonal decomposition gives the minimum-norm answer.
  if (lambda > 0) return prior + Eigen::HouseholderQR<Eigen::MatrixXd>(aug).solve(rhs);
  return prior + Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(aug).solve(rhs);
}

namespace {
double SpectrumFloor(const Eigen::VectorXd& e) { return 1e-13 * std::max(e.size() ? e[e.size() - 1] : 0.0, 1e-300); }

// The eigenvectors of a class held tridiagonal, Q U with T = U diag(e) Uᵀ,
// and those e: for the λ below SolveClassSystem's floor, where the
// pseudo-inverse needs the directions themselves.
std::pair<Eigen::MatrixXd, Eigen::VectorXd> VectorsOfTridiagonal(const ClassSpectrum& cls, int c) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  eig.computeFromTridiagonal(cls.diagonal[c], cls.off_diagonal[c], Eigen::ComputeEigenvectors);
  return {cls.Q[c] * eig.eigenvectors(), eig.eigenvalues().cwiseMax(0.0)};
}

// Σ_i v_i v_iᵀ b / (e_i + λ_l) per λ_l, the directions at or below the floor left out.
Eigen::MatrixXd SpectralSolves(const Eigen::MatrixXd& V, const Eigen::VectorXd& e, const Eigen::VectorXd& r,
                               const Eigen::VectorXd& lj) {
  const Eigen::VectorXd b = V.transpose() * r;
  const double floor = SpectrumFloor(e);
  Eigen::MatrixXd D(e.size(), lj.size());
  for (Eigen::Index l = 0; l < lj.size(); ++l)
    for (Eigen::Index i = 0; i < e.size(); ++i) D(i, l) = e[i] + lj[l] > floor ? b[i] / (e[i] + lj[l]) : 0.0;
  return V * D;
}
}  // namespace

Eigen::MatrixXd SolveClassSystem(const ClassSpectrum& cls, int c, const Eigen::VectorXd& r, const Eigen::VectorXd& lj) {
  BRDFSHOT_CHECK(cls.solvable(), "a solve at any λ needs the class's eigenvectors or its tridiagonal form");
  BRDFSHOT_CHECK(r.size() == static_cast<Eigen::Index>(cls.members.size()),
                 "a class solve's right side has " << r.size() << " rows for " << cls.members.size() << " members");
  if (cls.members.empty()) return Eigen::MatrixXd(0, lj.size());
  if (!cls.tridiagonal()) return SpectralSolves(cls.V[c], cls.e[c], r, lj);
  const Eigen::VectorXd& e = cls.e[c];
  const double floor = SpectrumFloor(e);
  std::vector<char> solved;
  Eigen::MatrixXd X = TridiagonalSolves(cls.diagonal[c], cls.off_diagonal[c], cls.Q[c].transpose() * r, lj, &solved);
  // A λ at or below the floor leaves directions out, which only the
  // eigenvectors can; a pivot that fails above it (rounding at the floor's
  // edge) is taken the same way.
  std::vector<Eigen::Index> spectral;
  for (Eigen::Index l = 0; l < lj.size(); ++l)
    if (!(e[0] + lj[l] > floor) || !solved[static_cast<size_t>(l)]) spectral.push_back(l);
  Eigen::MatrixXd W = cls.Q[c] * X;
  if (!spectral.empty()) {
    const auto [V, ev] = VectorsOfTridiagonal(cls, c);
    Eigen::VectorXd lj_spectral(static_cast<Eigen::Index>(spectral.size()));
    for (size_t i = 0; i < spectral.size(); ++i) lj_spectral[static_cast<Eigen::Index>(i)] = lj[spectral[i]];
    const Eigen::MatrixXd Ws = SpectralSolves(V, ev, r, lj_spectral);
    for (size_t i = 0; i < spectral.size(); ++i) W.col(spectral[i]) = Ws.col(static_cast<Eigen::Index>(i));
  }
  return W;
}

Eigen::VectorXd SolveFromSpectrum(const ClassSpectrum& cls, int c, const Eigen::VectorXd& zJ, double lambda_j) {
  if (cls.tridiagonal()) {
    const Eigen::Index k = static_cast<Eigen::Index>(cls.members.size());
    return SolveClassSystem(cls, c, zJ - cls.gram_prior[c], Eigen::VectorXd::Constant(1, lambda_j)).col(0) +
           Eigen::VectorXd::Constant(k, 1.0 / static_cast<double>(k));
  }
  BRDFSHOT_CHECK(cls.has_vectors(), "a solve through the spectrum needs the class's eigenvectors");
  const Eigen::VectorXd& e = cls.e[c];
  const Eigen::Index k = e.size();
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(k, 1.0 / static_cast<double>(k));
  // Directions with no data and no weight (e + λ_j ≈ 0) keep the prior: the
  // minimum-norm correction.
  const Eigen::VectorXd b = cls.V[c].transpose() * (zJ - cls.gram_prior[c]);
  const double floor = 1e-13 * std::max(k ? e[k - 1] : 0.0, 1e-300);
  Eigen::VectorXd d(k);
  for (Eigen::Index i = 0; i < k; ++i) d[i] = e[i] + lambda_j > floor ? b[i] / (e[i] + lambda_j) : 0.0;
  return prior + cls.V[c] * d;
}

namespace {
// V diag(1/(e + λ_j)) Vᵀ, the directions at or below the floor left out.
Eigen::MatrixXd SpectralInverse(const Eigen::MatrixXd& V, const Eigen::VectorXd& e, double lambda_j) {
  const double floor = SpectrumFloor(e);
  Eigen::VectorXd inv(e.size());
  for (Eigen::Index i = 0; i < e.size(); ++i) inv[i] = e[i] + lambda_j > floor ? 1.0 / (e[i] + lambda_j) : 0.0;
  return V * inv.asDiagonal() * V.transpose();
}

// (G_JJ + λ_j I)⁺ of channel c through the class's factor, with the floor of
// SolveFromSpectrum: directions it leaves at the prior, this leaves alone.
Eigen::MatrixXd SpectrumInverse(const ClassSpectrum& cls, int c, double lambda_j) {
  BRDFSHOT_CHECK(cls.solvable() && !cls.members.empty(),
                 "the bin constraint needs the class's eigenvectors or its tridiagonal form");
  if (!cls.tridiagonal()) return SpectralInverse(cls.V[c], cls.e[c], lambda_j);
  // Q (T + λ_j I)⁻¹ Qᵀ where T's recurrence holds, T's eigenvectors where
  // it does not (SolveClassSystem's rule).
  const ShiftedTridiagonal shifted(cls.diagonal[c], cls.off_diagonal[c], lambda_j);
  if (cls.e[c][0] + lambda_j > SpectrumFloor(cls.e[c]) && shifted.ok())
    return cls.Q[c] * shifted.Solve(cls.Q[c].transpose());
  const auto [V, e] = VectorsOfTridiagonal(cls, c);
  return SpectralInverse(V, e, lambda_j);
}
}  // namespace

double ClassResidual(const ClassSpectrum& cls, const Observation& obs, const Eigen::MatrixXd& wJ) {
  BRDFSHOT_CHECK(wJ.rows() == static_cast<Eigen::Index>(cls.members.size()) && wJ.cols() == 3,
                 "ClassResidual: weights are members × 3");
  double residual = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd zJ = obs.z[c](cls.members);
    const Eigen::VectorXd w = wJ.col(c);
    // ‖Y_J w − y‖² = wᵀG_JJ w − 2 wᵀz_J + ‖y‖²: accurate to ~1e-16 ‖y‖², ample
    // for comparing classes.
    residual += std::max(0.0, w.dot(cls.gram[c] * w) - 2 * w.dot(zJ) + obs.norm2[c]);
  }
  return residual;
}

ClassSolution SolveClass(const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls, const Observation& obs,
                         double lambda, const WeightConstraint& constraint) {
  const Eigen::Index n = f[0].gram.rows();
  const std::vector<int>& J = cls.members;
  ClassSolution s;
  s.members = static_cast<int>(J.size());
  s.weights = Eigen::MatrixXd::Zero(n, 3);
  BRDFSHOT_CHECK(!J.empty() && lambda >= 0);
  const double cj = static_cast<double>(J.size());
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(J.size(), 1.0 / cj);
  int worst = 0;                   // 0 normal, 1 normal-truncated, 2 qr
  Eigen::MatrixXd W(J.size(), 3);  // the class's weights per channel
  std::array<double, 3> lj{};
  for (int c = 0; c < 3; ++c) {
    lj[c] = lambda * obs.norm2[c] / cj;
    const Eigen::VectorXd& e = cls.e[c];
    const double emax = e.size() ? e[e.size() - 1] : 0, emin = e.size() ? e[0] : 0;
    const double kappa = emin + lj[c] > 0 ? (emax + lj[c]) / (emin + lj[c]) : std::numeric_limits<double>::infinity();
    s.condition[c] = std::sqrt(kappa);
    s.lambda_j[c] = lj[c];
    const Eigen::VectorXd zJ = obs.z[c](J);
    // ‖Y_J w − y‖² + λ_j‖w − μ'‖² = wᵀ(G_JJ + λ_j I)w − 2wᵀ(z_J + λ_j μ') + const.
    const auto regularised = [&] {
      Eigen::MatrixXd H = cls.gram[c];
      H.diagonal().array() += lj[c];
      return H;
    };
    if (constraint.kind == WeightConstraint::Kind::kWeights) {
      W.col(c) = SolveNonNegative(regularised(), zJ + lj[c] * prior).x;
    } else if (kappa > kMaxNormalCondition && f[c].has_qr() && obs.z_qr[c].size()) {
      W.col(c) = SolveRidge(f[c].R(Eigen::all, J), obs.z_qr[c], lj[c], prior);
      worst = std::max(worst, 2);
    } else if (cls.solvable()) {
      W.col(c) = SolveFromSpectrum(cls, c, zJ, lj[c]);
      if (kappa > kMaxNormalCondition) worst = std::max(worst, 1);
    } else {
      BRDFSHOT_CHECK(kappa <= kMaxNormalCondition,
                     "a class factored without eigenvectors is ill-conditioned (κ " << kappa << ") and has no QR");
      const Eigen::LLT<Eigen::MatrixXd> llt(regularised());
      BRDFSHOT_CHECK(llt.info() == Eigen::Success, "G_JJ + λ_j I is not positive definite at κ " << kappa);
      W.col(c) = llt.solve(zJ + lj[c] * prior);
    }
  }
  if (constraint.kind != WeightConstraint::Kind::kWeights) {
    s.unconstrained_weights = Eigen::MatrixXd::Zero(n, 3);
    s.unconstrained_weights(J, Eigen::all) = W;
  }
  if (constraint.kind == WeightConstraint::Kind::kBins) {
    BRDFSHOT_CHECK(constraint.bins && constraint.bins->cols() == static_cast<Eigen::Index>(J.size()),
                   "the constraint's bins must be restricted to the class's members");
    const std::vector<BinConstrainedSolution> constrained =
        ConstrainChannelsToNonNegativeBins([&](int c) { return SpectrumInverse(cls, c, lj[c]); }, W, *constraint.bins);
    for (int c = 0; c < 3; ++c) W.col(c) = constrained[c].w;
  }
  s.residual = ClassResidual(cls, obs, W);
  s.weights(J, Eigen::all) = W;
  s.path = constraint.kind == WeightConstraint::Kind::kWeights ? "nonneg-weights"
           : constraint.kind == WeightConstraint::Kind::kBins  ? "nonneg-bins"
           : worst == 2                                        ? "qr"
           : worst == 1                                        ? "normal-truncated"
                                                               : "normal";
  return s;
}

ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                            const Observation& obs, const std::vector<double>& lambda) {
  BRDFSHOT_CHECK(lambda.size() == classes.size());
  const Eigen::Index n = f[0].gram.rows();
  ClasswiseFit fit;
  double best = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < classes.size(); ++j) {
    ClassSolution s;
    if (classes[j].members.empty()) {
      s.weights = Eigen::MatrixXd::Zero(n, 3);
      s.residual = std::numeric_limits<double>::infinity();
    } else {
      s = SolveClass(f, classes[j], obs, lambda[j]);
      if (s.residual < best) best = s.residual, fit.chosen = static_cast<int>(j);
    }
    fit.classes.push_back(std::move(s));
  }
  BRDFSHOT_CHECK(fit.chosen >= 0, "no non-empty class to solve with");
  return fit;
}

ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const std::vector<ClassSpectrum>& classes,
                            const Observation& obs, const SolveOptions& opt) {
  return SolveClasswise(f, classes, obs, std::vector<double>(classes.size(), opt.lambda));
}

ClasswiseFit SolveClasswise(const std::array<ChannelFactor, 3>& f, const Observation& obs,
                            const std::vector<std::vector<int>>& members, const SolveOptions& opt) {
  return SolveClasswise(f, FactorClasses(f, members), obs, opt);
}

Eigen::MatrixXd SolveLeastSquares(const std::array<ChannelFactor, 3>& f, const Observation& obs,
                                  const std::vector<int>& columns) {
  const Eigen::Index n = f[0].gram.rows();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 3);
  for (int c = 0; c < 3; ++c) {
    BRDFSHOT_CHECK(f[c].has_qr() && obs.z_qr[c].size() == n, "least squares needs the QR factors");
    const Eigen::MatrixXd A = f[c].R(Eigen::all, columns);
    const Eigen::VectorXd x = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(obs.z_qr[c]);
    for (size_t k = 0; k < columns.size(); ++k) w(columns[k], c) = x[k];
  }
  return w;
}

}  // namespace brdfshot
