#include "calib/radiometric_scale.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "calib/sun_probe.h"
#include "capture/response.h"
#include "util/check.h"

namespace brdfshot {
namespace {

LatLongProbe ConstantProbe(float r, float g, float b, int width = 256) {
  return LatLongProbe(cv::Mat(width / 2, width, CV_32FC3, cv::Scalar(r, g, b)));
}

cv::Mat PhotoWithCard(const cv::Rect& card, const cv::Vec3f& value) {
  cv::Mat photo(60, 80, CV_32FC3, cv::Scalar::all(0.01));
  photo(card).setTo(cv::Scalar(value[0], value[1], value[2]));
  return photo;
}

TEST(Irradiance, ConstantProbeGivesPiTimesRadianceForAnyNormal) {
  // ∫ L cos θ dω over a hemisphere = π L (closed form).
  const LatLongProbe probe = ConstantProbe(2, 1, 0.5);
  for (const Vec3& n : {Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, -2, 0.5)}) {
    const cv::Vec3d e = Irradiance(probe, n);
    EXPECT_NEAR(e[0] / (kPi * 2), 1, 2e-3);
    EXPECT_NEAR(e[1] / (kPi * 1), 1, 2e-3);
    EXPECT_NEAR(e[2] / (kPi * 0.5), 1, 2e-3);
  }
}

TEST(Irradiance, SunFollowsTheCosineLawAndVanishesBehind) {
  const Vec3 sun = Normalize(Vec3(0.3, 0.8, -0.5));
  const LatLongProbe probe = SunProbe(sun, cv::Vec3f(3, 3, 3), 0.5, 512);
  for (double deg : {0.0, 30.0, 60.0, 80.0}) {
    // A normal `deg` away from the sun, in the plane of the sun and +Z.
    const Vec3 side = Normalize(Cross(sun, Cross(Vec3(0, 0, 1), sun)));
    const double a = deg * kPi / 180;
    const Vec3 n = std::cos(a) * sun + std::sin(a) * side;
    // The disc is rasterised on 0.7° texels, so its centroid may sit up to half
    // a texel off the given direction: cos moves by sin a · 0.35°.
    const double centroid = 3 * std::sin(a) * 0.35 * kPi / 180;
    EXPECT_NEAR(Irradiance(probe, n)[1], 3 * std::cos(a), 3e-3 + centroid) << deg << " deg";
  }
  EXPECT_EQ(Irradiance(probe, -sun)[0], 0);
}

TEST(RadiometricScale, RecoversAKnownScalePerChannelFromAGreyCard) {
  // A card of albedo 0.18 facing the camera under a constant probe L has
  // radiance 0.18 L (a/π · πL); the photo shows it × k_c.
  const cv::Vec3d k(40, 55, 70);
  const cv::Vec3f L(2, 1, 0.5);
  const cv::Rect region(10, 20, 15, 12);
  const cv::Vec3f value(0.18 * L[0] * k[0], 0.18 * L[1] * k[1], 0.18 * L[2] * k[2]);
  const RadiometricScale s = ScaleFromReferenceCard(PhotoWithCard(region, value), {region, 0.18, {0, 0, 1}},
                                                    ConstantProbe(L[0], L[1], L[2]), Rotation{});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.scale[c] / k[c], 1, 2e-3) << c;
  EXPECT_EQ(s.pixels, region.area());
  EXPECT_LT(s.spread, 1e-5);
}

TEST(RadiometricScale, TheCardNormalGoesThroughTheCameraToProbeRotation) {
  // Sun along the probe's +X; the card faces the camera (+Z camera). With a
  // yaw that turns camera +Z onto probe +X the card faces the sun; without it
  // the card is edge-on. The scale is the same either way only if the
  // rotation is applied.
  const LatLongProbe probe = SunProbe(Vec3(1, 0, 0), cv::Vec3f(5, 5, 5), 0.5, 512);
  Rotation yaw;
  for (double deg = -180; deg <= 180; deg += 1) {
    const Rotation r = Rotation::FromYawPitchRoll(deg, 0, 0);
    if (Dot(r(Vec3(0, 0, 1)), Vec3(1, 0, 0)) > Dot(yaw(Vec3(0, 0, 1)), Vec3(1, 0, 0))) yaw = r;
  }
  ASSERT_GT(Dot(yaw(Vec3(0, 0, 1)), Vec3(1, 0, 0)), 0.999);
  const cv::Rect region(5, 5, 10, 10);
  const float v = static_cast<float>(0.5 / kPi * 5 * 7);  // albedo 0.5, E = 5, k = 7
  const RadiometricScale s =
      ScaleFromReferenceCard(PhotoWithCard(region, {v, v, v}), {region, 0.5, {0, 0, 1}}, probe, yaw);
  EXPECT_NEAR(s.scale[0], 7, 7 * 3e-3);
  // Tilted card: 60° from the sun in the camera frame's XZ plane → E = 5 cos 60°.
  const RadiometricScale t =
      ScaleFromReferenceCard(PhotoWithCard(region, {v / 2, v / 2, v / 2}),
                             {region, 0.5, {std::sin(kPi / 3), 0, std::cos(kPi / 3)}}, probe, yaw);
  EXPECT_NEAR(t.scale[1], 7, 7 * 5e-3);
}

TEST(RadiometricScale, BadCardsAreNamedErrors) {
  const LatLongProbe probe = SunProbe(Vec3(0, 0, 1), cv::Vec3f(1, 1, 1), 0.5, 256);
  const cv::Rect region(5, 5, 10, 10);
  const cv::Mat photo = PhotoWithCard(region, {0.1f, 0.1f, 0.1f});
  auto message = [&](const ReferenceCard& card, const cv::Mat& img, const Rotation& rot = {}) -> std::string {
    try {
      ScaleFromReferenceCard(img, card, probe, rot);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message({cv::Rect(75, 5, 10, 10)}, photo).find("leaves the 80x60 photo"), std::string::npos);
  EXPECT_NE(message({cv::Rect(5, 5, 0, 10)}, photo).find("is empty"), std::string::npos);
  cv::Mat nan = photo.clone();
  nan(region).setTo(cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_NE(message({region}, nan).find("no finite pixel"), std::string::npos);
  EXPECT_NE(message({region}, cv::Mat(60, 80, CV_32FC3, cv::Scalar::all(0))).find("black"), std::string::npos);
  // Card facing away from the only light: the camera looks along the sun.
  EXPECT_NE(message({region}, photo, Rotation::FromYawPitchRoll(180, 0, 0)).find("no light"), std::string::npos);
  EXPECT_NE(message({region, 0}, photo).find("albedo"), std::string::npos);
}

}  // namespace
}  // namespace brdfshot

namespace brdfshot {
namespace {

nlohmann::json MergeSidecarJson(bool raw, const std::string& camera, const ResponseCurve& response,
                                std::array<double, 3> wb = {1, 1, 1}) {
  nlohmann::json frames = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) frames.push_back({{"file", "f" + std::to_string(k)}, {"wb", wb}});
  return {{"format", "brdfshot-merge-1"},
          {"raw", raw},
          {"camera", camera},
          {"frames", frames},
          {"response", response.ToJson()}};
}

ResponseCurve Gamma(double gamma, std::array<double, 3> gain) {
  ResponseCurve r;
  r.kind = "debevec";
  for (int c = 0; c < 3; ++c)
    for (int z = 0; z < 256; ++z) r.g[c].push_back(gamma * std::log(std::max(z, 1) / 255.0) + std::log(gain[c]));
  return r;
}

TEST(ScaleFromMergeSidecars, RawIsTheRatioOfTheWhiteBalances) {
  const ResponseCurve lin = ResponseCurve::Linear16();
  const RadiometricScale s =
      ScaleFromMergeSidecars(MergeSidecarJson(true, "Kodak DCS", lin, {2.0, 1.0, 1.5}), "p.json",
                             MergeSidecarJson(true, "Kodak DCS", lin, {1.6, 1.0, 2.0}), "q.json");
  EXPECT_DOUBLE_EQ(s.scale[0], 1.25);
  EXPECT_DOUBLE_EQ(s.scale[1], 1.0);
  EXPECT_DOUBLE_EQ(s.scale[2], 0.75);
}

TEST(ScaleFromMergeSidecars, DevelopedFramesGiveTheRatioOfTheResponses) {
  // A shared response (what the Makefile does): exactly 1.
  const ResponseCurve r = Gamma(2.2, {1, 1, 1});
  const RadiometricScale same =
      ScaleFromMergeSidecars(MergeSidecarJson(false, "cam", r), "p.json", MergeSidecarJson(false, "cam", r), "q.json");
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(same.scale[c], 1);
  EXPECT_DOUBLE_EQ(same.spread, 0);
  // Curves recovered separately, normalised differently per channel: their gains.
  const RadiometricScale gains = ScaleFromMergeSidecars(MergeSidecarJson(false, "cam", Gamma(2.2, {2, 1, 0.5})),
                                                        "p.json", MergeSidecarJson(false, "cam", r), "q.json");
  EXPECT_NEAR(gains.scale[0], 2, 1e-9);
  EXPECT_NEAR(gains.scale[1], 1, 1e-9);
  EXPECT_NEAR(gains.scale[2], 0.5, 1e-9);
  EXPECT_LT(gains.spread, 1e-9);
  // Curves of different shape: the spread says so.
  const RadiometricScale shape = ScaleFromMergeSidecars(MergeSidecarJson(false, "cam", Gamma(2.0, {1, 1, 1})), "p.json",
                                                        MergeSidecarJson(false, "cam", r), "q.json");
  EXPECT_GT(shape.spread, 0.1);
}

TEST(ScaleFromMergeSidecars, WhatMetadataCannotRelateIsANamedError) {
  const ResponseCurve r = Gamma(2.2, {1, 1, 1});
  auto message = [](const nlohmann::json& a, const nlohmann::json& b) -> std::string {
    try {
      ScaleFromMergeSidecars(a, "p.json", b, "q.json");
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(MergeSidecarJson(false, "Canon", r), MergeSidecarJson(false, "Nikon", r))
                .find("p.json: is from camera 'Canon'"),
            std::string::npos);
  EXPECT_NE(
      message(MergeSidecarJson(true, "c", ResponseCurve::Linear16()), MergeSidecarJson(false, "c", r)).find("is RAW"),
      std::string::npos);
  EXPECT_NE(
      message({{"format", "brdfshot-calib-1"}}, MergeSidecarJson(false, "c", r)).find("p.json: not a brdfshot merge"),
      std::string::npos);
  nlohmann::json no_frames = MergeSidecarJson(false, "c", r);
  no_frames.erase("frames");
  EXPECT_NE(message(MergeSidecarJson(false, "c", r), no_frames).find("q.json: incomplete merge sidecar"),
            std::string::npos);
}

}  // namespace
}  // namespace brdfshot
