#include "fit/class_model.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <random>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/json_int.h"

namespace brdfshot {

Eigen::MatrixXd ProjectFromGram(const Eigen::MatrixXd& gram, int dims, Eigen::VectorXd* sv) {
  BRDFSHOT_CHECK(gram.rows() == gram.cols() && dims >= 1 && dims <= gram.rows());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  BRDFSHOT_CHECK(eig.info() == Eigen::Success, "eigendecomposition of the Gram matrix failed");
  const Eigen::Index n = gram.rows();
  Eigen::MatrixXd coords(dims, n);
  Eigen::VectorXd s(dims);
  for (int k = 0; k < dims; ++k) {
    const Eigen::Index col = n - 1 - k;  // eigenvalues ascend
    s[k] = std::sqrt(std::max(0.0, eig.eigenvalues()[col]));
    Eigen::VectorXd v = eig.eigenvectors().col(col);
    // Fix the sign (an eigenvector's sign is arbitrary): largest entry positive,
    // so the same data always gives the same coordinates.
    Eigen::Index imax;
    v.cwiseAbs().maxCoeff(&imax);
    if (v[imax] < 0) v = -v;
    coords.row(k) = s[k] * v.transpose();
  }
  if (sv) *sv = s;
  return coords;
}

std::vector<int> KMeans(const Eigen::MatrixXd& X, int k, uint32_t seed, int restarts) {
  const Eigen::Index n = X.cols();
  BRDFSHOT_CHECK(k >= 1 && k <= n, "k-means needs 1 <= k <= points");
  std::mt19937 rng(seed);
  std::vector<int> best;
  double best_inertia = std::numeric_limits<double>::infinity();
  for (int run = 0; run < restarts; ++run) {
    // k-means++ seeding.
    Eigen::MatrixXd C(X.rows(), k);
    C.col(0) = X.col(std::uniform_int_distribution<Eigen::Index>(0, n - 1)(rng));
    Eigen::VectorXd d2 = (X.colwise() - C.col(0)).colwise().squaredNorm().transpose();
    for (int j = 1; j < k; ++j) {
      const double total = d2.sum();
      Eigen::Index pick = 0;
      if (total > 0) {
        double r = std::uniform_real_distribution<double>(0, total)(rng);
        for (pick = 0; pick < n - 1 && (r -= d2[pick]) > 0; ++pick) {
        }
      }
      C.col(j) = X.col(pick);
      d2 = d2.cwiseMin((X.colwise() - C.col(j)).colwise().squaredNorm().transpose());
    }
    std::vector<int> label(n, -1);
    double inertia = 0;
    for (int iter = 0; iter < 300; ++iter) {
      bool changed = false;
      inertia = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        Eigen::Index j;
        inertia += (C.colwise() - X.col(i)).colwise().squaredNorm().minCoeff(&j);
        if (label[i] != j) changed = true, label[i] = static_cast<int>(j);
      }
      if (!changed) break;
      Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(X.rows(), k);
      Eigen::VectorXd cnt = Eigen::VectorXd::Zero(k);
      for (Eigen::Index i = 0; i < n; ++i) sum.col(label[i]) += X.col(i), cnt[label[i]] += 1;
      for (int j = 0; j < k; ++j)
        if (cnt[j] > 0) C.col(j) = sum.col(j) / cnt[j];
    }
    if (inertia < best_inertia) best_inertia = inertia, best = label;
  }
  return best;
}

Eigen::VectorXd LogGaussian(const Eigen::MatrixXd& X, const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov) {
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  BRDFSHOT_CHECK(llt.info() == Eigen::Success, "covariance not positive definite");
  const Eigen::MatrixXd z = llt.matrixL().solve(X.colwise() - mean);
  const double logdet = 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  const double d = static_cast<double>(X.rows());
  return (-0.5 * (z.colwise().squaredNorm().array() + logdet + d * std::log(2 * M_PI))).matrix().transpose();
}

std::vector<int> ClassModel::Members(int j) const {
  std::vector<int> out;
  for (size_t i = 0; i < label.size(); ++i)
    if (label[i] == j) out.push_back(static_cast<int>(i));
  return out;
}

ClassModel FitGmm(const Eigen::MatrixXd& X, const GmmOptions& opt) {
  const Eigen::Index n = X.cols(), d = X.rows();
  const int K = opt.classes;
  BRDFSHOT_CHECK(K >= 1 && n >= K, "need at least as many bases as classes");
  ClassModel m;
  m.coords = X;
  m.paper_mstep = opt.paper_mstep;
  const Eigen::VectorXd grand_mean = X.rowwise().mean();
  const double mean_var = (X.colwise() - grand_mean).squaredNorm() / (n * d);
  const Eigen::MatrixXd ridge = Eigen::MatrixXd::Identity(d, d) * (opt.reg * std::max(mean_var, 1e-300));

  // Initialisation from k-means: π_j = share of points, μ_j, Σ_j of the cluster.
  const std::vector<int> km = KMeans(X, K, opt.seed);
  m.resp = Eigen::MatrixXd::Zero(n, K);
  for (Eigen::Index i = 0; i < n; ++i) m.resp(i, km[i]) = 1;
  m.mix.resize(K);
  m.means.assign(K, Eigen::VectorXd::Zero(d));
  m.covs.assign(K, Eigen::MatrixXd::Identity(d, d));

  auto m_step = [&]() {
    for (int j = 0; j < K; ++j) {
      const double nj = m.resp.col(j).sum();
      m.mix[j] = nj / n;
      // The corrected M-step normalises by N_j; the paper's printed one by π_j.
      const double denom = opt.paper_mstep ? m.mix[j] : nj;
      if (nj < 1e-12 || denom <= 0) {  // an empty class keeps its last Gaussian
        m.mix[j] = std::max(m.mix[j], 1e-300);
        continue;
      }
      m.means[j] = X * m.resp.col(j) / denom;
      const Eigen::MatrixXd c = X.colwise() - m.means[j];
      m.covs[j] = (c * m.resp.col(j).asDiagonal() * c.transpose()) / denom + ridge;
    }
  };
  auto e_step = [&]() {
    Eigen::MatrixXd logp(n, K);
    for (int j = 0; j < K; ++j) logp.col(j) = LogGaussian(X, m.means[j], m.covs[j]).array() + std::log(m.mix[j]);
    double ll = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double mx = logp.row(i).maxCoeff();
      const double lse = mx + std::log((logp.row(i).array() - mx).exp().sum());
      m.resp.row(i) = (logp.row(i).array() - lse).exp();
      ll += lse;
    }
    return ll;
  };

  m_step();
  double prev = -std::numeric_limits<double>::infinity();
  for (m.iterations = 1; m.iterations <= opt.max_iterations; ++m.iterations) {
    m.log_likelihood = e_step();
    if (std::abs(m.log_likelihood - prev) <= opt.tolerance * std::abs(m.log_likelihood)) {
      m.converged = true;
      break;
    }
    prev = m.log_likelihood;
    m_step();
  }
  m.iterations = std::min(m.iterations, opt.max_iterations);
  m.label.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Index j;
    m.resp.row(i).maxCoeff(&j);
    m.label[i] = static_cast<int>(j);
  }
  return m;
}

ClassModel BuildClassModel(const Eigen::MatrixXd& gram, const GmmOptions& opt) {
  Eigen::VectorXd sv;
  const Eigen::MatrixXd coords = ProjectFromGram(gram, opt.dims, &sv);
  ClassModel m = FitGmm(coords, opt);
  m.singular_values = sv;
  return m;
}

std::string ClassSizes(const ClassModel& m) {
  std::string s;
  for (int j = 0; j < m.classes(); ++j) s += (j ? " / " : "") + std::to_string(m.Members(j).size());
  return s;
}

namespace {
nlohmann::json Vec(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }
Eigen::VectorXd ToVec(const nlohmann::json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
}
}  // namespace

nlohmann::json ClassModel::ToJson() const {
  BRDFSHOT_CHECK(basis_names.size() == static_cast<size_t>(coords.cols()), "a class model names every basis");
  nlohmann::json j;
  j["format"] = "brdfshot-class-model-1";
  j["dims"] = coords.rows();
  j["classes"] = classes();
  j["paper_mstep"] = paper_mstep;
  j["log_likelihood"] = log_likelihood;
  j["iterations"] = iterations;
  j["converged"] = converged;
  j["database"] = database;
  j["grid"] = grid;
  j["singular_values"] = Vec(singular_values);
  j["mix"] = Vec(mix);
  for (int k = 0; k < classes(); ++k) {
    j["means"].push_back(Vec(means[k]));
    j["covs"].push_back(std::vector<double>(covs[k].data(), covs[k].data() + covs[k].size()));
  }
  for (Eigen::Index i = 0; i < coords.cols(); ++i) {
    j["bases"].push_back({{"name", basis_names[i]},
                          {"class", label[i]},
                          {"coords", Vec(coords.col(i))},
                          {"resp", Vec(resp.row(i).transpose())}});
  }
  return j;
}

ClassModel ClassModel::FromJson(const nlohmann::json& j, const std::string& source) {
  try {
    if (j.at("format") != "brdfshot-class-model-1") throw Error("unknown format");
    ClassModel m;
    const int d = static_cast<int>(JsonInt(j, "dims", 1, 1 << 20, source)),
              K = static_cast<int>(JsonInt(j, "classes", 1, 1 << 20, source));
    m.paper_mstep = j.at("paper_mstep");
    m.log_likelihood = j.at("log_likelihood");
    m.iterations = static_cast<int>(JsonInt(j, "iterations", 0, 1 << 30, source));
    m.converged = j.at("converged");
    m.singular_values = ToVec(j.at("singular_values"));
    m.mix = ToVec(j.at("mix"));
    if (m.mix.size() != K) throw Error("inconsistent dims/classes");
    for (int k = 0; k < K; ++k) {
      m.means.push_back(ToVec(j.at("means").at(k)));
      const Eigen::VectorXd c = ToVec(j.at("covs").at(k));
      if (m.means.back().size() != d || c.size() != d * d) throw Error("bad mean/cov size");
      m.covs.push_back(Eigen::Map<const Eigen::MatrixXd>(c.data(), d, d));
    }
    const auto& bases = j.at("bases");
    m.coords.resize(d, bases.size());
    m.resp.resize(bases.size(), K);
    for (size_t i = 0; i < bases.size(); ++i) {
      const int label = static_cast<int>(JsonInt(bases[i], "class", 0, K - 1, source));
      m.label.push_back(label);
      const Eigen::VectorXd c = ToVec(bases[i].at("coords")), r = ToVec(bases[i].at("resp"));
      if (c.size() != d || r.size() != K) throw Error("bad basis entry");
      m.coords.col(i) = c;
      m.resp.row(i) = r.transpose();
      m.basis_names.push_back(bases[i].at("name"));
    }
    m.database = j.value("database", "");
    if (j.contains("grid")) m.grid = j.at("grid");
    return m;
  } catch (const Error& e) {
    throw FileError(source, std::string("bad class model: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("bad class model: ") + e.what());
  }
}

void ClassModel::Write(const std::string& path) const {
  const std::string text = ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& o) { o << text << "\n"; });
}

ClassModel ClassModel::Read(const std::string& path) { return FromJson(ReadJsonFile(path), path); }

}  // namespace brdfshot
