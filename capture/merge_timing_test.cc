#include "capture/merge_timing.h"

#include <gtest/gtest.h>

#include "capture/test_scenes.h"
#include "util/check.h"

namespace brdfshot {
namespace {

// A gradient of grey seen through a linear camera at exposure t, `depth`-bit.
cv::Mat Gradient(double t, int depth) {
  const double top = depth == CV_8U ? 255 : 65535;
  cv::Mat bgr(48, 64, depth == CV_8U ? CV_8UC3 : CV_16UC3);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const double code = top * t * (0.08 + 0.8 * x / bgr.cols) * (0.6 + 0.4 * y / bgr.rows);
      for (int c = 0; c < 3; ++c)
        if (depth == CV_8U)
          bgr.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(code);
        else
          bgr.at<cv::Vec3w>(y, x)[c] = cv::saturate_cast<uint16_t>(code);
    }
  return bgr;
}

}  // namespace

// The merges run on the same files; each method's steps fit inside its total
// (they are timed within it), ours' noise model and pooling inside its merge,
// and the table quotes OpenCV's own ratio as 1.
TEST(MergeTiming, TimesBothMergesWithTheirStepsInsideTheTotal) {
  FrameFolder d("brdfshot_merge_timing");
  for (double t : {0.25, 0.5, 1.0, 2.0}) d.Add(Gradient(t, CV_8U), t);
  BracketReadOptions read;
  read.times_path = d.TimesPath();
  MergeTimingOptions opt;
  opt.repeats = 1;
  cv::MatAllocator* const before = cv::Mat::getDefaultAllocator();
  const BracketTimings timings = TimeBracketMerges(d.files, read, opt);
  EXPECT_EQ(cv::Mat::getDefaultAllocator(), before) << "each method's allocator is restored";
  ASSERT_EQ(timings.methods.size(), 3u);
  EXPECT_EQ(timings.frames, 4);
  EXPECT_EQ(timings.size, cv::Size(64, 48));
  EXPECT_EQ(timings.methods[0].method, "brdfshot");
  EXPECT_EQ(timings.methods[1].method, "OpenCV Debevec");
  for (const MergeTiming& t : timings.methods) {
    EXPECT_GT(t.read, 0) << t.method;
    EXPECT_GT(t.merge, 0) << t.method;
    EXPECT_LE(t.read + t.response + t.merge, t.total * 1.0001) << t.method;
  }
  EXPECT_LE(timings.methods[0].noise + timings.methods[0].pool, timings.methods[0].merge * 1.0001);
  EXPECT_EQ(timings.methods[1].noise, 0);
  EXPECT_EQ(timings.methods[2].method, "OpenCV Debevec, huge-page images");
  const std::string table = MergeTimingTable(timings, "test frames");
  EXPECT_NE(table.find("4 frames of 64x48 (test frames)"), std::string::npos) << table;
  const size_t opencv_row = table.find("| OpenCV Debevec |");
  ASSERT_NE(opencv_row, std::string::npos) << table;
  EXPECT_NE(table.find("| 1.000 |", opencv_row), std::string::npos) << table;
}

// OpenCV's Debevec merge takes 8-bit frames only: a 16-bit bracket is refused
// naming its first file, before anything is timed.
TEST(MergeTiming, RefusesASixteenBitBracketNamingTheFile) {
  FrameFolder d("brdfshot_merge_timing_16");
  for (double t : {0.5, 1.0, 2.0}) d.Add(Gradient(t, CV_16U), t);
  BracketReadOptions read;
  read.times_path = d.TimesPath();
  try {
    TimeBracketMerges(d.files, read);
    FAIL() << "a 16-bit bracket was timed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(d.files[0]), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("8-bit"), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot
