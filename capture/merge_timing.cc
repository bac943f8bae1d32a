#include "capture/merge_timing.h"

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/photo.hpp>

#include "util/check.h"
#include "util/huge_pages.h"
#include "util/progress.h"
#include "util/stats.h"

namespace brdfshot {
namespace {

struct Samples {
  std::vector<double> read, response, noise, pool, merge, total;
  MergeTiming Medians(const std::string& method) const {
    MergeTiming t;
    t.method = method;
    t.read = Median(read), t.response = Median(response), t.merge = Median(merge), t.total = Median(total);
    if (!noise.empty()) t.noise = Median(noise), t.pool = Median(pool);
    return t;
  }
};

void TimeOurs(const std::vector<std::string>& files, const BracketReadOptions& read, Samples* s) {
  const ScopedMatAllocator huge(HugePageMatAllocator());  // as `brdfshot merge` runs
  const Stopwatch total;
  BracketReadOptions quiet = read;
  quiet.progress = false;
  const Bracket b = ReadBracket(files, quiet);
  s->read.push_back(total.Seconds());
  const MergedBracket m = MergeReadBracket(b, {});
  s->total.push_back(total.Seconds());
  s->response.push_back(m.seconds.response);
  s->merge.push_back(m.seconds.merge);
  s->noise.push_back(m.merge.noise_seconds);
  s->pool.push_back(m.merge.pool_seconds);
}

void TimeOpenCv(const std::vector<std::string>& files, const std::vector<double>& exposure,
                cv::MatAllocator* allocator, Samples* s) {
  const ScopedMatAllocator scoped(allocator);
  const Stopwatch total;
  std::vector<cv::Mat> frames;
  for (const std::string& f : files) {
    frames.push_back(cv::imread(f, cv::IMREAD_COLOR));
    if (frames.back().empty()) throw FileError(f, "cannot decode image");
  }
  s->read.push_back(total.Seconds());
  const std::vector<float> t(exposure.begin(), exposure.end());
  const Stopwatch response_clock;
  cv::Mat response, radiance;
  cv::createCalibrateDebevec()->process(frames, response, t);
  s->response.push_back(response_clock.Seconds());
  const Stopwatch merge_clock;
  cv::createMergeDebevec()->process(frames, radiance, t, response);
  s->merge.push_back(merge_clock.Seconds());
  s->total.push_back(total.Seconds());
}

}  // namespace

BracketTimings TimeBracketMerges(const std::vector<std::string>& files, const BracketReadOptions& read,
                                 const MergeTimingOptions& opt) {
  if (opt.repeats < 1) throw Error("timing a merge needs at least one repeat");
  // The exposures OpenCV is given, and the checks `merge` makes, once and untimed.
  BracketReadOptions quiet = read;
  quiet.progress = false;
  const Bracket b = ReadBracket(files, quiet);
  if (b.frames[0].depth() != CV_8U || b.raw)
    throw FileError(files[0], "timing against OpenCV's Debevec merge needs 8-bit frames (JPEG, PNG, TIFF)");
  CheckBracketMeasured(b);
  Samples ours, opencv, opencv_huge;
  Progress progress("timing merges", 3 * opt.repeats, opt.progress);
  // Alternating, so that a slow spell of the machine falls on all.
  for (int r = 0; r < opt.repeats; ++r) {
    TimeOurs(files, read, &ours);
    progress.Step();
    TimeOpenCv(files, b.exposure, cv::Mat::getStdAllocator(), &opencv);
    progress.Step();
    TimeOpenCv(files, b.exposure, HugePageMatAllocator(), &opencv_huge);
    progress.Step();
  }
  BracketTimings out;
  out.frames = static_cast<int>(files.size());
  out.repeats = opt.repeats;
  out.size = b.frames[0].size();
  out.methods = {ours.Medians("brdfshot"), opencv.Medians("OpenCV Debevec"),
                 opencv_huge.Medians("OpenCV Debevec, huge-page images")};
  return out;
}

std::string MergeTimingTable(const BracketTimings& timings, const std::string& source) {
  BRDFSHOT_CHECK(!timings.methods.empty());
  const MergeTiming* opencv = nullptr;
  for (const MergeTiming& t : timings.methods)
    if (t.method == "OpenCV Debevec") opencv = &t;
  char head[512];
  std::snprintf(head, sizeof head, "%d frames of %dx%d (%s); medians of %d runs per method, alternating\n\n",
                timings.frames, timings.size.width, timings.size.height, source.c_str(), timings.repeats);
  std::string s = head + std::string(
                  "| method | read s | response s | merge s (noise model, colour pooling) | total s | "
                  "× OpenCV's total |\n|---|---|---|---|---|---|\n");
  char buf[256];
  for (const MergeTiming& t : timings.methods) {
    char parts[64] = "", ratio[32] = "—";
    if (t.noise > 0 || t.pool > 0) std::snprintf(parts, sizeof parts, " (%.2f, %.2f)", t.noise, t.pool);
    if (opencv && opencv->total > 0) std::snprintf(ratio, sizeof ratio, "%.3f", t.total / opencv->total);
    std::snprintf(buf, sizeof buf, "| %s | %.2f | %.2f | %.2f%s | %.2f | %s |\n", t.method.c_str(), t.read,
                  t.response, t.merge, parts, t.total, ratio);
    s += buf;
  }
  return s;
}

}  // namespace brdfshot
