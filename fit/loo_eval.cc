#include "fit/loo_eval.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>

#include "fit/bin_constraints.h"
#include "fit/fit_confidence.h"
#include "fit/photo_noise.h"
#include "util/check.h"
#include "util/progress.h"

namespace brdfshot {

double RelativeError(const std::array<const Eigen::MatrixXd*, 3>& g, const Eigen::MatrixXd& w, int m) {
  return RelativeErrors(g, {&w}, m)[0];
}

std::vector<double> RelativeErrors(const std::array<const Eigen::MatrixXd*, 3>& g,
                                   const std::vector<const Eigen::MatrixXd*>& w, int m) {
  const Eigen::Index sets = static_cast<Eigen::Index>(w.size());
  Eigen::VectorXd num = Eigen::VectorXd::Zero(sets);
  double den = 0;
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd D(g[c]->rows(), sets);
    for (Eigen::Index i = 0; i < sets; ++i) D.col(i) = w[static_cast<size_t>(i)]->col(c);
    D.row(3 * m + c).array() -= 1.0;
    const Eigen::MatrixXd GD = *g[c] * D;
    for (Eigen::Index i = 0; i < sets; ++i) num[i] += D.col(i).dot(GD.col(i));
    den += (*g[c])(3 * m + c, 3 * m + c);
  }
  std::vector<double> out(w.size(), 0.0);
  for (Eigen::Index i = 0; i < sets; ++i)
    out[static_cast<size_t>(i)] = den > 0 ? std::sqrt(std::max(0.0, num[i]) / den) : 0.0;
  return out;
}

namespace {
// Projection of channel c of material m onto `keep` in the metric `gcos`:
// argmin (w − e)ᵀ G (w − e) over w supported on keep ⇒ G_KK w_K = G_K,e.
// G_KK may be singular (near-duplicate bases): pseudo-inverse through its
// eigendecomposition, dropping eigenvalues below 1e-12 of the largest.
Eigen::MatrixXd OracleWeights(const Eigen::MatrixXd& gcos, const std::vector<int>& keep, int m) {
  const Eigen::Index n = gcos.rows();
  const Eigen::MatrixXd Gkk = gcos(keep, keep);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Gkk);
  const Eigen::VectorXd ev = eig.eigenvalues();
  const double cut = 1e-12 * ev.maxCoeff();
  Eigen::VectorXd inv = ev;
  for (Eigen::Index i = 0; i < ev.size(); ++i) inv[i] = ev[i] > cut ? 1.0 / ev[i] : 0.0;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 3);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd rhs = gcos(keep, std::vector<int>{3 * m + c});
    const Eigen::VectorXd x = eig.eigenvectors() * inv.asDiagonal() * (eig.eigenvectors().transpose() * rhs);
    for (size_t k = 0; k < keep.size(); ++k) w(keep[k], c) = x[k];
  }
  return w;
}

// The relit-space oracle: per channel, the weights over `keep` that fit the
// true relit images under every fitted scene b ≠ a in least squares,
// argmin Σ_b ‖Y_b (w − e)‖² ⇒ H_KK w_K = H_K,e with H = Σ_b Y_bᵀ Y_b. No fit
// from one photo relights better under those scenes in that sum, so it is the
// floor of the relit error. H sums the Gram matrices of thousands of pixels
// under several probes; where near-duplicate bases leave it singular, a ridge
// of 1e-12 of its mean diagonal keeps the Cholesky factor defined (it moves
// the residual by that order).
Eigen::MatrixXd RelitOracleWeights(const std::vector<SceneFactors>& scenes, int a, const std::vector<int>& keep,
                                   int m) {
  const Eigen::Index n = scenes[a].f[0].gram.rows();
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 3);
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    for (size_t b = 0; b < scenes.size(); ++b)
      if (static_cast<int>(b) != a && !scenes[b].scoring_only) H += scenes[b].f[c].gram;
    if (H.trace() == 0) continue;  // a single fitted scene: nothing to relight
    Eigen::MatrixXd Hk = H(keep, keep);
    Hk.diagonal().array() += 1e-12 * Hk.trace() / static_cast<double>(keep.size());
    const Eigen::VectorXd x = Hk.llt().solve(H(keep, std::vector<int>{3 * m + c}));
    for (size_t k = 0; k < keep.size(); ++k) w(keep[k], c) = x[k];
  }
  return w;
}

std::vector<std::vector<int>> MembersInFull(const ClassModel& model, const std::vector<int>& keep) {
  std::vector<std::vector<int>> out(model.classes());
  for (size_t i = 0; i < keep.size(); ++i) out[model.label[i]].push_back(keep[i]);
  return out;
}

// The candidates' spectra: the model's classes as `classes` already holds
// them (CandidateMembers lists them first), the rest (every basis) factored
// here in tridiagonal form: it is factored for every material and scene, and
// its eigenvectors would cost about twice as much (SpectrumParts).
std::vector<ClassSpectrum> CandidateSpectra(const std::array<ChannelFactor, 3>& f,
                                            const std::vector<ClassSpectrum>& classes,
                                            const std::vector<std::vector<int>>& candidates) {
  BRDFSHOT_CHECK(candidates.size() >= classes.size());
  for (size_t j = 0; j < classes.size(); ++j)
    BRDFSHOT_CHECK(candidates[j] == classes[j].members, "the candidates do not begin with the classes");
  std::vector<ClassSpectrum> out = classes;
  for (ClassSpectrum& s :
       FactorClasses(f, {candidates.begin() + static_cast<std::ptrdiff_t>(classes.size()), candidates.end()},
                     SpectrumParts::kTridiagonal))
    out.push_back(std::move(s));
  return out;
}

// The printed M-step's classes, eigenvalues only (it is solved once at its
// fixed λ). It leaves one class of every basis, whose spectrum the default's
// every-basis candidate already holds: taken from `known` where the members
// are the same (its eigenvalues, all that a solve at one λ needs, are those of
// G_JJ however it was factored, to rounding), factored otherwise.
std::vector<ClassSpectrum> EigenvaluesOfClasses(const std::array<ChannelFactor, 3>& f,
                                                const std::vector<std::vector<int>>& members,
                                                const std::vector<ClassSpectrum>& known) {
  std::vector<ClassSpectrum> out;
  for (const std::vector<int>& J : members) {
    const auto same = std::find_if(known.begin(), known.end(), [&](const ClassSpectrum& s) { return s.members == J; });
    if (same == known.end()) {
      out.push_back(FactorClasses(f, {J}, SpectrumParts::kEigenvalues)[0]);
    } else {
      out.push_back(*same);
      out.back().V = {};
      out.back().Q = {};
      out.back().diagonal = out.back().off_diagonal = {};
    }
  }
  return out;
}

}  // namespace

Eigen::MatrixXd MaterialImage(const std::array<MatrixXfR, 3>& images, int m) {
  Eigen::MatrixXd y(images[0].rows(), 3);
  for (int c = 0; c < 3; ++c) y.col(c) = images[c].col(3 * m + c).cast<double>();
  return y;
}

MatrixXfR SampleBins(const TablesRef& B, int stride, int offset) {
  BRDFSHOT_CHECK(stride >= 1 && offset >= 0);
  const Eigen::Index rows = B.rows() > offset ? (B.rows() - offset + stride - 1) / stride : 0;
  MatrixXfR out(rows, B.cols());
  for (Eigen::Index i = 0; i < rows; ++i) out.row(i) = B.row(offset + i * stride);
  return out;
}

std::vector<double> NegativeBinShares(const MatrixXfR& bins, const Eigen::MatrixXd& W) {
  BRDFSHOT_CHECK(W.cols() % 3 == 0);
  std::vector<double> out(W.cols() / 3, -1.0);
  if (bins.rows() == 0) return out;
  BRDFSHOT_CHECK(bins.cols() == W.rows());
  // One float product for every fit at once (the bins are read once); the
  // magnitude Σ|w_i b_i| only where a value is below zero.
  const Eigen::MatrixXf Wf = W.cast<float>();
  const Eigen::MatrixXf values = bins * Wf;
  std::fill(out.begin(), out.end(), 0.0);
  for (Eigen::Index c = 0; c < values.cols(); ++c)
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      if (values(i, c) >= 0) continue;
      const double magnitude = bins.row(i).cast<double>().cwiseAbs().dot(W.col(c).cwiseAbs());
      out[c / 3] += values(i, c) < -kNegativeBinTolerance * magnitude;
    }
  for (double& v : out) v /= 3.0 * static_cast<double>(bins.rows());
  return out;
}

double NegativeBinShare(const MatrixXfR& bins, const Eigen::MatrixXd& w) { return NegativeBinShares(bins, w)[0]; }

JointScene JointOfScenes(const SceneFactors& a, const SceneFactors& b, PhotoStats photo_a, PhotoStats photo_b) {
  BRDFSHOT_CHECK(!a.scoring_only && !b.scoring_only && a.fold_gram.size() == b.fold_gram.size(),
                 "a joint fit needs two fitted scenes with the same folds");
  BRDFSHOT_CHECK(photo_a.mean_square > 0 && photo_b.mean_square > 0, "a photo of the joint fit is black");
  // Each photo scaled by s = 1/RMS: its Gram matrices by s².
  const double sa = 1 / photo_a.mean_square, sb = 1 / photo_b.mean_square;
  JointScene j;
  for (int c = 0; c < 3; ++c) j.f[c].gram = sa * a.f[c].gram + sb * b.f[c].gram;
  j.fold_gram.resize(a.fold_gram.size());
  for (size_t k = 0; k < a.fold_gram.size(); ++k)
    for (int c = 0; c < 3; ++c) j.fold_gram[k][c] = sa * a.fold_gram[k][c] + sb * b.fold_gram[k][c];
  j.pixels = a.pixels + b.pixels;
  const double ea = photo_a.noise, eb = photo_b.noise;
  j.photo_noise = ea < 0 || eb < 0
                      ? kUnknownNoise
                      : std::sqrt((ea * ea * static_cast<double>(a.pixels) + eb * eb * static_cast<double>(b.pixels)) /
                                  static_cast<double>(std::max<size_t>(1, j.pixels)));
  j.scale = {sa, sb};
  return j;
}

JointScene JointOfScenes(const SceneFactors& a, const SceneFactors& b, int m) {
  const auto stats = [m](const SceneFactors& s) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += s.f[c].gram(3 * m + c, 3 * m + c);
    return PhotoStats{sum / (3.0 * static_cast<double>(std::max<size_t>(1, s.pixels))), s.PhotoNoise(m)};
  };
  return JointOfScenes(a, b, stats(a), stats(b));
}

std::vector<Observation> HeldObservations(const std::vector<std::array<Eigen::MatrixXd, 3>>& fold_gram, int m) {
  std::vector<Observation> held(fold_gram.size());
  for (size_t k = 0; k < fold_gram.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      held[k].z[c] = fold_gram[k][c].col(3 * m + c);
      held[k].norm2[c] = fold_gram[k][c](3 * m + c, 3 * m + c);
    }
  return held;
}

namespace {
int NextFitted(const std::vector<SceneFactors>& scenes, int a) {
  const int S = static_cast<int>(scenes.size());
  for (int i = 1; i < S; ++i) {
    const int b = (a + i) % S;
    if (!scenes[b].scoring_only) return b;
  }
  return -1;
}
}  // namespace

int JointPartner(const std::vector<SceneFactors>& scenes, int a) {
  if (scenes.at(a).scoring_only) return -1;
  const int b = NextFitted(scenes, a);
  // With two fitted scenes each is the other's next: one pair, counted at the first.
  return b < 0 || (b < a && NextFitted(scenes, b) == a) ? -1 : b;
}

std::string ClassFeaturesHelp() { return "linear, cos or log-cos"; }

LobeSystem LobeScene::System(int m) const {
  LobeSystem s;
  for (int c = 0; c < 3; ++c) s.gram[c] = gram[c], s.z[c] = cross[c].row(m).transpose(), s.norm2[c] = self[c][m];
  return s;
}

LobeScene MakeLobeScene(const std::array<MatrixXfR, 3>& images, const std::array<MatrixXfR, 3>& L) {
  const Eigen::Index M = images[0].cols() / 3;
  LobeScene s;
  for (int c = 0; c < 3; ++c) {
    BRDFSHOT_CHECK(images[c].rows() == L[c].rows(), "lobe images and material images differ in pixels");
    const Eigen::MatrixXd Lc = L[c].cast<double>();
    s.gram[c] = Lc.transpose() * Lc;
    s.cross[c].resize(M, Lc.cols());
    s.self[c].resize(M);
    for (Eigen::Index m = 0; m < M; ++m) {
      const Eigen::VectorXd y = images[c].col(3 * m + c).cast<double>();
      s.cross[c].row(m) = (Lc.transpose() * y).transpose();
      s.self[c][m] = y.squaredNorm();
    }
  }
  return s;
}

LooRow LambertGgxRow(const LooInputs& in, int a, int m, const std::string& material) {
  const LambertGgxFit fit = FitLambertGgx(in.lobes, in.lobe_scenes[a].System(m));
  LooRow row;
  row.material = material;
  row.probe = in.scenes[a].probe;
  row.method = "lambert-ggx";
  ScoreRelit(
      in.scenes, a, [&](int b) { return LobeRelativeError(in.lobe_scenes[b].System(m), fit.weights); }, &row);
  row.brdf = std::nan("");
  row.insample = fit.relative_residual;
  row.negative_bins = 0;
  return row;
}

LooRow MethodRow(const FittedMethod& method, const std::string& material, const std::string& probe,
                 const LambdaChoice& choice, double fixed_lambda, const FitConfidence* confidence) {
  LooRow row;
  row.material = material;
  row.probe = probe;
  row.method = method.name;
  row.chosen_class = method.chosen_class;
  const std::string name = method.name;
  if (name.rfind("auto", 0) == 0) {
    row.lambda = choice.lambda, row.predicted = choice.predicted_error, row.held_out = choice.held_out_error;
    row.condition_bound = choice.condition_bound;
  }
  if (name == "auto" && confidence && confidence->prior_sensitivity >= 0)
    row.prior_sensitivity = confidence->prior_sensitivity, row.predicted = confidence->predicted_relit_error;
  if (name == "ours" || name == "paper") row.lambda = fixed_lambda;
  return row;
}

Eigen::MatrixXd SignedWeights(const ClassSolution& fit, const std::array<ChannelFactor, 3>& f, const ClassSpectrum& cls,
                              const Observation& obs, double lambda) {
  return fit.unconstrained_weights.size() ? fit.unconstrained_weights : SolveClass(f, cls, obs, lambda).weights;
}

ClassSolution SolveAuto(const LooInputs& in, WeightConstraint::Kind kind, const std::array<ChannelFactor, 3>& f,
                        const Observation& obs, const ClassSpectrum& cls, double lambda,
                        std::map<int, BinRows>* bins_of_class, int class_index) {
  WeightConstraint constraint;
  constraint.kind = kind;
  BinRows* bins = nullptr;
  if (kind == WeightConstraint::Kind::kBins) {
    auto it = bins_of_class->find(class_index);
    if (it == bins_of_class->end())
      it = bins_of_class->emplace(class_index, BinRows::AllRows(in.constraint_sample, cls.members)).first;
    bins = &it->second;
    constraint.bins = bins;
  }
  ClassSolution s = SolveClass(f, cls, obs, lambda, constraint);
  if (bins && in.table_check) {
    TableCheckSource checks(in.table_check->tables(), in.table_check);
    KeepNonNegativeOnTable(f, cls, obs, lambda, &checks, bins, &s);
  }
  return s;
}

AutoFit SolveChoice(const LooInputs& in, WeightConstraint::Kind kind, const std::array<ChannelFactor, 3>& f,
                    const Observation& obs, const std::vector<ClassSpectrum>& classes, const LambdaChoice& choice,
                    std::map<int, BinRows>* bins_of_class, bool with_sensitivity) {
  BRDFSHOT_CHECK(!choice.parts.empty(), "a choice without parts");
  AutoFit out;
  for (const LambdaChoice::Part& part : choice.parts) {
    const ClassSpectrum& cls = classes.at(part.cls);
    const ClassSolution s = SolveAuto(in, kind, f, obs, cls, part.lambda, bins_of_class, part.cls);
    const Eigen::MatrixXd signed_weights = SignedWeights(s, f, cls, obs, part.lambda);
    if (out.weights.size() == 0) {
      out.weights = part.weight * s.weights;
      out.signed_weights = part.weight * signed_weights;
    } else {
      out.weights += part.weight * s.weights;
      out.signed_weights += part.weight * signed_weights;
    }
  }
  const Eigen::MatrixXd& metric = in.sun_gram.rows() == f[0].gram.rows() ? in.sun_gram : in.gram_cos;
  if (with_sensitivity && metric.rows() == f[0].gram.rows())
    out.confidence = ConfidenceOf(choice, classes, obs, [&](int j) {
      const std::vector<int>& J = classes[static_cast<size_t>(j)].members;
      return Eigen::MatrixXd(metric(J, J));
    });
  return out;
}

void SetNegativeBins(const MatrixXfR& bins, const std::vector<FittedMethod>& methods, LooRow* rows) {
  if (methods.empty()) return;
  Eigen::MatrixXd W(methods[0].w.rows(), 3 * static_cast<Eigen::Index>(methods.size()));
  for (size_t i = 0; i < methods.size(); ++i) W.middleCols(3 * static_cast<Eigen::Index>(i), 3) = methods[i].w;
  const std::vector<double> negative = NegativeBinShares(bins, W);
  for (size_t i = 0; i < methods.size(); ++i) rows[i].negative_bins = negative[i];
}

namespace {
std::vector<double> Ranks(const std::vector<double>& v) {
  std::vector<size_t> order(v.size());
  for (size_t i = 0; i < v.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  std::vector<double> rank(v.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    for (size_t k = i; k <= j; ++k) rank[order[k]] = 0.5 * static_cast<double>(i + j);
    i = j + 1;
  }
  return rank;
}
}  // namespace

double SpearmanCorrelation(const std::vector<double>& a, const std::vector<double>& b) {
  BRDFSHOT_CHECK(a.size() == b.size());
  if (a.size() < 2) return 0;
  const std::vector<double> ra = Ranks(a), rb = Ranks(b);
  const double mean = 0.5 * static_cast<double>(a.size() - 1);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (ra[i] - mean) * (rb[i] - mean);
    saa += (ra[i] - mean) * (ra[i] - mean);
    sbb += (rb[i] - mean) * (rb[i] - mean);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

LooResult RunLeaveOneOut(const LooInputs& in, const LooOptions& opt) {
  const int M = static_cast<int>(in.materials.size());
  const int n = 3 * M;
  BRDFSHOT_CHECK(in.gram.rows() == n && in.gram_cos.rows() == n && !in.scenes.empty());
  const int S = static_cast<int>(in.scenes.size());

  std::vector<std::vector<LooRow>> per_material(M);
  std::vector<double> t_cluster(M), t_solve(M);
  Progress progress("leave-one-out", (M - opt.shard_index + opt.shard_count - 1) / opt.shard_count, opt.progress);
#pragma omp parallel for schedule(dynamic, 1)
  for (int m = 0; m < M; ++m) {
    if (m % opt.shard_count != opt.shard_index) continue;
    Stopwatch sw;
    std::vector<int> keep;
    for (int i = 0; i < n; ++i)
      if (i / 3 != m) keep.push_back(i);
    const Eigen::MatrixXd gk = in.gram(keep, keep);
    GmmOptions ours_opt = opt.gmm, paper_opt = opt.gmm;
    ours_opt.paper_mstep = false;
    paper_opt.paper_mstep = true;
    const Eigen::MatrixXd ck = in.class_gram.size() ? Eigen::MatrixXd(in.class_gram(keep, keep)) : gk;
    const auto ours_members = MembersInFull(BuildClassModel(ck, ours_opt), keep);
    const auto auto_members = CandidateMembers(ours_members, keep, opt.choice);
    const std::vector<Eigen::MatrixXd> auto_metrics = ClassMetrics(in.gram_cos, auto_members);
    const auto paper_members = MembersInFull(BuildClassModel(gk, paper_opt), keep);
    const Eigen::MatrixXd oracle = OracleWeights(in.gram_cos, keep, m);
    t_cluster[m] = sw.Seconds();

    Stopwatch sw2;
    SolveOptions so;
    so.lambda = opt.lambda;
    const std::array<const Eigen::MatrixXd*, 3> gcos = {&in.gram_cos, &in.gram_cos, &in.gram_cos};
    std::map<int, BinRows> constraint_bins;        // per chosen class of material m
    std::vector<Eigen::MatrixXd> auto_weights(S);  // the default fit from each scene's photo, for the joint rows
    for (int a = 0; a < S; ++a) {
      if (in.scenes[a].scoring_only) continue;
      const auto& fa = in.scenes[a].f;
      const Observation obs = BasisObservation(fa, {3 * m, 3 * m + 1, 3 * m + 2});
      const std::vector<ClassSpectrum> ours_classes = FactorClasses(fa, ours_members);
      const ClasswiseFit ours = SolveClasswise(fa, ours_classes, obs, so);
      const std::vector<ClassSpectrum> auto_classes = CandidateSpectra(fa, ours_classes, auto_members);
      // Solved once at its fixed λ: eigenvalues only (the printed M-step
      // leaves one class of every basis, whose eigenvectors cost about a quarter of a fit).
      const ClasswiseFit paper = SolveClasswise(fa, EigenvaluesOfClasses(fa, paper_members, auto_classes), obs, so);
      // The default fit: folds of this scene without material m's columns.
      const std::vector<Observation> held = HeldObservations(in.scenes[a].fold_gram, m);
      const CvSystem cv = FactorFolds(fa, in.scenes[a].fold_gram, auto_members, FoldQ::kReflectors,
                                      in.scenes[a].fold_all.empty() ? nullptr : &in.scenes[a].fold_all);
      double pixel_noise = in.scenes[a].PhotoNoise(m);
      if (in.geometry && in.scenes[a].images) {
        // The photo is the material's own basis images.
        const std::array<MatrixXfR, 3>& Y = *in.scenes[a].images;
        pixel_noise = BoundPixelNoise(pixel_noise, *in.geometry, Y, MaterialImage(Y, m), auto_classes, obs, opt.choice);
      }
      const LambdaChoice choice = ChooseLambda(
          fa, auto_classes, &cv, obs, held, in.scenes[a].pixels,
          ResolveConditionBound(opt.choice, pixel_noise, auto_classes, obs, in.scenes[a].pixels), &auto_metrics);
      const AutoFit fit = SolveChoice(in, opt.constraint, fa, obs, auto_classes, choice, &constraint_bins, true);
      const std::vector<FittedMethod> methods = {{"auto", fit.weights, choice.chosen_class},
                                                 {"auto-signed", fit.signed_weights, choice.chosen_class},
                                                 {"ours", ours.weights(), ours.chosen},
                                                 {"paper", paper.weights(), paper.chosen},
                                                 {"lsq", SolveLeastSquares(fa, obs, keep), -1},
                                                 {"oracle", oracle, -1},
                                                 {"relit-oracle", RelitOracleWeights(in.scenes, a, keep, m), -1}};
      // relit[b][i]: method i relit under scene b (in-sample under a).
      std::vector<const Eigen::MatrixXd*> weights;
      for (const FittedMethod& meth : methods) weights.push_back(&meth.w);
      std::vector<std::vector<double>> relit(in.scenes.size());
      for (size_t b = 0; b < in.scenes.size(); ++b) {
        const auto& f = in.scenes[b].f;
        relit[b] = RelativeErrors({&f[0].gram, &f[1].gram, &f[2].gram}, weights, m);
      }
      const std::vector<double> brdf = RelativeErrors(gcos, weights, m);
      for (size_t i = 0; i < methods.size(); ++i) {
        const FittedMethod& meth = methods[i];
        LooRow row = MethodRow(meth, in.materials[m], in.scenes[a].probe, choice, opt.lambda, &fit.confidence);
        ScoreRelit(
            in.scenes, a, [&](int b) { return relit[static_cast<size_t>(b)][i]; }, &row);
        row.brdf = brdf[i];
        row.insample = relit[static_cast<size_t>(a)][i];
        per_material[m].push_back(row);
      }
      SetNegativeBins(in.bin_sample, methods, &per_material[m][per_material[m].size() - methods.size()]);
      // Before the floor (relit-oracle), which the tables and plots keep last.
      if (!in.lobe_scenes.empty())
        per_material[m].insert(per_material[m].end() - 1, LambertGgxRow(in, a, m, in.materials[m]));
      auto_weights[a] = methods[0].w;
    }
    for (int a = 0; a < S && opt.joint; ++a) {
      const int b = JointPartner(in.scenes, a);
      if (b < 0) continue;
      const JointScene js = JointOfScenes(in.scenes[a], in.scenes[b], m);
      const Observation obs = BasisObservation(js.f, {3 * m, 3 * m + 1, 3 * m + 2});
      const std::vector<ClassSpectrum> classes = FactorClasses(js.f, auto_members);
      const CvSystem cv = FactorFolds(js.f, js.fold_gram, auto_members, FoldQ::kReflectors);
      const LambdaChoice choice =
          ChooseLambda(js.f, classes, &cv, obs, HeldObservations(js.fold_gram, m), js.pixels,
                       ResolveConditionBound(opt.choice, js.photo_noise, classes, obs, js.pixels), &auto_metrics);
      const std::string pair = in.scenes[a].probe + "+" + in.scenes[b].probe;
      const std::vector<FittedMethod> methods = {
          {"auto-joint", SolveChoice(in, opt.constraint, js.f, obs, classes, choice, &constraint_bins, false).weights,
           choice.chosen_class},
          {"auto-one", auto_weights[a], -1},
          {"auto-one", auto_weights[b], -1}};
      const std::string probes[3] = {pair, in.scenes[a].probe + " (" + pair + ")",
                                     in.scenes[b].probe + " (" + pair + ")"};
      for (int i = 0; i < 3; ++i) {
        LooRow row = MethodRow(methods[i], in.materials[m], probes[i], choice, opt.lambda);
        if (i > 0)  // the single fits' own are in their "auto" rows
          row.lambda = row.predicted = row.held_out = row.condition_bound = -1;
        ScoreRelitExcept(
            in.scenes, {a, b},
            [&](int s) {
              const auto& f = in.scenes[s].f;
              return RelativeError({&f[0].gram, &f[1].gram, &f[2].gram}, methods[i].w, m);
            },
            &row);
        row.brdf = RelativeError(gcos, methods[i].w, m);
        const std::array<ChannelFactor, 3>& fi = i == 2 ? in.scenes[b].f : i == 1 ? in.scenes[a].f : js.f;
        row.insample = RelativeError({&fi[0].gram, &fi[1].gram, &fi[2].gram}, methods[i].w, m);
        per_material[m].push_back(row);
      }
      SetNegativeBins(in.bin_sample, methods, &per_material[m][per_material[m].size() - methods.size()]);
    }
    t_solve[m] = sw2.Seconds();
    progress.Step();
  }
  LooResult r;
  for (int m = 0; m < M; ++m) {
    r.rows.insert(r.rows.end(), per_material[m].begin(), per_material[m].end());
    r.seconds_cluster += t_cluster[m];
    r.seconds_solve += t_solve[m];
  }
  return r;
}

}  // namespace brdfshot
