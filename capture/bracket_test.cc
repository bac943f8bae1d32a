#include "capture/bracket.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "capture/clipping.h"
#include "capture/merge_sidecar.h"
#include "capture/test_scenes.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {
namespace fs = std::filesystem;

// A gradient scene seen through a linear 8-bit camera at exposure t.
cv::Mat Shot(double t, cv::Size size = {32, 24}) {
  cv::Mat bgr(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double e = t * (20.0 + 200.0 * x / size.width);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b::all(cv::saturate_cast<uchar>(e));
    }
  return bgr;
}

std::string Message(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Bracket, ReadsFramesAndTimesAndMergesToTheSceneUpToScale) {
  FrameFolder d("brdfshot_bracket_read");
  for (double t : {0.25, 0.5, 1.0}) d.Add(Shot(t), t);
  BracketReadOptions opt;
  opt.times_path = d.TimesPath();
  const Bracket b = ReadBracket(ExpandBracketInputs({d.dir.string()}), opt);
  ASSERT_EQ(b.files.size(), 3u);
  EXPECT_EQ(b.exposure, (std::vector<double>{0.25, 0.5, 1.0}));
  EXPECT_FALSE(b.raw);
  EXPECT_FALSE(b.jpeg);
  EXPECT_EQ(b.records.size(), 3u);
  EXPECT_EQ(b.records[1]["exposure"], 0.5);
  const MergedBracket m = MergeReadBracket(b, BracketMergeOptions{});
  // The scene is linear in x: the merged radiance's ratio between two columns
  // is the scene's (within the 8-bit quantisation of the response recovery).
  const cv::Vec3f left = m.merge.radiance.at<cv::Vec3f>(12, 4), right = m.merge.radiance.at<cv::Vec3f>(12, 28);
  const double want = (20.0 + 200.0 * 28 / 32) / (20.0 + 200.0 * 4 / 32);
  EXPECT_NEAR(right[1] / left[1], want, 0.1 * want);
  EXPECT_EQ(m.sidecar.frames.size(), 3u);
  EXPECT_EQ(m.sidecar.clip_reach, -1);
}

// Where the longest frame clips two channels, its third can be wrong too
// (halation, blooming, JPEG's chroma blocks): there it is lowered from 89 to
// 60. Per-channel clipping (the default for a photo) lets it pull the merged
// blue down; a clip reach given in the options overrides the default, the
// shorter frames measure that pixel, and the sidecar records the reach.
TEST(Bracket, AGivenClipReachKeepsAFramesThirdChannelOutNearItsClippedOnes) {
  FrameFolder d("brdfshot_bracket_clip_reach");
  for (double t : {0.25, 0.5, 1.0}) {
    cv::Mat bgr = Shot(t);
    if (t == 1.0) bgr(cv::Rect(10, 10, 4, 4)).setTo(cv::Scalar(60, 255, 255));  // BGR: red and green clipped
    d.Add(bgr, t);
  }
  BracketReadOptions read;
  read.times_path = d.TimesPath();
  const Bracket b = ReadBracket(d.files, read);
  BracketMergeOptions per_channel, reach;
  reach.clip_reach = 1;
  const MergedBracket plain = MergeReadBracket(b, per_channel), kept = MergeReadBracket(b, reach);
  EXPECT_EQ(plain.sidecar.clip_reach, -1);
  EXPECT_EQ(kept.sidecar.clip_reach, 1);
  // Blue at x = 11 against x = 28, where nothing is clipped: the scene's ratio.
  const double want = (20.0 + 200.0 * 11 / 32) / (20.0 + 200.0 * 28 / 32);
  auto ratio = [](const MergedBracket& m) {
    return m.merge.radiance.at<cv::Vec3f>(12, 11)[2] / m.merge.radiance.at<cv::Vec3f>(12, 28)[2];
  };
  EXPECT_NEAR(ratio(kept), want, 0.05 * want);
  EXPECT_LT(ratio(plain), 0.95 * want) << "per channel, the lowered blue pulls the merge down";
  EXPECT_LT(std::abs(ratio(kept) - want), 0.5 * std::abs(ratio(plain) - want)) << ratio(kept) << " " << ratio(plain);
}

// The outputs read back as written: the EXR is the merged radiance, the
// sidecar names the outputs and the frames, the mask is the merge's. A half
// float that cannot hold the radiance is refused before anything is written.
TEST(Bracket, OutputsReadBackAndHalfFloatOverflowIsRefusedFirst) {
  FrameFolder d("brdfshot_bracket_outputs");
  for (double t : {0.25, 0.5, 1.0}) d.Add(Shot(t), t);
  BracketReadOptions opt;
  opt.times_path = d.TimesPath();
  MergedBracket m = MergeReadBracket(ReadBracket(ExpandBracketInputs({d.dir.string()}), opt), BracketMergeOptions{});
  MergeOutputs out;
  out.image = (d.dir / "merged.exr").string();
  out.mask = (d.dir / "merged_mask.png").string();
  out.sidecar = (d.dir / "merged.json").string();
  out.response_json = (d.dir / "response.json").string();
  out.response_plot = (d.dir / "response.png").string();
  out.command = "brdfshot merge test";
  WriteMergeOutputs(m, out);
  EXPECT_EQ(cv::norm(ReadHdrImage(out.image), m.merge.radiance, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(cv::imread(out.mask, cv::IMREAD_GRAYSCALE), m.merge.mask, cv::NORM_INF), 0);
  const MergeSidecar side = MergeSidecar::Read(out.sidecar);
  EXPECT_EQ(side.output, out.image);
  EXPECT_EQ(side.mask, out.mask);
  EXPECT_EQ(side.response_plot, out.response_plot);
  EXPECT_EQ(side.command, out.command);
  EXPECT_EQ(side.frames.size(), 3u);
  EXPECT_TRUE(fs::exists(out.response_plot));
  EXPECT_EQ(ResponseCurve::FromJson(ReadJsonFile(out.response_json), out.response_json).ToJson(), m.response.ToJson());

  m.merge.radiance.at<cv::Vec3f>(0, 0)[0] = 70000;
  MergeOutputs half = out;
  half.half = true;
  half.image = (d.dir / "half.exr").string();
  half.sidecar = (d.dir / "half.json").string();
  EXPECT_NE(Message([&] { WriteMergeOutputs(m, half); }).find("--half: the merged radiance reaches 70000"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(half.image));
  EXPECT_FALSE(fs::exists(half.sidecar));
}

TEST(Bracket, RefusalsNameTheFrame) {
  FrameFolder d("brdfshot_bracket_refuse");
  d.Add(Shot(0.5), 0.5);
  d.Add(Shot(1.0, {16, 24}), 1.0);
  BracketReadOptions opt;
  opt.times_path = d.TimesPath();
  EXPECT_NE(Message([&] { ReadBracket(d.files, opt); }).find(d.files[1] + ": is 16x24, " + d.files[0] + " is 32x24"),
            std::string::npos);
  EXPECT_NE(Message([&] { ReadBracket({(d.dir / "missing.png").string()}, opt); }).find("missing.png: cannot decode"),
            std::string::npos);
  EXPECT_NE(Message([&] { ExpandBracketInputs({(d.dir / "missing.png").string()}); }).find("missing.png: no such file"),
            std::string::npos);
  // One 8-bit frame cannot give a response.
  const Bracket one = ReadBracket({d.files[0]}, BracketReadOptions{});
  EXPECT_NE(Message([&] { MergeReadBracket(one, BracketMergeOptions{}); }).find("is a single 8-bit frame"),
            std::string::npos);
}

TEST(Bracket, ABracketThatSawNothingIsRefusedInThePhotographersTerms) {
  FrameFolder d("brdfshot_bracket_nothing");
  d.Add(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(255)), 0.5);
  d.Add(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(255)), 1.0);
  BracketReadOptions opt;
  opt.times_path = d.TimesPath();
  const std::string white = Message([&] { CheckBracketMeasured(ReadBracket(d.files, opt)); });
  EXPECT_NE(white.find(d.files[0] + ": is saturated everywhere, and it is the shortest exposure"), std::string::npos)
      << white;
  FrameFolder k("brdfshot_bracket_black");
  k.Add(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(0)), 0.5);
  k.Add(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(1)), 1.0);
  opt.times_path = k.TimesPath();
  const std::string black = Message([&] { CheckBracketMeasured(ReadBracket(k.files, opt)); });
  EXPECT_NE(black.find(k.files[1] + ": is black everywhere, and it is the longest exposure"), std::string::npos)
      << black;
}

TEST(Bracket, ClippingRuleOnlyForJpegProbes) {
  Bracket b;
  b.jpeg = true;
  EXPECT_EQ(ClipReachFor(b, true), kJpegClipReach);
  EXPECT_EQ(ClipReachFor(b, false), -1) << "a sphere's photo keeps its per-channel samples";
  b.jpeg = false;
  EXPECT_EQ(ClipReachFor(b, true), -1) << "lossless frames keep per-channel clipping";
  EXPECT_TRUE(IsRawFile("a/B.NEF"));
  EXPECT_TRUE(IsJpegFile("x.JPEG"));
  EXPECT_FALSE(IsRawFile("x.png"));
}

}  // namespace
}  // namespace brdfshot
