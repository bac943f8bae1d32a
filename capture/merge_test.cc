#include "capture/merge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <exiv2/exiv2.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <random>
#include <unistd.h>

#include "capture/clipping.h"
#include "capture/exposure.h"
#include "capture/merge_quality.h"
#include "capture/raw.h"
#include "capture/response.h"
#include "capture/synthetic_bracket.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {
fs::path TempDir() {
  const fs::path d = fs::temp_directory_path() / ("brdfshot_capture_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}
ResponseCurve Linear8() {
  ResponseCurve r;
  r.levels = 256;
  return r;
}
}  // namespace

TEST(Exposure, ParsesFractionsDecimalsAndRejectsGarbage) {
  EXPECT_DOUBLE_EQ(ParseExposureTime("1/250", "t"), 1.0 / 250);
  EXPECT_DOUBLE_EQ(ParseExposureTime(" 0.5 ", "t"), 0.5);
  EXPECT_DOUBLE_EQ(ParseExposureTime("2s", "t"), 2.0);
  EXPECT_THROW(ParseExposureTime("fast", "t"), Error);
  EXPECT_THROW(ParseExposureTime("1/0", "t"), Error);
  EXPECT_THROW(ParseExposureTime("-3", "t"), Error);
  const fs::path f = TempDir() / "times.txt";
  std::ofstream(f) << "# bracket\n1/4\n\n1/2\n1\n";
  EXPECT_EQ(ReadTimesFile(f.string()), (std::vector<double>{0.25, 0.5, 1.0}));
  try {
    ReadTimesFile(f.string(), 4);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("times.txt"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("3 exposure times for 4 frames"), std::string::npos);
  }
}

TEST(Exposure, ReadsExifThatExiv2Wrote) {
  const fs::path f = TempDir() / "exif.jpg";
  cv::imwrite(f.string(), cv::Mat(8, 8, CV_8UC3, cv::Scalar(10, 20, 30)));
  {
    auto img = Exiv2::ImageFactory::open(f.string());
    Exiv2::ExifData exif;
    exif["Exif.Photo.ExposureTime"] = Exiv2::URational(1, 60);
    exif["Exif.Photo.FNumber"] = Exiv2::URational(4, 1);
    exif["Exif.Photo.ISOSpeedRatings"] = uint16_t(200);
    exif["Exif.Image.Orientation"] = uint16_t(6);
    exif["Exif.Image.Make"] = "TestCam";
    img->setExifData(exif);
    img->writeMetadata();
  }
  const ExifInfo e = ReadExif(f.string());
  EXPECT_DOUBLE_EQ(e.exposure_time, 1.0 / 60);
  EXPECT_DOUBLE_EQ(e.f_number, 4.0);
  EXPECT_DOUBLE_EQ(e.iso, 200.0);
  EXPECT_EQ(e.orientation, 6);
  EXPECT_EQ(e.camera, "TestCam");
  EXPECT_DOUBLE_EQ(e.RelativeExposure(), (1.0 / 60) * 2.0 / 16.0);
  EXPECT_THROW(ReadExif((TempDir() / "missing.jpg").string()), Error);
}

TEST(Exposure, WriteExifRoundTripsThroughReadExif) {
  // Bracket times as a synthetic capture writes them: powers of two around an
  // arbitrary middle, plus a long one; exact when 1/n or n/1, else to 1 µs.
  const fs::path f = TempDir() / "written.jpg";
  for (const double t : {1.0 / 1024, 1.0 / 60, 0.0123456, 2.0, 8.0}) {
    cv::imwrite(f.string(), cv::Mat(8, 8, CV_8UC3, cv::Scalar(10, 20, 30)));
    ExifInfo in;
    in.exposure_time = t;
    in.f_number = 5.6;
    in.iso = 400;
    in.focal_35mm = 49.6;  // EXIF holds whole mm
    in.camera = "brdfshot synthetic";
    WriteExif(f.string(), in);
    const ExifInfo out = ReadExif(f.string());
    EXPECT_NEAR(out.exposure_time, t, t < 1 && std::abs(1 / t - std::round(1 / t)) > 1e-9 ? 5e-7 : 1e-12 * t) << t;
    EXPECT_NEAR(out.f_number, 5.6, 1e-6);
    EXPECT_EQ(out.iso, 400);
    EXPECT_EQ(out.focal_35mm, 50);
    EXPECT_EQ(out.camera, "brdfshot synthetic");
  }
  try {
    WriteExif((TempDir() / "missing.jpg").string(), ExifInfo{});
    FAIL() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.jpg"), std::string::npos) << e.what();
  }
}

TEST(Merge, SingleLinearFrameIsCodeOverTimeAndFlagsOnlyClipping) {
  // A DiLiGenT-like 16-bit linear image: dark, mid, clipped pixels.
  cv::Mat f(1, 3, CV_16UC3);
  f.at<cv::Vec3w>(0, 0) = {100, 200, 300};
  f.at<cv::Vec3w>(0, 1) = {30000, 20000, 10000};
  f.at<cv::Vec3w>(0, 2) = {65535, 65535, 40000};
  const MergeResult m = MergeBracket({f}, {0.5}, ResponseCurve::Linear16());
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(m.radiance.at<cv::Vec3f>(0, x)[c], f.at<cv::Vec3w>(0, x)[c] / 65535.0 / 0.5, 1e-6) << x << c;
  EXPECT_EQ(m.mask.at<uint8_t>(0, 0), 0);  // dark but measured: no other frame to prefer
  EXPECT_EQ(m.mask.at<uint8_t>(0, 1), 0);
  EXPECT_EQ(m.mask.at<uint8_t>(0, 2), 255);  // clipped
  // One 8-bit frame has no response to recover from: refused.
  EXPECT_THROW(MergeBracket({cv::Mat(1, 3, CV_8UC3, cv::Scalar::all(9))}, {1.0}, ResponseCurve()), Error);
}

TEST(Merge, ClippedAndNearBlackCodesGetZeroWeight) {
  // Pixel 0: clipped in the long frame → only the short frame counts.
  // Pixel 1: near-black in the short frame → only the long frame counts.
  cv::Mat shortf(1, 2, CV_8UC3), longf(1, 2, CV_8UC3);
  shortf.at<cv::Vec3b>(0, 0) = {100, 100, 100};
  longf.at<cv::Vec3b>(0, 0) = {255, 255, 255};
  shortf.at<cv::Vec3b>(0, 1) = {3, 3, 3};
  longf.at<cv::Vec3b>(0, 1) = {60, 60, 60};
  const MergeResult m = MergeBracket({shortf, longf}, {1.0, 4.0}, Linear8());
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(m.radiance.at<cv::Vec3f>(0, 0)[c], 100.0f / 255);
    EXPECT_FLOAT_EQ(m.radiance.at<cv::Vec3f>(0, 1)[c], 60.0f / 255 / 4);
  }
  EXPECT_EQ(m.mask.at<uint8_t>(0, 0), 0);
  // Clipped in every frame: flagged, and the shortest frame's bound returned.
  shortf.at<cv::Vec3b>(0, 0) = {255, 255, 255};
  const MergeResult all = MergeBracket({shortf, longf}, {1.0, 4.0}, Linear8());
  EXPECT_EQ(all.mask.at<uint8_t>(0, 0), 255);
  EXPECT_FLOAT_EQ(all.radiance.at<cv::Vec3f>(0, 0)[0], 1.0f);
  EXPECT_DOUBLE_EQ(all.unreliable_fraction, 0.5);
}

TEST(Merge, ChannelLoweredNextToAClippedHighlightIsNotMeasured) {
  // What JPEG's chroma subsampling does to a white highlight clipped in the
  // long frame between green leaves: the long frame's blue decodes to 200,
  // a code that looks valid. Weighted by t², it would win and put the blue
  // 2.5× too low; the short frame alone measures that pixel, all channels,
  // and so its neighbour within reach. Farther away the long frame counts.
  cv::Mat shortf(1, 8, CV_8UC3, cv::Scalar::all(40)), longf(1, 8, CV_8UC3, cv::Scalar::all(160));
  shortf.at<cv::Vec3b>(0, 2) = {120, 120, 120};
  longf.at<cv::Vec3b>(0, 2) = {255, 255, 200};
  longf.at<cv::Vec3b>(0, 3) = {160, 160, 150};  // chroma-smeared neighbour
  MergeOptions jpeg;
  jpeg.clip_reach = kJpegClipReach;
  const MergeResult m = MergeBracket({shortf, longf}, {1.0, 4.0}, Linear8(), jpeg);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(m.radiance.at<cv::Vec3f>(0, 2)[c], 120.0f / 255) << c;
  EXPECT_FLOAT_EQ(m.radiance.at<cv::Vec3f>(0, 3)[2], 40.0f / 255);
  // x = 6 is 4 px from the highlight: both frames, 40/255 and 160/255/4 agree.
  EXPECT_FLOAT_EQ(m.radiance.at<cv::Vec3f>(0, 6)[2], 40.0f / 255);
  EXPECT_EQ(m.mask.at<uint8_t>(0, 2), 0);
  // Per channel (the default, for lossless frames) the long frame's 200 is
  // believed and wins: the blue the JPEG rule exists for.
  const MergeResult per_channel = MergeBracket({shortf, longf}, {1.0, 4.0}, Linear8());
  EXPECT_LT(per_channel.radiance.at<cv::Vec3f>(0, 2)[2], 0.5f * 120 / 255);
  // Clipped in every frame: its neighbours within reach are measured by no
  // frame either — flagged, with the shortest frame's value as their bound.
  shortf.at<cv::Vec3b>(0, 2) = {255, 255, 255};
  const MergeResult all = MergeBracket({shortf, longf}, {1.0, 4.0}, Linear8(), jpeg);
  EXPECT_EQ(all.mask.at<uint8_t>(0, 4), 255);
  EXPECT_FLOAT_EQ(all.radiance.at<cv::Vec3f>(0, 4)[0], 40.0f / 255);
  EXPECT_EQ(all.mask.at<uint8_t>(0, 5), 0);
  // 16-bit (linear, RAW-like) frames keep per-channel clipping even so: a
  // channel below the clip level there is a measurement.
  cv::Mat s16(1, 8, CV_16UC3, cv::Scalar::all(10000)), l16(1, 8, CV_16UC3, cv::Scalar::all(40000));
  l16.at<cv::Vec3w>(0, 2) = {65535, 65535, 40000};
  const MergeResult w = MergeBracket({s16, l16}, {1.0, 4.0}, ResponseCurve::Linear16(), jpeg);
  EXPECT_NEAR(w.radiance.at<cv::Vec3f>(0, 2)[2], 10000.0 / 65535, 1e-6);
}

TEST(Merge, RejectsMismatchedBrackets) {
  const cv::Mat a(4, 4, CV_8UC3, cv::Scalar::all(9)), b(4, 5, CV_8UC3, cv::Scalar::all(9));
  EXPECT_THROW(MergeBracket({a}, {1.0}, Linear8()), Error);
  EXPECT_THROW(MergeBracket({a, b}, {1.0, 2.0}, Linear8()), Error);
  EXPECT_THROW(MergeBracket({a, a}, {1.0}, Linear8()), Error);
  EXPECT_THROW(MergeBracket({a, a}, {1.0, 0.0}, Linear8()), Error);
}

TEST(Response, RecoversAKnownGammaCurveUpToScale) {
  // Radiance spanning 3 decades through f(x) = x^(1/2.2), 7 frames 1 EV apart.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3, 0);
  cv::Mat E(120, 160, CV_64FC3);
  for (int y = 0; y < E.rows; ++y)
    for (int x = 0; x < E.cols; ++x)
      for (int c = 0; c < 3; ++c) E.at<cv::Vec3d>(y, x)[c] = std::pow(10.0, u(rng));
  std::vector<cv::Mat> frames;
  std::vector<double> times;
  for (int j = 0; j < 7; ++j) {
    const double t = std::pow(2.0, j - 3);
    cv::Mat f(E.size(), CV_8UC3);
    for (int y = 0; y < E.rows; ++y)
      for (int x = 0; x < E.cols; ++x)
        for (int c = 0; c < 3; ++c)
          f.at<cv::Vec3b>(y, x)[c] =
              cv::saturate_cast<uint8_t>(255 * std::pow(std::min(1.0, E.at<cv::Vec3d>(y, x)[c] * t * 4), 1 / 2.2));
    frames.push_back(f);
    times.push_back(t);
  }
  const ResponseCurve r = RecoverResponseDebevec(frames, times);
  for (int c = 0; c < 3; ++c) {
    for (int z = 1; z < 256; ++z) EXPECT_GE(r.g[c][z], r.g[c][z - 1]);
    // Ratio of linear values between two well-exposed codes matches the truth.
    for (int z : {40, 80, 160, 220}) {
      const double want = std::pow(z / 128.0, 2.2);
      EXPECT_NEAR(r.Linear(c, z) / r.Linear(c, 128), want, 0.05 * want) << "code " << z;
    }
  }
}

TEST(Response, MemorialSequenceIsMonotoneAndFramesAgree) {
  const std::string dir = DataPath("real/memorial_debevec");
  if (dir.empty() || !fs::exists(dir + "/shutter_times.txt")) GTEST_SKIP() << "memorial sequence not found";
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  const std::vector<double> times = ReadTimesFile(dir + "/shutter_times.txt", paths.size());
  std::vector<cv::Mat> frames;
  for (const auto& p : paths) {
    cv::Mat bgr = cv::imread(p, cv::IMREAD_COLOR), rgb;
    ASSERT_FALSE(bgr.empty()) << p;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    frames.push_back(rgb);
  }
  const ResponseCurve r = RecoverResponseDebevec(frames, times);
  for (int c = 0; c < 3; ++c)
    for (int z = 1; z < 256; ++z) ASSERT_GE(r.g[c][z], r.g[c][z - 1]);
  // Two neighbouring frames (1 EV apart) must give the same radiance wherever
  // both are well exposed: the median ratio within 5 %.
  const int a = 7, b = 8;
  std::vector<double> ratio;
  for (int y = 0; y < frames[a].rows; y += 2)
    for (int x = 0; x < frames[a].cols; x += 2)
      for (int c = 0; c < 3; ++c) {
        const int za = frames[a].at<cv::Vec3b>(y, x)[c], zb = frames[b].at<cv::Vec3b>(y, x)[c];
        if (za < 30 || za > 220 || zb < 30 || zb > 220) continue;
        ratio.push_back((r.Linear(c, za) / times[a]) / (r.Linear(c, zb) / times[b]));
      }
  ASSERT_GT(ratio.size(), 1000u);
  std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
  EXPECT_NEAR(ratio[ratio.size() / 2], 1.0, 0.05);
}

TEST(Raw, RealRawFileReadsThroughLibrawWithItsLevels) {
  const std::string f = DataPath("real/raw/RAW_KODAK_DC50.KDC");
  if (f.empty() || !fs::exists(f)) GTEST_SKIP() << "RAW sample not found";
  const RawFrame r = ReadRaw(f);
  EXPECT_GT(r.rgb16.cols, 100);
  EXPECT_GT(r.rgb16.rows, 100);
  EXPECT_GT(r.white, r.black);
  double mx = 0;
  cv::minMaxLoc(r.rgb16.reshape(1), nullptr, &mx);
  EXPECT_GT(mx, 0);
  EXPECT_THROW(ReadRaw((TempDir() / "none.kdc").string()), Error);
}

// The reader reuses one LibRaw per thread: reading with a white balance, or a
// file that fails, must not change the next read of the same file.
TEST(Raw, ReadsAreIndependentOfThePreviousRead) {
  const std::string f = DataPath("real/raw/RAW_KODAK_DC50.KDC");
  if (f.empty() || !fs::exists(f)) GTEST_SKIP() << "RAW sample not found";
  const RawFrame first = ReadRaw(f);
  const std::array<double, 3> wb{2.0, 1.0, 1.5};
  const RawFrame balanced = ReadRaw(f, &wb);
  EXPECT_EQ(balanced.wb[0], 2.0);
  EXPECT_GT(cv::norm(balanced.rgb16, first.rgb16, cv::NORM_INF), 0);  // the multipliers did act
  EXPECT_THROW(ReadRaw((TempDir() / "none.kdc").string()), Error);
  const RawFrame again = ReadRaw(f);
  EXPECT_EQ(cv::norm(again.rgb16, first.rgb16, cv::NORM_INF), 0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(again.wb[c], first.wb[c]);
  EXPECT_EQ(again.black, first.black);
  EXPECT_EQ(again.white, first.white);
}

// A minimal uncompressed DNG (little-endian TIFF, one IFD, an RGGB CFA) whose
// header declares `w` × `h` sensor pixels over whatever `data` it holds.
std::string MinimalDng(uint32_t w, uint32_t h, const std::string& data) {
  struct Entry {
    uint16_t tag, type;
    uint32_t count, value;  // value or inline bytes, little-endian
  };
  auto bytes4 = [](const char* s) {
    uint32_t v = 0;
    std::memcpy(&v, s, 4);
    return v;
  };
  const uint32_t data_at = 8, ifd_at = data_at + static_cast<uint32_t>((data.size() + 1) / 2 * 2);
  const std::vector<Entry> entries = {{254, 4, 1, 0},
                                      {256, 4, 1, w},
                                      {257, 4, 1, h},
                                      {258, 3, 1, 16},
                                      {259, 3, 1, 1},
                                      {262, 3, 1, 32803},          // uncompressed CFA
                                      {271, 2, 4, bytes4("Abc")},  // Make
                                      {273, 4, 1, data_at},
                                      {277, 3, 1, 1},
                                      {278, 4, 1, h},
                                      {279, 4, 1, static_cast<uint32_t>(data.size())},
                                      {33421, 3, 2, 2u | (2u << 16)},     // CFARepeatPatternDim 2×2
                                      {33422, 1, 4, bytes4("\0\1\1\2")},  // CFAPattern RGGB
                                      {50706, 1, 4, bytes4("\1\4\0\0")},  // DNGVersion 1.4
                                      {50708, 2, 4, bytes4("Abc")}};      // UniqueCameraModel
  std::string out("II*\0", 4);
  auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  put(&ifd_at, 4);
  out += data;
  out.resize(ifd_at, '\0');
  const uint16_t n = static_cast<uint16_t>(entries.size());
  put(&n, 2);
  for (const Entry& e : entries) put(&e, sizeof e);
  const uint32_t next = 0;
  put(&next, 4);
  return out;
}

// A header that declares far more sensor than the file can hold is refused
// before LibRaw allocates and decodes it (fuzz_raw: a 418-byte file decoded
// as 95 × 63679 pixels of garbage, 10 s under ASan).
TEST(Raw, HeaderDeclaringMoreSensorThanTheFileHoldsIsRefused) {
  static_assert(sizeof(uint16_t) * 2 + sizeof(uint32_t) * 2 == 12, "TIFF entries are 12 bytes");
  // The same construction with its pixels present reads: the refusal below
  // is about the size, not about a file LibRaw cannot parse.
  std::string pixels(64 * 64 * 2, '\0');
  for (size_t i = 0; i < pixels.size() / 2; ++i) {
    const uint16_t v = static_cast<uint16_t>(100 + (i * 37) % 4096);
    std::memcpy(&pixels[2 * i], &v, 2);
  }
  const fs::path ok = TempDir() / "ok.dng";
  std::ofstream(ok, std::ios::binary) << MinimalDng(64, 64, pixels);
  const RawFrame r = ReadRaw(ok.string());
  EXPECT_EQ(r.rgb16.cols, 64);
  EXPECT_EQ(r.rgb16.rows, 64);
  const fs::path f = TempDir() / "huge.dng";
  std::ofstream(f, std::ios::binary) << MinimalDng(10000, 10000, std::string(64, '\0'));
  try {
    ReadRaw(f.string());
    FAIL() << "a 10000x10000 sensor in a few hundred bytes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("declares a 10000x10000 sensor but holds"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos);
  }
}

}  // namespace brdfshot

namespace brdfshot {

// A high-ISO JPEG bracket exposed for its bright half leaves the dark half
// to a few noisy codes per channel: merged channel by channel it is full of
// isolated saturated hues. With the colour pooled where the estimates are
// noisy, the speckle is gone — below 1 % and no more than OpenCV's — while
// every pixel measured well is exactly as merged, and the pooled pixels keep
// their brightness (the sum over channels).
TEST(Merge, NoisyShadowsTakeTheirColourFromTheirNeighbours) {
  cv::Mat scene(240, 320, CV_32FC3);
  for (int y = 0; y < scene.rows; ++y)
    for (int x = 0; x < scene.cols; ++x)
      scene.at<cv::Vec3f>(y, x) =
          x < 160 ? cv::Vec3f(0.004f, 0.003f, 0.0025f) : cv::Vec3f(0.2f + x / 400.0f, 0.3f + y / 600.0f, 0.25f);
  std::vector<double> t = BracketTimes(scene, 7, 1);
  for (double& ti : t) ti /= 2;
  CameraModel camera;
  camera.full_well = 1500, camera.read_noise = 6;
  std::vector<cv::Mat> frames = SimulateBracket(scene, t, camera);
  for (cv::Mat& f : frames) {
    std::vector<uint8_t> bytes;
    cv::imencode(".jpg", f, bytes, {cv::IMWRITE_JPEG_QUALITY, 90});
    f = cv::imdecode(bytes, cv::IMREAD_COLOR);  // channel order does not matter to the merge
  }
  const ResponseCurve response = RecoverResponse(frames, t);
  MergeOptions raw_channels;
  raw_channels.pool_noisy_chroma = false;
  const MergeResult plain = MergeBracket(frames, t, response, raw_channels);
  const MergeResult pooled = MergeBracket(frames, t, response);
  const std::vector<float> tf(t.begin(), t.end());
  cv::Mat cv_response, cv_hdr;
  cv::createCalibrateDebevec()->process(frames, cv_response, tf);
  cv::createMergeDebevec()->process(frames, cv_hdr, tf, cv_response);

  const double before = ChromaSpeckle(plain.radiance), after = ChromaSpeckle(pooled.radiance),
               opencv = ChromaSpeckle(cv_hdr);
  std::printf("chroma speckle: channel by channel %.4f, pooled %.4f, OpenCV %.4f; %.1f %% of pixels pooled\n", before,
              after, opencv, 100 * pooled.chroma_pooled_fraction);
  EXPECT_GT(before, 0.05) << "the scene is a hard one";
  EXPECT_LT(after, 0.01);
  EXPECT_LE(after, opencv);
  EXPECT_GT(pooled.chroma_pooled_fraction, 0.3);
  EXPECT_LT(pooled.chroma_pooled_fraction, 0.7);
  long changed_bright = 0;
  for (int y = 0; y < scene.rows; ++y)
    for (int x = 0; x < scene.cols; ++x) {
      const cv::Vec3f a = plain.radiance.at<cv::Vec3f>(y, x), b = pooled.radiance.at<cv::Vec3f>(y, x);
      if (x >= 200) changed_bright += a != b;  // the bright half, away from the boundary
      ASSERT_NEAR(a[0] + a[1] + a[2], b[0] + b[1] + b[2], 1e-5 * (a[0] + a[1] + a[2])) << x << "," << y;
    }
  EXPECT_EQ(changed_bright, 0);
}

}  // namespace brdfshot
