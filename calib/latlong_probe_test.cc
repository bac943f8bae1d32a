#include "calib/latlong_probe.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {

TEST(LatLongProbe, SolidAnglesSumToFourPi) {
  LatLongProbe p(cv::Mat(64, 128, CV_32FC3, cv::Scalar::all(1)));
  double sum = 0;
  for (int r = 0; r < p.height(); ++r) sum += p.width() * p.TexelSolidAngle(r);
  EXPECT_NEAR(sum, 4 * kPi, 1e-12);
}

TEST(LatLongProbe, DirectionPixelRoundTripAndConvention) {
  LatLongProbe p(cv::Mat(64, 128, CV_32FC3, cv::Scalar::all(1)));
  // Map centre looks down -Z, top row is +Y, three quarters across is +X.
  EXPECT_NEAR(p.DirectionAt(64, 32).z, -1, 1e-12);
  EXPECT_NEAR(p.DirectionAt(96, 32).x, 1, 1e-12);
  EXPECT_NEAR(p.DirectionAt(10, 0).y, 1, 1e-12);
  for (double c : {0.3, 17.5, 100.25})
    for (double r : {0.7, 31.0, 60.5}) {
      double c2, r2;
      p.PixelAt(p.DirectionAt(c, r), &c2, &r2);
      EXPECT_NEAR(c, c2, 1e-9);
      EXPECT_NEAR(r, r2, 1e-9);
    }
}

TEST(LatLongProbe, RotatedMovesABrightTexelToTheInverseDirection) {
  // L'(d) = L(R d): a light at d in this frame is at R⁻¹ d in the rotated one.
  cv::Mat img(64, 128, CV_32FC3, cv::Scalar::all(0.1));
  img.at<cv::Vec3f>(20, 37) = cv::Vec3f(100, 100, 100);
  const LatLongProbe p(img);
  const Vec3 d = p.DirectionAt(37.5, 20.5);
  const Rotation R = Rotation::FromYawPitchRoll(50, -15, 10);
  const cv::Mat q = p.Rotated(R).rgb();
  cv::Point peak;
  cv::Mat lum;
  cv::extractChannel(q, lum, 0);
  cv::minMaxLoc(lum, nullptr, nullptr, nullptr, &peak);
  const double deg =
      std::acos(std::min(1.0, Dot(p.DirectionAt(peak.x + 0.5, peak.y + 0.5), R.Inverse()(d)))) * 180 / kPi;
  EXPECT_LT(deg, 2.9);  // within one 2.8° texel
  // And back: rotating by R then R⁻¹ returns a smooth probe to within interpolation error.
  cv::Mat smooth(64, 128, CV_32FC3);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 128; ++c) {
      const Vec3 v = p.DirectionAt(c + 0.5, r + 0.5);
      smooth.at<cv::Vec3f>(r, c) = cv::Vec3f(1 + 0.5f * v.y, 1 + 0.3f * v.x, 1 - 0.2f * v.z);
    }
  const LatLongProbe s(smooth);
  EXPECT_LT(cv::norm(s.Rotated(R).Rotated(R.Inverse()).rgb(), smooth, cv::NORM_INF), 0.02);
}

TEST(PrefilteredProbe, CoarsestLevelIsTheSolidAngleWeightedMean) {
  cv::Mat img(32, 64, CV_32FC3);
  cv::randu(img, 0, 10);
  LatLongProbe p(img);
  double mean[3] = {0, 0, 0};
  for (int r = 0; r < p.height(); ++r)
    for (int c = 0; c < p.width(); ++c)
      for (int k = 0; k < 3; ++k) mean[k] += p.Texel(c, r)[k] * p.TexelSolidAngle(r) / (4 * kPi);
  PrefilteredProbe f(p);
  const cv::Vec3f top = f.LookupLevel(Vec3(0, 0, 1), f.levels() - 1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(top[k], mean[k], 1e-4 * mean[k]);
  // Level 0 at a texel centre returns that texel (the lookup's fast atan2 places
  // it to ~1e-5 rad, 1e-4 of a texel here: values in [0, 10] move by < 1e-2).
  const cv::Vec3f t = f.LookupLevel(p.DirectionAt(5.5, 7.5), 0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(t[k], p.Texel(5, 7)[k], 1e-2);
  // ...and half-way between two texels of a row, their mean.
  const cv::Vec3f h = f.LookupLevel(p.DirectionAt(6.0, 7.5), 0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(h[k], 0.5f * (p.Texel(5, 7)[k] + p.Texel(6, 7)[k]), 1e-2);
}

TEST(LatLongProbe, ResizePreservesRadiantPower) {
  cv::Mat img(64, 128, CV_32FC3);
  cv::randu(img, 0, 5);
  LatLongProbe p(img);
  auto power = [](const LatLongProbe& q) {
    double s = 0;
    for (int r = 0; r < q.height(); ++r)
      for (int c = 0; c < q.width(); ++c) s += q.Texel(c, r)[1] * q.TexelSolidAngle(r);
    return s;
  };
  EXPECT_NEAR(power(p.Resized(32)), power(p), 2e-3 * power(p));
}

class RealProbeTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RealProbeTest, ReadsAndIsAPlausibleHdrProbe) {
  const std::string path = DataPath(GetParam());
  if (path.empty() || !std::filesystem::exists(path)) GTEST_SKIP() << "no data: " << GetParam();
  const LatLongProbe p = LatLongProbe::Read(path);
  EXPECT_EQ(p.width(), 2 * p.height());
  EXPECT_GE(p.width(), 1024);
  double lo, hi;
  cv::minMaxLoc(p.rgb().reshape(1), &lo, &hi);
  EXPECT_GE(lo, 0);
  EXPECT_GT(hi, 1.0) << "an HDR probe should exceed 1 somewhere";
}

INSTANTIATE_TEST_SUITE_P(SharedProbes, RealProbeTest,
                         ::testing::Values("envmaps/city.exr", "envmaps/courtyard.exr", "envmaps/forest.exr",
                                           "envmaps/interior.exr", "envmaps/night.exr", "envmaps/studio.exr",
                                           "envmaps/sunrise.exr", "envmaps/sunset.exr",
                                           "real/probes_polyhaven_cc0/studio_small_09_1k.hdr"));

TEST(LatLongProbe, BadFilesGiveNamedErrors) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  const std::string bad = dir + "/brdfshot_bad_probe.exr";
  { std::ofstream(bad) << "not an exr"; }
  try {
    LatLongProbe::Read(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  std::filesystem::remove(bad);
  EXPECT_THROW(LatLongProbe::Read(dir + "/brdfshot_missing.hdr"), Error);
  EXPECT_THROW(LatLongProbe::Read(dir + "/x.jpg"), Error);
}

}  // namespace brdfshot

namespace brdfshot {

TEST(LatLongProbe, ReadsPfmWrittenByOpenCvInRgbOrder) {
  cv::Mat rgb(16, 32, CV_32FC3);
  cv::randu(rgb, 0, 100);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::string path = std::filesystem::temp_directory_path() / "brdfshot_probe_test.pfm";
  ASSERT_TRUE(cv::imwrite(path, bgr));
  const LatLongProbe p = LatLongProbe::Read(path);
  std::filesystem::remove(path);
  ASSERT_EQ(p.width(), 32);
  for (int r = 0; r < 16; r += 5)
    for (int c = 0; c < 32; c += 7)
      for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(p.Texel(c, r)[k], rgb.at<cv::Vec3f>(r, c)[k]);
}

TEST(PrefilteredProbe, BatchedLookupMatchesTheScalarOne) {
  // The batched path (float, fast log2) against the scalar one (double, libm
  // log2) over random directions and footprints from a texel to a hemisphere.
  cv::Mat img(64, 128, CV_32FC3);
  cv::randu(img, 0, 10);
  const PrefilteredProbe f{LatLongProbe(img)};
  cv::RNG rng(7);
  const int n = 500;
  std::vector<float> dir(3 * n), omega(n), scratch(3 * n), rgb(3 * n);
  std::vector<Vec3> d(n);
  for (int i = 0; i < n; ++i) {
    d[i] = Normalize(Vec3(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1)));
    for (int k = 0; k < 3; ++k) dir[3 * i + k] = static_cast<float>(d[i][k]);
    omega[i] = i % 10 == 0 ? 0.0f : static_cast<float>(std::exp(rng.uniform(std::log(1e-4), std::log(6.0))));
  }
  f.LookupMany(n, dir.data(), omega.data(), scratch.data(), rgb.data());
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      if (omega[i] == 0) {
        EXPECT_EQ(rgb[3 * i + k], 0.0f);
        continue;
      }
      // A 1e-3 error in the level and 1e-6 rad in the angles move a value in
      // [0, 10] by well under 0.02.
      EXPECT_NEAR(rgb[3 * i + k], f.Lookup(d[i], omega[i])[k], 0.02) << i;
    }
}

}  // namespace brdfshot
