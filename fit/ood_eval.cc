#include "fit/ood_eval.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>

#include "fit/bin_constraints.h"
#include "fit/fit_confidence.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

TargetScene MakeTargetScene(const std::array<ChannelFactor, 3>& f, const std::array<MatrixXfR, 3>& Y,
                            const std::array<MatrixXfR, 3>& Yt, const std::vector<int>& fold_of_pixel, int folds) {
  const Eigen::Index T = Yt[0].cols() / 3, n = Y[0].cols();
  const std::vector<std::vector<int>> rows = RowsByFold(fold_of_pixel, folds);
  TargetScene s;
  s.fold_cross.resize(folds);
  s.fold_self.resize(folds);
  for (int c = 0; c < 3; ++c) {
    s.cross[c].resize(n, T);
    if (f[c].has_qr()) s.cross_qr[c].resize(n, T);
    s.self[c].resize(T);
    for (int k = 0; k < folds; ++k) s.fold_cross[k][c].resize(n, T), s.fold_self[k][c].resize(T);
#pragma omp parallel for schedule(dynamic, 4)
    for (Eigen::Index t = 0; t < T; ++t) {
      const Eigen::VectorXd y = Yt[c].col(3 * t + c).cast<double>();
      s.self[c][t] = y.squaredNorm();
      const std::vector<Eigen::VectorXd> z = ProjectRowsByFold(Y[c], y, fold_of_pixel, folds);
      Eigen::VectorXd parts = Eigen::VectorXd::Zero(n);
      for (int k = 0; k < folds; ++k) {
        const Eigen::VectorXd& zk = z[static_cast<size_t>(k)];
        s.fold_cross[k][c].col(t) = zk;
        s.fold_self[k][c][t] = y(rows[k]).squaredNorm();
        parts += zk;
      }
      s.cross[c].col(t) = parts;
      if (!f[c].has_qr()) continue;
      Eigen::VectorXd full = y;
      full.applyOnTheLeft(f[c].qr->householderQ().adjoint());
      s.cross_qr[c].col(t) = Eigen::VectorXd::Zero(n);
      const Eigen::Index k = std::min<Eigen::Index>(n, full.size());
      s.cross_qr[c].col(t).head(k) = full.head(k);
    }
  }
  return s;
}

namespace {
std::vector<std::vector<int>> Members(const ClassModel& model) {
  std::vector<std::vector<int>> out;
  for (int j = 0; j < model.classes(); ++j) out.push_back(model.Members(j));
  return out;
}

// Relit error of w against target t under scene b.
double TargetError(const ChannelFactor* f, const TargetScene& s, const Eigen::MatrixXd& w, int t) {
  double num = 0, den = 0;
  for (int c = 0; c < 3; ++c) {
    num += w.col(c).dot(f[c].gram * w.col(c)) - 2 * w.col(c).dot(s.cross[c].col(t)) + s.self[c][t];
    den += s.self[c][t];
  }
  return den > 0 ? std::sqrt(std::max(0.0, num) / den) : 0.0;
}

// Pseudo-inverse of a symmetric matrix through its eigendecomposition,
// eigenvalues below 1e-12 of the largest dropped.
Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& g) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
  const Eigen::VectorXd ev = eig.eigenvalues();
  const double cut = 1e-12 * ev.maxCoeff();
  Eigen::VectorXd inv = ev;
  for (Eigen::Index i = 0; i < ev.size(); ++i) inv[i] = ev[i] > cut ? 1.0 / ev[i] : 0.0;
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}
}  // namespace

LooResult RunOutOfDatabase(const LooInputs& bases, const std::vector<TargetScene>& scenes,
                           const std::vector<std::string>& targets, const LooOptions& opt) {
  const int S = static_cast<int>(bases.scenes.size()), T = static_cast<int>(targets.size());
  const int n = static_cast<int>(bases.gram.rows());
  BRDFSHOT_CHECK(static_cast<int>(scenes.size()) == S);
  std::vector<int> fitted;  // the scenes fits are made from (and the oracle's)
  for (int a = 0; a < S; ++a)
    if (!bases.scenes[a].scoring_only) fitted.push_back(a);
  const int F = static_cast<int>(fitted.size());
  BRDFSHOT_CHECK(F > 1, "out-of-database evaluation needs two probes to fit from");
  Stopwatch sw;
  GmmOptions ours_opt = opt.gmm, paper_opt = opt.gmm;
  ours_opt.paper_mstep = false;
  paper_opt.paper_mstep = true;
  const auto ours_members = Members(BuildClassModel(bases.class_gram.size() ? bases.class_gram : bases.gram, ours_opt));
  const auto paper_members = Members(BuildClassModel(bases.gram, paper_opt));
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  const auto auto_members = CandidateMembers(ours_members, all, opt.choice);
  // The BRDF metric of the λ choice's sensitivity penalty; none without the database's.
  const std::vector<Eigen::MatrixXd> auto_metrics =
      bases.gram_cos.rows() == n ? ClassMetrics(bases.gram_cos, auto_members) : std::vector<Eigen::MatrixXd>{};
  const std::vector<Eigen::MatrixXd>* metrics = auto_metrics.empty() ? nullptr : &auto_metrics;
  // Per scene: what does not depend on the target.
  std::vector<std::vector<ClassSpectrum>> ours_classes(S), paper_classes(S), auto_classes(S);
  std::vector<CvSystem> cv(S);
  std::vector<std::array<Eigen::MatrixXd, 3>> oracle_inverse(S);  // (Σ_{b≠a} G_b)⁺ per channel
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < F; ++i) {
    const int a = fitted[i];
    const auto& fa = bases.scenes[a].f;
    ours_classes[a] = FactorClasses(fa, ours_members);
    paper_classes[a] = FactorClasses(fa, paper_members, SpectrumParts::kEigenvalues);  // solved at its fixed λ only
    auto_classes[a] = auto_members.size() == ours_members.size() ? ours_classes[a] : FactorClasses(fa, auto_members);
    cv[a] = FactorFolds(fa, bases.scenes[a].fold_gram, auto_members);
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(n, n);
      for (int b : fitted)
        if (b != a) sum += bases.scenes[b].f[c].gram;
      oracle_inverse[a][c] = PseudoInverse(sum);
    }
  }
  LooResult r;
  r.seconds_cluster = sw.Seconds();

  std::vector<std::vector<LooRow>> per_target(T);
  Progress progress("out of database", (T - opt.shard_index + opt.shard_count - 1) / opt.shard_count, opt.progress);
  SolveOptions so;
  so.lambda = opt.lambda;
#pragma omp parallel for schedule(dynamic, 1)
  for (int t = 0; t < T; ++t) {
    if (t % opt.shard_count != opt.shard_index) continue;
    std::vector<Eigen::MatrixXd> auto_weights(S);  // the default fit from each scene's photo, for the joint rows
    std::map<int, BinRows> constraint_bins;        // per chosen class, for this target's fits (SolveAuto)
    for (int a : fitted) {
      const auto& fa = bases.scenes[a].f;
      const TargetScene& ta = scenes[a];
      Observation obs;
      for (int c = 0; c < 3; ++c) {
        obs.z[c] = ta.cross[c].col(t);
        obs.z_qr[c] = ta.cross_qr[c].col(t);
        obs.norm2[c] = ta.self[c][t];
      }
      const int K = static_cast<int>(ta.fold_cross.size());
      std::vector<Observation> held(K);
      for (int k = 0; k < K; ++k)
        for (int c = 0; c < 3; ++c) held[k].z[c] = ta.fold_cross[k][c].col(t), held[k].norm2[c] = ta.fold_self[k][c][t];
      double pixel_noise = bases.scenes[a].PhotoNoise(t);
      if (bases.geometry && ta.images && ta.target_images) {
        pixel_noise = BoundPixelNoise(pixel_noise, *bases.geometry, *ta.images, MaterialImage(*ta.target_images, t),
                                      auto_classes[a], obs, opt.choice);
      }
      const LambdaChoice choice = ChooseLambda(
          fa, auto_classes[a], &cv[a], obs, held, bases.scenes[a].pixels,
          ResolveConditionBound(opt.choice, pixel_noise, auto_classes[a], obs, bases.scenes[a].pixels), metrics);
      const ClasswiseFit ours = SolveClasswise(fa, ours_classes[a], obs, so);
      const ClasswiseFit paper = SolveClasswise(fa, paper_classes[a], obs, so);
      Eigen::MatrixXd oracle(n, 3);
      for (int c = 0; c < 3; ++c) {
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
        for (int b : fitted)
          if (b != a) rhs += scenes[b].cross[c].col(t);
        oracle.col(c) = oracle_inverse[a][c] * rhs;
      }
      const AutoFit fit = SolveChoice(bases, opt.constraint, fa, obs, auto_classes[a], choice, &constraint_bins, true);
      const std::vector<FittedMethod> methods = {
          {"auto", fit.weights, choice.chosen_class},   {"auto-signed", fit.signed_weights, choice.chosen_class},
          {"ours", ours.weights(), ours.chosen},        {"paper", paper.weights(), paper.chosen},
          {"lsq", SolveLeastSquares(fa, obs, all), -1}, {"relit-oracle", oracle, -1}};
      for (const FittedMethod& m : methods) {
        LooRow row = MethodRow(m, targets[t], bases.scenes[a].probe, choice, opt.lambda, &fit.confidence);
        ScoreRelit(
            bases.scenes, a, [&](int b) { return TargetError(bases.scenes[b].f.data(), scenes[b], m.w, t); }, &row);
        row.brdf = std::nan("");
        row.insample = TargetError(fa.data(), ta, m.w, t);
        per_target[t].push_back(row);
      }
      SetNegativeBins(bases.bin_sample, methods, &per_target[t][per_target[t].size() - methods.size()]);
      // Before the floor (relit-oracle), which the tables and plots keep last.
      if (!bases.lobe_scenes.empty())
        per_target[t].insert(per_target[t].end() - 1, LambertGgxRow(bases, a, t, targets[t]));
      auto_weights[a] = methods[0].w;
    }
    for (int a : fitted) {
      const int b = opt.joint ? JointPartner(bases.scenes, a) : -1;
      if (b < 0) continue;
      const auto stats = [&](int s) {
        double sum = 0;
        for (int c = 0; c < 3; ++c) sum += scenes[s].self[c][t];
        return PhotoStats{sum / (3.0 * static_cast<double>(std::max<size_t>(1, bases.scenes[s].pixels))),
                          bases.scenes[s].PhotoNoise(t)};
      };
      const JointScene js = JointOfScenes(bases.scenes[a], bases.scenes[b], stats(a), stats(b));
      const double sa = js.scale[0], sb = js.scale[1];
      Observation obs;
      std::vector<Observation> held(js.fold_gram.size());
      for (int c = 0; c < 3; ++c) {
        obs.z[c] = sa * scenes[a].cross[c].col(t) + sb * scenes[b].cross[c].col(t);
        obs.norm2[c] = sa * scenes[a].self[c][t] + sb * scenes[b].self[c][t];
        for (size_t k = 0; k < held.size(); ++k) {
          held[k].z[c] = sa * scenes[a].fold_cross[k][c].col(t) + sb * scenes[b].fold_cross[k][c].col(t);
          held[k].norm2[c] = sa * scenes[a].fold_self[k][c][t] + sb * scenes[b].fold_self[k][c][t];
        }
      }
      const std::vector<ClassSpectrum> classes = FactorClasses(js.f, auto_members);
      const CvSystem joint_cv = FactorFolds(js.f, js.fold_gram, auto_members, FoldQ::kReflectors);
      const LambdaChoice choice =
          ChooseLambda(js.f, classes, &joint_cv, obs, held, js.pixels,
                       ResolveConditionBound(opt.choice, js.photo_noise, classes, obs, js.pixels), metrics);
      const Eigen::MatrixXd w =
          SolveChoice(bases, opt.constraint, js.f, obs, classes, choice, &constraint_bins, false).weights;
      const std::string pair = bases.scenes[a].probe + "+" + bases.scenes[b].probe;
      const std::vector<FittedMethod> methods = {
          {"auto-joint", w, choice.chosen_class}, {"auto-one", auto_weights[a], -1}, {"auto-one", auto_weights[b], -1}};
      const std::string probes[3] = {pair, bases.scenes[a].probe + " (" + pair + ")",
                                     bases.scenes[b].probe + " (" + pair + ")"};
      for (int i = 0; i < 3; ++i) {
        LooRow row = MethodRow(methods[i], targets[t], probes[i], choice, opt.lambda);
        if (i > 0)  // the single fits' own are in their "auto" rows
          row.lambda = row.predicted = row.held_out = row.condition_bound = -1;
        ScoreRelitExcept(
            bases.scenes, {a, b},
            [&](int s) { return TargetError(bases.scenes[s].f.data(), scenes[s], methods[i].w, t); }, &row);
        row.brdf = std::nan("");
        if (i == 0) {  // in-sample over both photos, each at its scale
          double num = 0, den = 0;
          for (int c = 0; c < 3; ++c) {
            num += w.col(c).dot(js.f[c].gram * w.col(c)) - 2 * w.col(c).dot(obs.z[c]) + obs.norm2[c];
            den += obs.norm2[c];
          }
          row.insample = den > 0 ? std::sqrt(std::max(0.0, num) / den) : 0.0;
        } else {
          const int s = i == 1 ? a : b;
          row.insample = TargetError(bases.scenes[s].f.data(), scenes[s], methods[i].w, t);
        }
        per_target[t].push_back(row);
      }
      SetNegativeBins(bases.bin_sample, methods, &per_target[t][per_target[t].size() - methods.size()]);
    }
    progress.Step();
  }
  for (auto& rows : per_target) r.rows.insert(r.rows.end(), rows.begin(), rows.end());
  r.seconds_solve = sw.Seconds() - r.seconds_cluster;
  return r;
}

}  // namespace brdfshot
