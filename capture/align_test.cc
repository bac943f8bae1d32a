#include "capture/align.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "capture/synthetic_bracket.h"
#include "capture/test_scenes.h"
#include "util/check.h"

namespace brdfshot {
namespace {

// Where two warps send the pixels of a 9 × 9 grid over the image, apart:
// the RMS and the largest distance.
std::pair<double, double> Disagreement(const cv::Matx33d& A, const cv::Matx33d& B, cv::Size size) {
  double worst = 0, sum = 0;
  int n = 0;
  for (int y = 0; y <= size.height; y += size.height / 8)
    for (int x = 0; x <= size.width; x += size.width / 8, ++n) {
      const cv::Vec3d a = A * cv::Vec3d(x, y, 1), b = B * cv::Vec3d(x, y, 1);
      const double d = std::hypot(a[0] / a[2] - b[0] / b[2], a[1] / a[2] - b[1] / b[2]);
      worst = std::max(worst, d), sum += d * d;
    }
  return {std::sqrt(sum / n), worst};
}

}  // namespace

TEST(Align, TranslationRecoversAKnownShiftAcrossExposures) {
  const cv::Mat e = TexturedRadiance({640, 480});
  const std::vector<double> t = BracketTimes(e, 3, 2);
  std::vector<cv::Mat> f = SimulateBracket(e, t, CameraModel{});
  // The short frame was taken with the camera moved: content 7 px right, 4 up.
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 7, 0, 1, -4);
  cv::warpAffine(f[0], f[0], M, f[0].size(), cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  AlignOptions o;
  o.model = AlignModel::kTranslation;
  o.max_shift_px = 16;
  const AlignedBracket a = AlignBracket(f, t, o);
  EXPECT_EQ(a.reference, 1);
  EXPECT_EQ(a.shifts[0], cv::Point(-7, 4));
  EXPECT_EQ(a.shifts[1], cv::Point(0, 0));
  EXPECT_LE(std::abs(a.shifts[2].x) + std::abs(a.shifts[2].y), 1);
  EXPECT_THROW(AlignBracket({f[0]}, {1.0}, o), Error);
}

// Five frames 1 EV apart, each shot with the camera turned a little (up to
// 1.5° with perspective, the way a hand-held camera moves between shots):
// every frame's homography onto the middle one is recovered within 0.1 px
// RMS over the image (0.2 px at the corners, where a homography
// extrapolates), through exposure changes of up to 2 EV either way.
TEST(Align, HomographyRecoversAHandHeldBracketWithinATenthOfAPixel) {
  const cv::Size size(800, 600);
  const cv::Mat e = TexturedRadiance({size.width + 200, size.height + 200});
  const std::vector<double> t = BracketTimes(e, 5, 1);
  const double f = 900;
  const std::vector<std::array<double, 3>> turns = {
      {0.8, -0.5, 1.2}, {-0.4, 0.3, -0.6}, {0, 0, 0}, {0.5, 0.6, 0.4}, {-1.0, -0.7, -1.5}};
  std::vector<cv::Mat> frames;
  std::vector<cv::Matx33d> truth;                            // reference pixel → frame pixel
  const cv::Matx33d crop = {1, 0, 100, 0, 1, 100, 0, 0, 1};  // the frame's window into the wider scene
  for (size_t j = 0; j < t.size(); ++j) {
    const cv::Matx33d H = TurnedCamera(turns[j][0], turns[j][1], turns[j][2], f, size);
    // Frame pixel p sees scene point crop · H⁻¹ · p; the reference (H = I) sees crop · p.
    cv::Mat radiance;
    cv::warpPerspective(e, radiance, cv::Mat(crop * H.inv()), size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                        cv::BORDER_REFLECT);
    frames.push_back(SimulateBracket(radiance, {t[j]}, CameraModel{})[0]);
    truth.push_back(H);
  }
  const AlignedBracket a = AlignBracket(frames, t);
  EXPECT_EQ(a.reference, 2);
  for (size_t j = 0; j < frames.size(); ++j) {
    const auto [rms, worst] = Disagreement(a.warps[j], truth[j], size);
    std::printf("frame %zu: homography off by %.3f px RMS, %.3f px at most\n", j, rms, worst);
    EXPECT_LT(rms, 0.1) << "frame " << j;
    EXPECT_LT(worst, 0.2) << "frame " << j;
  }
}

// A frame of another scene, with signal where its neighbour has it, is
// refused, naming it and the frame it was compared with.
TEST(Align, AFrameOfAnotherSceneIsRefusedByName) {
  const cv::Mat e = TexturedRadiance({400, 300}), other = TexturedRadiance({400, 300}, 11);
  const std::vector<double> t = {0.5, 1, 1.4};
  std::vector<cv::Mat> f = SimulateBracket(e, t, CameraModel{});
  f[2] = SimulateBracket(other, {1.4}, CameraModel{})[0];
  AlignOptions o;
  o.frame_names = {"a.jpg", "b.jpg", "c.jpg"};
  try {
    AlignBracket(f, t, o);
    ADD_FAILURE() << "a frame of another scene is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("c.jpg"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("b.jpg"), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot
