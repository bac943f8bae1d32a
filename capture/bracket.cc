#include "capture/bracket.h"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "capture/align.h"
#include "capture/clipping.h"
#include "capture/exposure.h"
#include "capture/ghosts.h"
#include "capture/orientation.h"
#include "capture/raw.h"
#include "capture/response_plot.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace fs = std::filesystem;

bool IsRawFile(const std::string& path) {
  const std::string e = LowerExtension(path);
  for (const char* r : {".kdc", ".cr2", ".cr3", ".nef", ".arw", ".dng", ".raf", ".orf", ".rw2", ".pef", ".srw"})
    if (e == r) return true;
  return false;
}

bool IsJpegFile(const std::string& path) {
  const std::string e = LowerExtension(path);
  return e == ".jpg" || e == ".jpeg";
}

std::vector<std::string> ExpandBracketInputs(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& a : paths) {
    std::error_code ec;
    if (fs::is_directory(a, ec)) {
      std::vector<std::string> in_dir;
      for (const auto& e : fs::directory_iterator(a)) {
        const std::string p = e.path().string(), ext = LowerExtension(p);
        if (ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".tif" || ext == ".tiff" || IsRawFile(p))
          in_dir.push_back(p);
      }
      std::sort(in_dir.begin(), in_dir.end());
      files.insert(files.end(), in_dir.begin(), in_dir.end());
    } else {
      if (!fs::exists(a, ec)) throw FileError(a, "no such file");
      files.push_back(a);
    }
  }
  return files;
}

namespace {

// One frame as read: RGB codes, EXIF orientation applied, and its record.
struct ReadFrameResult {
  cv::Mat rgb;
  ExifInfo exif;
  nlohmann::json record;
  bool jpeg = false;
};

ReadFrameResult ReadFrame(const std::string& f, const BracketReadOptions& opt) {
  ReadFrameResult r;
  if (IsRawFile(f)) {
    const RawFrame raw = ReadRaw(f, opt.white_balance_given ? &opt.white_balance : nullptr);
    r.rgb = raw.rgb16;
    r.exif.exposure_time = raw.exposure_time;
    r.exif.f_number = raw.f_number;
    r.exif.iso = raw.iso;
    r.exif.camera = raw.camera;
    r.exif.focal_35mm = raw.focal_35mm;
    r.record = {{"file", f}, {"black", raw.black}, {"white", raw.white}, {"wb", raw.wb}};
    return r;
  }
  r.jpeg = IsJpegFile(f);
  const cv::Mat bgr = DecodeImageFile(f, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
  if (bgr.depth() != CV_8U && bgr.depth() != CV_16U) throw FileError(f, "frames must be 8- or 16-bit");
  cv::cvtColor(bgr, r.rgb, cv::COLOR_BGR2RGB);
  try {
    // exiv2 parses XMP with a global parser it initialises lazily without a
    // lock: its reads are serialised (they are a small part of a frame's time).
    static std::mutex exif_mutex;
    const std::lock_guard<std::mutex> lock(exif_mutex);
    r.exif = ReadExif(f);
  } catch (const Error&) {
    if (opt.times_path.empty()) throw;  // with a times file the metadata is not needed (e.g. PPM frames)
  }
  r.rgb = ApplyExifOrientation(r.rgb, r.exif.orientation);
  r.record = {{"file", f}, {"orientation", r.exif.orientation}};
  return r;
}

}  // namespace

Bracket ReadBracket(const std::vector<std::string>& files, const BracketReadOptions& opt) {
  if (files.empty()) throw Error("merge: no frames given");
  Bracket b;
  b.files = files;
  b.exposure.assign(files.size(), 0);
  b.raw = IsRawFile(files[0]);
  for (const std::string& f : files)
    if (IsRawFile(f) != b.raw) throw FileError(f, "mixes RAW and non-RAW frames in one bracket");
  // Decoding is most of a merge's time at 12 MP and each frame decodes on its
  // own: one frame per thread. The first failure in frame order is reported.
  const int n = static_cast<int>(files.size());
  std::vector<ReadFrameResult> read(n);
  std::vector<std::exception_ptr> failed(n);
  Progress progress("reading frames", files.size(), opt.progress);
#pragma omp parallel for schedule(dynamic)
  for (int j = 0; j < n; ++j) {
    try {
      read[j] = ReadFrame(files[j], opt);
    } catch (...) {
      failed[j] = std::current_exception();
    }
    progress.Step();
  }
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  for (int j = 0; j < n; ++j) {
    ReadFrameResult& r = read[j];
    b.jpeg = b.jpeg || r.jpeg;
    b.records.push_back(std::move(r.record));
    b.exposure[j] = r.exif.RelativeExposure();
    b.records.back()["exif_exposure"] = b.exposure[j];
    if (b.camera.empty()) b.camera = r.exif.camera;
    if (!(b.focal_35mm > 0)) b.focal_35mm = r.exif.focal_35mm;
    b.frames.push_back(std::move(r.rgb));
  }
  if (!opt.times_path.empty()) {
    b.exposure = ReadTimesFile(opt.times_path, files.size());
  } else if (files.size() == 1 && !(b.exposure[0] > 0)) {
    b.exposure[0] = 1;  // one linear frame: radiance in its own units (calib's scale relates them to the probe)
  } else {
    for (size_t j = 0; j < files.size(); ++j)
      if (!(b.exposure[j] > 0))
        throw FileError(files[j], "has no EXIF exposure time: pass --times FILE (one time per frame)");
  }
  for (size_t j = 0; j < files.size(); ++j) {
    b.records[j]["exposure"] = b.exposure[j];
    if (b.frames[j].size() != b.frames[0].size())
      throw FileError(files[j], "is " + std::to_string(b.frames[j].cols) + "x" + std::to_string(b.frames[j].rows) +
                                    ", " + files[0] + " is " + std::to_string(b.frames[0].cols) + "x" +
                                    std::to_string(b.frames[0].rows));
  }
  return b;
}

void CheckBracketMeasured(const Bracket& b) {
  size_t shortest = 0, longest = 0;
  for (size_t j = 0; j < b.files.size(); ++j) {
    if (b.exposure[j] < b.exposure[shortest]) shortest = j;
    if (b.exposure[j] > b.exposure[longest]) longest = j;
  }
  const double top = b.frames[0].depth() == CV_8U ? 255 : 65535;
  const cv::Mat short_codes = b.frames[shortest].reshape(1), long_codes = b.frames[longest].reshape(1);
  if (cv::countNonZero(short_codes >= 0.98 * top) > 0.999 * short_codes.total())
    throw FileError(b.files[shortest],
                    "is saturated everywhere, and it is the shortest exposure of the bracket: "
                    "nothing was measured; shoot shorter exposures");
  if (cv::countNonZero(long_codes <= 0.02 * top) > 0.999 * long_codes.total())
    throw FileError(b.files[longest],
                    "is black everywhere, and it is the longest exposure of the bracket: "
                    "nothing was measured; shoot longer exposures");
}

int ClipReachFor(const Bracket& b, bool is_probe) { return b.jpeg && is_probe ? kJpegClipReach : -1; }

MergedBracket MergeReadBracket(Bracket b, const BracketMergeOptions& opt) {
  // One frame is enough only when it is linear (16-bit: RAW or a linear
  // PNG/TIFF); an 8-bit frame needs a bracket to recover its response.
  if (b.files.size() < 2 && b.frames[0].depth() == CV_8U && !opt.response)
    throw FileError(b.files[0],
                    "is a single 8-bit frame: merge needs a bracket (two or more exposures) "
                    "or --response CURVE.json to linearise it");
  MergedBracket out;
  const Stopwatch align_clock;
  if (opt.align && b.files.size() > 1) {
    AlignOptions align;
    align.model = opt.align_model;
    align.frame_names = b.files;
    AlignedBracket a = AlignBracket(b.frames, b.exposure, align);
    for (size_t j = 0; j < b.files.size(); ++j) {
      if (align.model == AlignModel::kTranslation) {
        b.records[j]["shift"] = {a.shifts[j].x, a.shifts[j].y};
      } else {
        const cv::Matx33d& W = a.warps[j];
        b.records[j]["homography_to_reference"] = std::vector<double>(W.val, W.val + 9);
      }
    }
    b.frames = std::move(a.frames);
  }
  out.seconds.align = align_clock.Seconds();
  CheckBracketMeasured(b);
  const int clip_reach = opt.clip_reach >= -1 ? opt.clip_reach : ClipReachFor(b, opt.is_probe);
  const Stopwatch response_clock;
  if (opt.response)
    out.response = *opt.response;
  else if (b.frames[0].depth() == CV_8U)
    out.response = RecoverResponse(b.frames, b.exposure, 3, 200000, clip_reach);
  else
    out.response = ResponseCurve::Linear16();
  out.seconds.response = response_clock.Seconds();
  MergeOptions merge_options;
  merge_options.clip_reach = clip_reach;
  int reference = -1;
  const Stopwatch deghost_clock;
  if (opt.deghost && b.frames.size() > 1) {
    std::vector<int> order(b.frames.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return b.exposure[p] < b.exposure[q]; });
    reference = order[order.size() / 2];  // the middle exposure, as the alignment's
    merge_options.excluded = DetectGhosts(b.frames, b.exposure, out.response, reference,
                                          EstimateNoise(b.frames, b.exposure, out.response, merge_options));
    out.ghosts = GhostUnion(merge_options.excluded);
  }
  out.seconds.deghost = deghost_clock.Seconds();
  const Stopwatch merge_clock;
  out.merge = MergeBracket(b.frames, b.exposure, out.response, merge_options);
  out.seconds.merge = merge_clock.Seconds();
  MergeSidecar& s = out.sidecar;
  s.frames = b.records;
  s.camera = b.camera;
  s.focal_35mm = b.focal_35mm;
  s.response = out.response;
  s.raw = b.raw;
  s.aligned = opt.align;
  s.unreliable_fraction = out.merge.unreliable_fraction;
  s.chroma_pooled_fraction = out.merge.chroma_pooled_fraction;
  s.deghosted = reference >= 0;
  s.reference_frame = reference;
  s.ghost_fraction = out.ghosts.empty() ? 0 : cv::countNonZero(out.ghosts) / static_cast<double>(out.ghosts.total());
  s.clip_reach = clip_reach;
  out.frames = std::move(b.frames);
  return out;
}

MergeSidecar WriteMergeOutputs(const MergedBracket& m, const MergeOutputs& out) {
  double max_radiance = 0;
  cv::minMaxLoc(m.merge.radiance.reshape(1), nullptr, &max_radiance);
  if (out.half && max_radiance > 65504)
    throw Error("--half: the merged radiance reaches " + std::to_string(max_radiance) +
                ", beyond half float's 65504; drop --half or rescale the times");
  if (!out.response_json.empty())
    WriteFileAtomic(out.response_json, [&](std::ostream& o) { o << m.response.ToJson().dump(1) << "\n"; });
  WriteExr(out.image, m.merge.radiance, out.half ? ExrPixel::kHalf : ExrPixel::kFloat);
  const bool plotted = !out.response_plot.empty() && m.frames[0].depth() == CV_8U;
  if (plotted) WritePng(out.response_plot, ResponsePlot(m.response, m.frames));
  WriteFileAtomicByName(out.mask, [&](const std::string& tmp) {
    if (!cv::imwrite(tmp, m.merge.mask)) throw FileError(tmp, "cannot write mask");
  });
  const bool ghosts = !m.ghosts.empty() && !out.ghosts.empty();
  if (ghosts)
    WriteFileAtomicByName(out.ghosts, [&](const std::string& tmp) {
      if (!cv::imwrite(tmp, m.ghosts)) throw FileError(tmp, "cannot write ghost mask");
    });
  MergeSidecar side = m.sidecar;
  side.output = out.image;
  side.mask = out.mask;
  side.half = out.half;
  side.response_plot = plotted ? out.response_plot : "";
  side.ghosts = ghosts ? out.ghosts : "";
  side.command = out.command;
  side.Write(out.sidecar);
  return side;
}

}  // namespace brdfshot
