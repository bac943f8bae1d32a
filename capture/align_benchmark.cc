// Aligning a hand-held bracket at 12 MP (4000 × 3000, five frames 1 EV apart,
// each shot with the camera turned by up to 1.5°): homography (MTB start,
// histogram-matched ECC on a pyramid up to 2000 px) against translation only
// (MTB). Numbers in docs/benchmarks.md; run: build/capture/capture_align_benchmark.
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>

#include "capture/align.h"
#include "capture/synthetic_bracket.h"
#include "capture/test_scenes.h"

namespace brdfshot {
namespace {

struct Bracket12MP {
  std::vector<cv::Mat> frames;
  std::vector<double> times;
};

const Bracket12MP& TheBracket() {
  static const Bracket12MP b = [] {
    const cv::Size size(4000, 3000), wide(4400, 3400);
    const cv::Mat e = TexturedRadiance(wide, 5);
    Bracket12MP out;
    out.times = BracketTimes(e, 5, 1);
    const double f = 3600;
    const double turns[5][3] = {{0.8, -0.5, 1.2}, {-0.4, 0.3, -0.6}, {0, 0, 0}, {0.5, 0.6, 0.4}, {-1.0, -0.7, -1.5}};
    for (int j = 0; j < 5; ++j) {
      const cv::Matx33d H = TurnedCamera(turns[j][0], turns[j][1], turns[j][2], f, size),
                        crop(1, 0, 200, 0, 1, 200, 0, 0, 1);
      cv::Mat radiance;
      cv::warpPerspective(e, radiance, cv::Mat(crop * H.inv()), size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                          cv::BORDER_REFLECT);
      out.frames.push_back(SimulateBracket(radiance, {out.times[j]}, CameraModel{})[0]);
    }
    return out;
  }();
  return b;
}

void BM_AlignHomography12MP(benchmark::State& state) {
  const Bracket12MP& b = TheBracket();
  for (auto _ : state) benchmark::DoNotOptimize(AlignBracket(b.frames, b.times));
}
BENCHMARK(BM_AlignHomography12MP)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_AlignTranslation12MP(benchmark::State& state) {
  const Bracket12MP& b = TheBracket();
  AlignOptions o;
  o.model = AlignModel::kTranslation;
  for (auto _ : state) benchmark::DoNotOptimize(AlignBracket(b.frames, b.times, o));
}
BENCHMARK(BM_AlignTranslation12MP)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace brdfshot

BENCHMARK_MAIN();
