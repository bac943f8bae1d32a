#include "util/vec3.h"

#include <gtest/gtest.h>

#include <random>

namespace brdfshot {

TEST(Frame, FromZIsOrthonormalEverywhereButTheSouthPole) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n = Normalize(Vec3(g(rng), g(rng), g(rng)));
    const Frame f = Frame::FromZ(n);
    EXPECT_NEAR(Dot(f.x, f.y), 0, 1e-12);
    EXPECT_NEAR(Dot(f.x, f.z), 0, 1e-12);
    EXPECT_NEAR(Length(f.x), 1, 1e-12);
    EXPECT_NEAR(Length(f.y), 1, 1e-12);
    EXPECT_NEAR(Dot(Cross(f.x, f.y), f.z), 1, 1e-12) << "not right-handed";
    const Vec3 v = Normalize(Vec3(g(rng), g(rng), g(rng)));
    const Vec3 back = f.FromLocal(f.ToLocal(v));
    EXPECT_NEAR(Length(back - v), 0, 1e-12);
  }
}

TEST(Frame, FromZXPutsTheViewInTheXZPlane) {
  const Vec3 n = Normalize(Vec3(0.3, -0.2, 0.9));
  const Vec3 v(0, 0, 1);
  const Frame f = Frame::FromZX(n, v);
  const Vec3 local = f.ToLocal(v);
  EXPECT_NEAR(local.y, 0, 1e-12);
  EXPECT_GT(local.x, 0);
  EXPECT_NEAR(local.z, Dot(n, v), 1e-12);
}

TEST(Vec3, ReflectKeepsTheAngleToTheNormal) {
  const Vec3 n = Normalize(Vec3(1, 2, 3));
  const Vec3 v = Normalize(Vec3(-1, 0.5, 2));
  const Vec3 r = Reflect(v, n);
  EXPECT_NEAR(Dot(r, n), Dot(v, n), 1e-12);
  EXPECT_NEAR(Length(r), 1, 1e-12);
  EXPECT_NEAR(Length(Normalize(r + v) - n), 0, 1e-12);
}

}  // namespace brdfshot
