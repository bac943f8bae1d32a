#include "fit/class_model.h"

#include <gtest/gtest.h>

#include <filesystem>

#include <opencv2/core/eigen.hpp>
#include <opencv2/ml.hpp>
#include <Eigen/SVD>
#include <random>

#include "util/check.h"

namespace brdfshot {

namespace {
// Four well-separated anisotropic Gaussian blobs in 4-D.
Eigen::MatrixXd Blobs(std::vector<int>* truth, uint32_t seed = 4) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  const int sizes[4] = {60, 45, 20, 30};
  const double centres[4][4] = {{0, 0, 0, 0}, {12, 0, 3, 0}, {0, 15, 0, -4}, {-10, -8, 6, 2}};
  Eigen::MatrixXd X(4, 155);
  int col = 0;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < sizes[k]; ++i, ++col) {
      for (int d = 0; d < 4; ++d) X(d, col) = centres[k][d] + g(rng) * (1.0 + 0.5 * d);
      X(1, col) += 0.8 * X(0, col) - 0.8 * centres[k][0];  // correlated axes: full covariances matter
      truth->push_back(k);
    }
  return X;
}

// Fraction of pairs on which two labelings agree about "same class or not".
double RandIndex(const std::vector<int>& a, const std::vector<int>& b) {
  size_t agree = 0, total = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = i + 1; j < a.size(); ++j, ++total) agree += (a[i] == a[j]) == (b[i] == b[j]);
  return static_cast<double>(agree) / total;
}
}  // namespace

TEST(ClassModel, ProjectionFromGramEqualsProjectionOnLeftSingularVectors) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Random(500, 12);
  B.col(3) *= 50;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinU);
  const Eigen::MatrixXd want = svd.matrixU().leftCols(4).transpose() * B;  // Û^T B
  const Eigen::MatrixXd got = ProjectFromGram(B.transpose() * B, 4);
  for (int k = 0; k < 4; ++k) {
    const double sign = want.row(k).dot(got.row(k)) < 0 ? -1 : 1;  // an SVD's sign is free
    EXPECT_LT((sign * got.row(k) - want.row(k)).norm(), 1e-8 * want.row(k).norm());
  }
}

TEST(ClassModel, ResponsibilitiesSumToOneAndEmIsMonotone) {
  std::vector<int> truth;
  const Eigen::MatrixXd X = Blobs(&truth);
  GmmOptions opt;
  const ClassModel m = FitGmm(X, opt);
  for (Eigen::Index i = 0; i < m.resp.rows(); ++i) EXPECT_NEAR(m.resp.row(i).sum(), 1.0, 1e-12);
  EXPECT_NEAR(m.mix.sum(), 1.0, 1e-12);
  EXPECT_TRUE(m.converged);
  GmmOptions few = opt;
  few.max_iterations = 2;
  EXPECT_LE(FitGmm(X, few).log_likelihood, m.log_likelihood + 1e-9);
  EXPECT_GT(RandIndex(m.label, truth), 0.99);
}

TEST(ClassModel, AgreesWithOpenCvEm) {
  std::vector<int> truth;
  const Eigen::MatrixXd X = Blobs(&truth, 17);
  const ClassModel ours = FitGmm(X, GmmOptions{});
  cv::Mat samples;
  const Eigen::MatrixXd Xt = X.transpose();
  cv::eigen2cv(Xt, samples);
  auto em = cv::ml::EM::create();
  em->setClustersNumber(4);
  em->setCovarianceMatrixType(cv::ml::EM::COV_MAT_GENERIC);
  em->setTermCriteria(cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 1000, 1e-10));
  cv::Mat labels, loglik;
  ASSERT_TRUE(em->trainEM(samples, loglik, labels, cv::noArray()));
  std::vector<int> cv_labels(labels.rows);
  for (int i = 0; i < labels.rows; ++i) cv_labels[i] = labels.at<int>(i);
  EXPECT_GT(RandIndex(ours.label, cv_labels), 0.99);
  // Same total log-likelihood (OpenCV returns it per sample).
  EXPECT_NEAR(ours.log_likelihood, cv::sum(loglik)[0], 1e-3 * std::abs(ours.log_likelihood));
}

TEST(ClassModel, PaperMStepInflatesTheMeansByN) {
  // The M-step on the same k-means responsibilities (no E-step yet): the printed
  // M-step divides by π_j = N_j / n instead of N_j, so every mean is n times the
  // corrected one.
  std::vector<int> truth;
  const Eigen::MatrixXd X = Blobs(&truth);
  GmmOptions a, b;
  a.max_iterations = b.max_iterations = 0;
  b.paper_mstep = true;
  const ClassModel ours = FitGmm(X, a), paper = FitGmm(X, b);
  for (int k = 0; k < 4; ++k)
    EXPECT_LT((paper.means[k] - X.cols() * ours.means[k]).norm(), 1e-9 * paper.means[k].norm());
}

TEST(ClassModel, JsonRoundTripAndNamedErrors) {
  std::vector<int> truth;
  const Eigen::MatrixXd X = Blobs(&truth);
  ClassModel m = FitGmm(X, GmmOptions{});
  EXPECT_THROW(m.ToJson(), std::logic_error) << "a model that does not name its bases is not written";
  for (Eigen::Index i = 0; i < X.cols(); ++i)
    m.basis_names.push_back("material" + std::to_string(i / 3) + "/RGB"[i % 3]);
  m.database = "test database";
  m.grid = {9, 9, 18};
  const std::string path = (std::filesystem::temp_directory_path() / "brdfshot_class_model_test.json").string();
  m.Write(path);
  const ClassModel back = ClassModel::Read(path);
  std::filesystem::remove(path);
  EXPECT_EQ(back.label, m.label);
  EXPECT_EQ(back.basis_names, m.basis_names);
  EXPECT_EQ(back.database, m.database);
  EXPECT_EQ(back.grid, m.grid);
  EXPECT_LT((back.coords - m.coords).norm(), 1e-12);
  EXPECT_EQ(back.ToJson(), m.ToJson());
  nlohmann::json j = m.ToJson();
  j["bases"][3]["class"] = 9;
  EXPECT_THROW(ClassModel::FromJson(j, "x.json"), std::runtime_error);
}

}  // namespace brdfshot
