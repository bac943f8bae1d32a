#include "util/rotation.h"

#include <gtest/gtest.h>

#include <random>

namespace brdfshot {
namespace {

TEST(Rotation, YawPitchRollFollowTheirDocumentedSenses) {
  const Rotation yaw = Rotation::FromYawPitchRoll(90, 0, 0);
  const Vec3 z = yaw(Vec3(0, 0, 1));
  EXPECT_NEAR(z.x, 1, 1e-12);  // +Z towards +X
  const Vec3 y = Rotation::FromYawPitchRoll(0, 90, 0)(Vec3(0, 1, 0));
  EXPECT_NEAR(y.z, 1, 1e-12);  // +Y towards +Z
  const Vec3 x = Rotation::FromYawPitchRoll(0, 0, 90)(Vec3(1, 0, 0));
  EXPECT_NEAR(x.y, 1, 1e-12);  // +X towards +Y
  const Rotation r = Rotation::FromYawPitchRoll(31, -12, 7);
  EXPECT_LT(r.OrthonormalityError(), 1e-14);
  EXPECT_LT((r * r.Inverse()).Angle(), 1e-7);
}

// Angles → matrix → angles over random rotations, and the matrix rebuilt from
// the recovered angles; at pitch ±90° (gimbal lock) only the matrix must agree.
TEST(Rotation, ToYawPitchRollInvertsFromYawPitchRoll) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-179.9, 179.9), pitch(-89.9, 89.9);
  for (int i = 0; i < 1000; ++i) {
    const double y = angle(rng), p = pitch(rng), r = angle(rng);
    const std::array<double, 3> back = Rotation::FromYawPitchRoll(y, p, r).ToYawPitchRoll();
    EXPECT_NEAR(back[0], y, 1e-8);
    EXPECT_NEAR(back[1], p, 1e-8);
    EXPECT_NEAR(back[2], r, 1e-8);
  }
  for (const double p : {90.0, -90.0}) {
    const Rotation R = Rotation::FromYawPitchRoll(40, p, 15);
    const std::array<double, 3> a = R.ToYawPitchRoll();
    EXPECT_NEAR(a[1], p, 1e-6);
    EXPECT_EQ(a[2], 0.0);
    EXPECT_LT((Rotation::FromYawPitchRoll(a[0], a[1], a[2]) * R.Inverse()).Angle(), 1e-6) << p;
  }
}

}  // namespace
}  // namespace brdfshot
