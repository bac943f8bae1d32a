#include "capture/merge_benchmark.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {

// A merge off by one factor everywhere is exact after the per-channel scale;
// a quarter of the samples 20 % too bright give median 0, mean 0.05, 95th
// percentile 0.2 and 5 % too much power; a non-positive sample is unusable.
TEST(MergeBenchmark, ErrorStatisticsAfterTheScaleHaveClosedForms) {
  const cv::Mat truth(8, 10, CV_32FC3, cv::Scalar::all(1.0));
  const cv::Mat all(truth.size(), CV_8UC3, cv::Scalar::all(1));
  const MergeErrorStats exact = CompareToTruth(truth / 3, truth, all);
  EXPECT_NEAR(exact.median, 0, 1e-6);
  EXPECT_NEAR(exact.p95, 0, 1e-6);
  EXPECT_NEAR(exact.power, 0, 1e-6);

  cv::Mat merged = truth * 3;
  for (int y = 0; y < merged.rows; ++y)
    for (int x = 0; x < merged.cols; x += 4) merged.at<cv::Vec3f>(y, x) *= 1.2f;  // columns 0, 4, 8: 30 %
  const MergeErrorStats s = CompareToTruth(merged, truth, all);
  EXPECT_NEAR(s.median, 0, 1e-6);
  EXPECT_NEAR(s.mean, 0.3 * 0.2, 1e-5);
  EXPECT_NEAR(s.p95, 0.2, 1e-5);
  EXPECT_NEAR(s.power, 0.3 * 0.2, 1e-5);
  EXPECT_EQ(s.bad_fraction, 0);

  merged.at<cv::Vec3f>(0, 1) = cv::Vec3f(0, 0, 0);
  EXPECT_NEAR(CompareToTruth(merged, truth, all).bad_fraction, 1.0 / 80, 1e-9);
}

// A sample is measurable when the shortest exposure does not clip it (e·t_min
// < 0.9 of full scale) and the longest lifts it 20× above the read noise.
TEST(MergeBenchmark, MeasurableWhereSomeFrameSawTheTruth) {
  CameraModel cam;
  cam.full_well = 1000, cam.read_noise = 5;  // the floor: e · t_max · 1000 > 100
  cv::Mat truth(1, 3, CV_32FC3);
  truth.at<cv::Vec3f>(0, 0) = cv::Vec3f(0.04f, 0.2f, 1.0f);  // t = 0.5 … 2: floor at e > 0.05, clip at e ≥ 1.8
  truth.at<cv::Vec3f>(0, 1) = cv::Vec3f(1.7f, 1.9f, 0.06f);
  truth.at<cv::Vec3f>(0, 2) = cv::Vec3f(0.049f, 2.5f, 0.5f);
  const cv::Mat m = MeasurableMask(truth, {0.5, 1.0, 2.0}, cam);
  EXPECT_EQ(m.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 1, 1));
  EXPECT_EQ(m.at<cv::Vec3b>(0, 1), cv::Vec3b(1, 0, 1));
  EXPECT_EQ(m.at<cv::Vec3b>(0, 2), cv::Vec3b(0, 0, 1));
}

// The benchmark end to end on one small scene: our merge and OpenCV's both
// recover it, and the table has a row for each; an unknown method is named.
TEST(MergeBenchmark, RunsMethodsSideBySideAndNamesAnUnknownOne) {
  const std::string scene = (std::filesystem::temp_directory_path() / "brdfshot_bench_scene.exr").string();
  cv::Mat hdr(48, 64, CV_32FC3);
  for (int y = 0; y < hdr.rows; ++y)
    for (int x = 0; x < hdr.cols; ++x)
      hdr.at<cv::Vec3f>(y, x) = cv::Vec3f(0.02f + x / 16.0f, 0.05f + y / 24.0f, 0.5f + (x + y) / 40.0f);
  WriteExr(scene, hdr);
  MergeBenchmarkOptions o;
  o.scenes = {scene};
  o.size = {64, 48};
  o.frames = 7;
  o.methods = {"ours", "cv-debevec"};
  const MergeBenchmarkTables t = RunMergeBenchmark(o);
  // The median relative error of each method's row: "scene,\"name\",median,…".
  auto median = [&](const std::string& name) {
    const size_t at = t.csv.find("brdfshot_bench_scene,\"" + name + "\",");
    if (at == std::string::npos) return -1.0;
    return std::stod(t.csv.substr(at + name.size() + std::string("brdfshot_bench_scene,\"\",").size()));
  };
  const double ours = median("brdfshot: Debevec + Robertson-refined response, noise-aware weights (default)");
  const double cv = median("OpenCV CalibrateDebevec + MergeDebevec");
  EXPECT_GE(ours, 0) << t.csv;
  EXPECT_LT(ours, 0.05) << t.csv;
  EXPECT_GE(cv, 0) << t.csv;
  EXPECT_NE(t.markdown.find("| method | median of medians"), std::string::npos);
  o.methods = {"ours", "nonsense"};
  try {
    RunMergeBenchmark(o);
    ADD_FAILURE() << "an unknown method is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'nonsense'"), std::string::npos);
  }
  std::filesystem::remove(scene);
}

}  // namespace brdfshot
