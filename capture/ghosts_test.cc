#include "capture/ghosts.h"

#include <gtest/gtest.h>

#include "capture/synthetic_bracket.h"

namespace brdfshot {
namespace {

// A static background (a smooth ramp) and a red square that moves 70 px
// between shots.
cv::Mat SceneWithSquareAt(int x0) {
  cv::Mat e(120, 240, CV_32FC3);
  for (int y = 0; y < e.rows; ++y)
    for (int x = 0; x < e.cols; ++x) {
      const float v = 0.05f + 0.1f * x / e.cols + 0.05f * y / e.rows;
      e.at<cv::Vec3f>(y, x) = cv::Vec3f(v, 0.9f * v, 0.8f * v);
    }
  e(cv::Rect(x0, 40, 30, 30)).setTo(cv::Scalar(0.3, 0.1, 0.06));
  return e;
}

// A room (a dim ramp) with a bright window band (rows 30–89) that the middle
// exposure clips, and in the window a bright thing at x0 (30 × 30).
cv::Mat WindowSceneWithThingAt(int x0) {
  cv::Mat e(120, 240, CV_32FC3);
  for (int y = 0; y < e.rows; ++y)
    for (int x = 0; x < e.cols; ++x) {
      const float v = 0.08f + 0.1f * x / e.cols;
      e.at<cv::Vec3f>(y, x) = y >= 30 && y < 90 ? cv::Vec3f(2.5f, 2.4f, 2.3f) : cv::Vec3f(v, 0.9f * v, 0.8f * v);
    }
  e(cv::Rect(x0, 45, 30, 30)).setTo(cv::Scalar(3.5, 1.2, 1.0));
  return e;
}

double RelativeError(const cv::Vec3f& got, const cv::Vec3f& want) { return cv::norm(got - want) / cv::norm(want); }

}  // namespace

// Merged as it is, the bracket shows the square three times, each a blend;
// with the ghosts excluded the square stands where the reference frame saw it
// and the background where the other frames' squares were. The static part
// of the scene is merged exactly as without ghost detection.
TEST(Ghosts, AMovingThingIsTakenFromTheReferenceFrameAlone) {
  const std::vector<double> t = BracketTimes(SceneWithSquareAt(100), 3, 1);
  const int positions[3] = {30, 100, 170};
  std::vector<cv::Mat> frames;
  for (int j = 0; j < 3; ++j) {
    CameraModel camera;  // linear 12-bit frames: the response is known, the test is about motion
    camera.raw_bits = 12;
    camera.seed = 7 + j;
    frames.push_back(SimulateBracket(SceneWithSquareAt(positions[j]), {t[j]}, camera)[0]);
  }
  const ResponseCurve response = ResponseCurve::Linear16();
  const NoiseModel noise = EstimateNoise(frames, t, response, MergeOptions{});
  const std::vector<cv::Mat> ghosts = DetectGhosts(frames, t, response, 1, noise);
  EXPECT_EQ(cv::countNonZero(ghosts[1]), 0) << "the reference has no ghosts of its own";
  MergeOptions deghosted;
  deghosted.excluded = ghosts;
  const MergeResult plain = MergeBracket(frames, t, response), clean = MergeBracket(frames, t, response, deghosted);

  // Truth up to the merge's per-channel scale: the background beside the squares fixes it.
  const cv::Mat truth = SceneWithSquareAt(100);
  cv::Vec3f scale;
  for (int c = 0; c < 3; ++c) scale[c] = truth.at<cv::Vec3f>(100, 215)[c] / clean.radiance.at<cv::Vec3f>(100, 215)[c];
  auto at = [&](const cv::Mat& m, int y, int x) { return m.at<cv::Vec3f>(y, x).mul(scale); };
  // The other frames' squares: background again (within 5 %); blended without detection.
  for (int x : {45, 185}) {
    const double with = RelativeError(at(clean.radiance, 55, x), truth.at<cv::Vec3f>(55, x)),
                 without = RelativeError(at(plain.radiance, 55, x), truth.at<cv::Vec3f>(55, x));
    std::printf("x %d: %.3f without ghost detection, %.3f with\n", x, without, with);
    EXPECT_LT(with, 0.05) << x;
    EXPECT_GT(without, with + 0.03) << x << ": the shortest frame weighs least, the longest most";
  }
  EXPECT_LT(RelativeError(at(clean.radiance, 55, 115), truth.at<cv::Vec3f>(55, 115)), 0.05) << "the square itself";
  // Away from every square, nothing changes.
  const cv::Mat ghost_region = GhostUnion(ghosts);
  long static_changed = 0, static_pixels = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      if (y >= 34 && y < 76) continue;  // the squares' rows, with margin
      ++static_pixels;
      static_changed += plain.radiance.at<cv::Vec3f>(y, x) != clean.radiance.at<cv::Vec3f>(y, x);
      EXPECT_EQ(ghost_region.at<uint8_t>(y, x), 0) << "no false ghost at " << x << "," << y;
    }
  EXPECT_EQ(static_changed, 0) << "of " << static_pixels;
}

// Where the middle frame is clipped (the window), the nearest frame that
// measures stands in for it: the thing is taken from the 1/4-exposure frame
// alone instead of blended with the 1/8 frame's copy 80 px away. The room,
// which the middle frame measures, is merged exactly as without detection.
TEST(Ghosts, WhereTheReferenceIsClippedTheNearestMeasuringFrameStandsIn) {
  const std::vector<double> t = {0.125, 0.25, 1, 2, 4};
  const int positions[5] = {40, 120, 200, 200, 200};
  std::vector<cv::Mat> frames;
  for (int j = 0; j < 5; ++j) {
    CameraModel camera;
    camera.raw_bits = 12;
    camera.seed = 11 + j;
    frames.push_back(SimulateBracket(WindowSceneWithThingAt(positions[j]), {t[j]}, camera)[0]);
  }
  const ResponseCurve response = ResponseCurve::Linear16();
  // The camera's own noise (CameraModel's defaults: full well 20 000 e⁻, read
  // noise 4 e⁻): the things cover a tenth of the window, too much for the
  // estimate from the frames to stay clean, and the test is about where the
  // reference does not measure.
  NoiseModel noise;
  noise.shot = 1 / 20000.0;
  noise.read = (4 / 20000.0) * (4 / 20000.0);
  const std::vector<cv::Mat> ghosts = DetectGhosts(frames, t, response, 2, noise);
  EXPECT_EQ(ghosts[1].at<uint8_t>(60, 55), 0) << "the stand-in keeps its own view";
  EXPECT_EQ(ghosts[0].at<uint8_t>(60, 55), 255) << "the 1/8 frame's window, where the stand-in saw the thing";
  MergeOptions deghosted;
  deghosted.excluded = ghosts;
  const MergeResult plain = MergeBracket(frames, t, response), clean = MergeBracket(frames, t, response, deghosted);
  // Linear 12-bit frames: the merge's radiance is the scene's (no scale to fix).
  const cv::Mat as_frame_1 = WindowSceneWithThingAt(120);
  for (int x : {55, 135}) {  // the 1/8 frame's thing (window behind it in frame 1), frame 1's thing
    const cv::Vec3f want = as_frame_1.at<cv::Vec3f>(60, x);
    const double with = RelativeError(clean.radiance.at<cv::Vec3f>(60, x), want),
                 without = RelativeError(plain.radiance.at<cv::Vec3f>(60, x), want);
    std::printf("x %d: %.3f without ghost detection, %.3f with\n", x, without, with);
    EXPECT_LT(with, 0.03) << x;
    EXPECT_GT(without, with + 0.05) << x;
  }
  // The room: measured by the middle frame, no ghost, merged as without detection.
  long changed = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 240; ++x) {
      if (y >= 26 && y < 94) continue;  // the window, with margin
      changed += plain.radiance.at<cv::Vec3f>(y, x) != clean.radiance.at<cv::Vec3f>(y, x);
    }
  EXPECT_EQ(changed, 0);
}

}  // namespace brdfshot
