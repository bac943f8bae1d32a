#include "fit/capture_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fit/photo_fit.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

// A make re-run logs a stage again: its later time replaces the earlier one,
// in the order stages were first seen; the outputs named by -o or --out
// (all of them, for a command that writes several) tell two runs of one
// command apart.
TEST(CaptureReport, StageTimesKeepTheLastRunOfEachStage) {
  const fs::path log = fs::temp_directory_path() / "brdfshot_report_times.tsv";
  std::ofstream(log) << "1.5\tbrdfshot merge photo -o r/photo.exr\n"
                     << "2.0\tbrdfshot merge probe --probe --out r/probe_hdr.exr\n"
                     << "not a time line\n"
                     << "0.5\tbrdfshot merge photo -o r/photo.exr\n"
                     << "3.25\tbrdfshot fit --basis b -o r/fit\n"
                     << "0.75\tbrdfshot render --probe p --merl a -o r/a.exr --merl b -o r/b.exr\n";
  const auto rows = StageTimes(log.string());
  fs::remove(log);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].first, "merge → photo.exr");
  EXPECT_EQ(rows[0].second, 0.5);
  EXPECT_EQ(rows[1].first, "merge → probe_hdr.exr");
  EXPECT_EQ(rows[2].first, "fit → fit");
  EXPECT_EQ(rows[2].second, 3.25);
  EXPECT_EQ(rows[3].first, "render → a.exr, b.exr");
}

// A fit relit at half the truth's radiance is off by exactly 0.5 in relative
// RMSE; the page says so, and the stage table sums the stages.
TEST(CaptureReport, ThePageStatesTheRelitErrorAgainstTheTruthAndTheStageTimes) {
  const fs::path r = fs::temp_directory_path() / "brdfshot_report_results";
  fs::remove_all(r);
  fs::create_directories(r / "relit");
  cv::Mat truth(16, 16, CV_32FC3);
  cv::randu(truth, cv::Scalar::all(0.2), cv::Scalar::all(1.0));
  WriteExr((r / "relit" / "forest_truth.exr").string(), truth);
  WriteExr((r / "relit" / "forest_fit.exr").string(), cv::Mat(truth * 0.5));
  std::ofstream(r / "times.tsv") << "1.25\tbrdfshot merge photo -o x/photo.exr\n2.5\tbrdfshot fit -o x/fit\n";
  CaptureReportOptions o;
  o.results = r.string();
  o.title = "test capture";
  const CaptureReport report = WriteCaptureReport(o);
  ASSERT_EQ(report.relit_error.size(), 1u);
  EXPECT_EQ(report.relit_error[0].first, "forest");
  EXPECT_NEAR(report.relit_error[0].second, 0.5, 1e-6);
  EXPECT_EQ(report.page, (r / "report.md").string());
  const std::string md = Slurp(report.page);
  EXPECT_NE(md.find("# brdfshot report: test capture"), std::string::npos) << md;
  EXPECT_NE(md.find("relative RMSE **0.5000**"), std::string::npos) << md;
  EXPECT_NE(md.find("| **all** | **3.75** |"), std::string::npos) << md;
  EXPECT_TRUE(fs::exists(r / "report" / "relit_forest.png"));
  fs::remove_all(r);
}

// The fit's section says how far the photo was trusted: its noise and the
// condition bound the λ search ran under, as fit.json records them.
TEST(CaptureReport, TheFitSectionStatesThePhotosNoiseAndTheConditionBound) {
  const fs::path r = fs::temp_directory_path() / "brdfshot_report_fit";
  fs::remove_all(r);
  fs::create_directories(r / "fit");
  FitRecord f;
  f.database = "db", f.database_kind = "standin", f.grid = MerlGrid{2, 2, 4}, f.probe = "p.exr", f.photo = "x.exr";
  f.lambda_rule = "cv", f.lambda = 0.01, f.chosen_class = 0, f.relative_residual = 0.02;
  f.classes = {{3, 1.0, 10, "normal"}, {3, 0.5, 100, "normal"}};
  f.lambda_grid = {0.01};
  f.lambda_scores = {{1.0}, {2.0}};
  f.bases = {"a/R", "a/G", "a/B"};
  f.weights = Eigen::MatrixXd::Identity(3, 3);
  f.relative_noise = 0.0049, f.condition_bound = 1.5e6;
  f.parts = {{0, 0.01, 0.75, 0.03}, {1, 1e-4, 0.25, 0.04}};
  f.Write((r / "fit" / "fit.json").string());
  CaptureReportOptions o;
  o.results = r.string();
  const std::string md = Slurp(WriteCaptureReport(o).page);
  EXPECT_NE(md.find("pixel noise 0.0049 of its RMS: λ searched within the condition bound 1.5e+06"), std::string::npos)
      << md;
  EXPECT_NE(md.find("blended: 0.75 × class 0 at λ = "), std::string::npos) << md;
  EXPECT_NE(md.find(" + 0.25 × class 1 at λ = "), std::string::npos) << md;
  fs::remove_all(r);
}

TEST(CaptureReport, AMissingResultsFolderIsNamed) {
  CaptureReportOptions o;
  o.results = "/nonexistent/brdfshot-results";
  try {
    WriteCaptureReport(o);
    ADD_FAILURE() << "a missing folder is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(o.results), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot
