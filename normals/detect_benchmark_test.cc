#include "normals/detect_benchmark.h"

#include <gtest/gtest.h>

#include <cmath>

#include "normals/synthetic_sphere.h"

namespace brdfshot {

// OpenCV's Hough transform, as the benchmark runs it, finds a clean sphere
// within a couple of pixels: the baseline is a fair one.
TEST(DetectBenchmark, HoughAloneFindsACleanSphere) {
  SyntheticSphereScene s;
  s.width = 320, s.height = 240, s.circle = {150, 110, 60}, s.clutter = 0, s.noise = 0.002;
  const Circle h = HoughAlone(RenderSyntheticSphere(s), 20, 120);
  EXPECT_LT(std::hypot(h.cx - 150, h.cy - 110), 2.0);
  EXPECT_LT(std::abs(h.r - 60), 2.0);
}

// Small scenes end to end: a row per size, camera and method; ours finds
// every sphere to a fraction of a pixel.
TEST(DetectBenchmark, RowsForEachSizeCameraAndMethod) {
  DetectBenchmarkOptions o;
  o.sizes = {{320, 240}};
  o.seeds = 2;
  const std::vector<DetectBenchmarkRow> rows = RunDetectBenchmark(o);
  ASSERT_EQ(rows.size(), 4u);
  for (const DetectBenchmarkRow& r : rows) {
    EXPECT_EQ(r.scenes, 2);
    if (r.method != "ours") continue;
    EXPECT_EQ(r.misses, 0);
    EXPECT_LT(r.centre_max, 0.5) << (r.perspective ? "perspective" : "orthographic");
    EXPECT_LT(r.radius_max, 0.5) << (r.perspective ? "perspective" : "orthographic");
  }
  EXPECT_NE(DetectBenchmarkTable(rows).find("| 320x240 | perspective | HoughCircles alone |"), std::string::npos);
}

}  // namespace brdfshot
