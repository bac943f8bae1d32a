// brdfshot merge: a bracketed series (LDR with EXIF or a times file, or RAW) to
// one linear-radiance EXR, a mask of pixels no frame measured well, and a JSON
// sidecar recording exposures, camera, response and the command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "apps/command.h"
#include "capture/merge_sidecar.h"
#include "apps/common_options.h"
#include "capture/exposure.h"
#include "capture/align.h"
#include "capture/clipping.h"
#include "capture/merge.h"
#include "capture/orientation.h"
#include "capture/raw.h"
#include "capture/response.h"
#include "fit/plots.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

std::string LowerExtension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  return e;
}

bool IsJpeg(const std::string& path) {
  const std::string e = LowerExtension(path);
  return e == ".jpg" || e == ".jpeg";
}

bool IsRaw(const std::string& path) {
  const std::string e = LowerExtension(path);
  for (const char* r : {".kdc", ".cr2", ".cr3", ".nef", ".arw", ".dng", ".raf", ".orf", ".rw2", ".pef", ".srw"})
    if (e == r) return true;
  return false;
}

std::vector<std::string> ExpandInputs(const std::vector<std::string>& args) {
  std::vector<std::string> files;
  for (const std::string& a : args) {
    std::error_code ec;
    if (fs::is_directory(a, ec)) {
      std::vector<std::string> in_dir;
      for (const auto& e : fs::directory_iterator(a)) {
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".tif" || ext == ".tiff" || IsRaw(e.path().string()))
          in_dir.push_back(e.path().string());
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

// The recovered curve as people draw it: relative exposure (log) against code,
// one line per channel, over the codes the frames actually contain (a code no
// pixel shows is only extrapolated by the smoothness term, and would stretch
// the axis without telling anything). A kink shows at a glance.
cv::Mat ResponsePlot(const ResponseCurve& r, const std::vector<cv::Mat>& frames) {
  // Which codes occur, from a grid of ~250 000 pixels per frame: the plot
  // needs no more, and a 12 MP bracket would otherwise cost half a merge.
  std::vector<std::array<long, 3>> count(r.levels, {0, 0, 0});
  const int step = std::max(1, static_cast<int>(std::sqrt(frames[0].total() / 250000.0)));
  long counted = 0;
  for (const cv::Mat& f : frames)
    for (int y = 0; y < f.rows; y += step)
      for (int x = 0; x < f.cols; x += step, ++counted)
        for (int c = 0; c < 3; ++c) ++count[f.at<cv::Vec3b>(y, x)[c]][c];
  const long min_count = std::max<long>(10, counted / 100000);
  std::vector<XYSeries> series;
  const char* names[3] = {"R", "G", "B"};
  const cv::Scalar bgr[3] = {{40, 40, 220}, {40, 160, 40}, {220, 80, 40}};
  for (int c = 0; c < 3; ++c) {
    XYSeries s{names[c], {}, {}, bgr[c]};
    for (int z = 1; z + 1 < r.levels; ++z)
      if (count[z][c] >= min_count) s.x.push_back(z), s.y.push_back(r.Linear(c, z));
    series.push_back(s);
  }
  return LogLogPlot(series, "response curve (" + r.kind + "), codes seen in the frames", "pixel code",
                    "relative exposure");
}

}  // namespace

int MergeMain(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::string times_path, response_in, response_out, out = "merged.exr", mask_out, sidecar;
  bool align = false, half = false, probe = false;
  std::string wb_arg, plot_out;
  po::options_description desc("options");
  desc.add_options()
      ("input", po::value(&inputs)->multitoken(), "frames: files or a folder (positional)")
      ("times", po::value(&times_path), "exposure times file, one per frame in input order (overrides EXIF)")
      ("response", po::value(&response_in), "reuse a response curve (JSON) instead of recovering one")
      ("save-response", po::value(&response_out), "write the recovered response curve (JSON)")
      ("align", po::bool_switch(&align), "align hand-held frames by translation (median threshold bitmaps)")
      ("wb", po::value(&wb_arg), "RAW white balance R,G,B multipliers (default: the camera's)")
      ("mask", po::value(&mask_out), "mask PNG of unreliable pixels (default: <out>_mask.png)")
      ("sidecar", po::value(&sidecar), "JSON sidecar (default: <out>.json)")
      ("plot-response", po::value(&plot_out), "PNG plot of the response curve (default: <out>_response.png for 8-bit frames)")
      ("half", po::bool_switch(&half), "write half-float EXR (half the size; values above 65504 saturate)")
      ("probe", po::bool_switch(&probe),
       "the bracket is a light probe: with JPEG frames, a frame does not count near a highlight clipped in two "
       "channels (JPEG lowers the third; a small sun's power comes out far too low otherwise)")
      ("out,o", po::value(&out)->default_value(out), "merged linear radiance (.exr)");
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!ParseOptions("merge", "FRAME... | FOLDER [options]", desc, argc, argv, &pos)) return 0;
  const std::vector<std::string> files = ExpandInputs(inputs);
  if (files.empty()) throw Error("merge: no frames given");
  const std::string stem = (fs::path(out).parent_path() / fs::path(out).stem()).string();
  if (mask_out.empty()) mask_out = stem + "_mask.png";
  if (sidecar.empty()) sidecar = stem + ".json";
  if (plot_out.empty()) plot_out = stem + "_response.png";

  std::array<double, 3> wb{};
  if (!wb_arg.empty()) {
    const std::vector<double> v = ParseNumberList(wb_arg, 3, "--wb", "R,G,B");
    std::copy(v.begin(), v.end(), wb.begin());
  }

  Stopwatch sw;
  Progress progress("reading frames", files.size(), true);
  std::vector<cv::Mat> frames;
  std::vector<double> exposure(files.size(), 0);
  nlohmann::json frames_json = nlohmann::json::array();
  std::string camera;
  double focal_35mm = 0;  // the first frame's that says
  const bool raw = IsRaw(files[0]);
  bool jpeg = false;
  for (size_t j = 0; j < files.size(); ++j) {
    const std::string& f = files[j];
    if (IsRaw(f) != raw) throw FileError(f, "mixes RAW and non-RAW frames in one bracket");
    cv::Mat rgb;
    ExifInfo exif;
    if (raw) {
      const RawFrame r = ReadRaw(f, wb_arg.empty() ? nullptr : &wb);
      rgb = r.rgb16;
      exif.exposure_time = r.exposure_time;
      exif.f_number = r.f_number;
      exif.iso = r.iso;
      exif.camera = r.camera;
      exif.focal_35mm = r.focal_35mm;
      frames_json.push_back({{"file", f}, {"black", r.black}, {"white", r.white}, {"wb", r.wb}});
    } else {
      const cv::Mat bgr = cv::imread(f, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
      if (bgr.empty()) throw FileError(f, "cannot decode image");
      jpeg = jpeg || IsJpeg(f);
      if (bgr.depth() != CV_8U && bgr.depth() != CV_16U) throw FileError(f, "frames must be 8- or 16-bit");
      cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
      try {
        exif = ReadExif(f);
      } catch (const Error&) {
        if (times_path.empty()) throw;  // with --times the metadata is not needed (e.g. PPM frames)
      }
      rgb = ApplyExifOrientation(rgb, exif.orientation);
      frames_json.push_back({{"file", f}, {"orientation", exif.orientation}});
    }
    exposure[j] = exif.RelativeExposure();
    frames_json.back()["exif_exposure"] = exposure[j];
    if (camera.empty()) camera = exif.camera;
    if (!(focal_35mm > 0)) focal_35mm = exif.focal_35mm;
    frames.push_back(rgb);
    progress.Step();
  }
  if (!times_path.empty()) {
    exposure = ReadTimesFile(times_path, files.size());
  } else if (files.size() == 1 && !(exposure[0] > 0)) {
    exposure[0] = 1;  // one linear frame: radiance in its own units (calib's scale relates them to the probe)
  } else {
    for (size_t j = 0; j < files.size(); ++j)
      if (!(exposure[j] > 0))
        throw FileError(files[j], "has no EXIF exposure time: pass --times FILE (one time per frame)");
  }
  for (size_t j = 0; j < files.size(); ++j) {
    frames_json[j]["exposure"] = exposure[j];
    if (frames[j].size() != frames[0].size())
      throw FileError(files[j], "is " + std::to_string(frames[j].cols) + "x" + std::to_string(frames[j].rows) +
                                    ", " + files[0] + " is " + std::to_string(frames[0].cols) + "x" +
                                    std::to_string(frames[0].rows));
  }
  // One frame is enough only when it is linear (16-bit: RAW or a linear PNG/TIFF,
  // e.g. DiLiGenT's); an 8-bit frame needs a bracket to recover its response.
  if (files.size() < 2 && frames[0].depth() == CV_8U && response_in.empty())
    throw FileError(files[0], "is a single 8-bit frame: merge needs a bracket (two or more exposures) "
                              "or --response CURVE.json to linearise it");
  if (align && files.size() > 1) {
    AlignedBracket a = AlignBracket(frames);
    for (size_t j = 0; j < files.size(); ++j) frames_json[j]["shift"] = {a.shifts[j].x, a.shifts[j].y};
    frames = std::move(a.frames);
  }
  // A bracket that saw nothing: every pixel clipped even in the shortest
  // frame, or near-black even in the longest. Said in the photographer's terms.
  {
    size_t shortest = 0, longest = 0;
    for (size_t j = 0; j < files.size(); ++j) {
      if (exposure[j] < exposure[shortest]) shortest = j;
      if (exposure[j] > exposure[longest]) longest = j;
    }
    const double top = frames[0].depth() == CV_8U ? 255 : 65535;
    const cv::Mat short_codes = frames[shortest].reshape(1), long_codes = frames[longest].reshape(1);
    if (cv::countNonZero(short_codes >= 0.98 * top) > 0.999 * short_codes.total())
      throw FileError(files[shortest], "is saturated everywhere, and it is the shortest exposure of the bracket: "
                                       "nothing was measured; shoot shorter exposures");
    if (cv::countNonZero(long_codes <= 0.02 * top) > 0.999 * long_codes.total())
      throw FileError(files[longest], "is black everywhere, and it is the longest exposure of the bracket: "
                                      "nothing was measured; shoot longer exposures");
  }
  // A JPEG light probe: its power sits in a few small, clipped sources, whose
  // other channels JPEG lowers (capture/clipping.h), so there the clipping
  // rule is worth the samples it drops. On a sphere's photo it dropped more
  // than it saved (samples_test's rotated capture: relit error 3.9 % with the
  // rule on the probe only, 5.3 % on both).
  const int clip_reach = jpeg && probe ? kJpegClipReach : -1;
  ResponseCurve response;
  if (!response_in.empty()) {
    response = ResponseCurve::FromJson(ReadJsonFile(response_in), response_in);
  } else if (frames[0].depth() == CV_8U) {
    response = RecoverResponse(frames, exposure, 3, 200000, clip_reach);
  } else {
    response = ResponseCurve::Linear16();
  }
  if (!response_out.empty())
    WriteFileAtomic(response_out, [&](std::ostream& o) { o << response.ToJson().dump(1) << "\n"; });
  MergeOptions merge_options;
  merge_options.clip_reach = clip_reach;
  const MergeResult m = MergeBracket(frames, exposure, response, merge_options);
  double max_radiance = 0;
  cv::minMaxLoc(m.radiance.reshape(1), nullptr, &max_radiance);
  if (half && max_radiance > 65504)
    throw Error("--half: the merged radiance reaches " + std::to_string(max_radiance) +
                ", beyond half float's 65504; drop --half or rescale the times");
  WriteExr(out, m.radiance, half ? ExrPixel::kHalf : ExrPixel::kFloat);
  const bool plotted = frames[0].depth() == CV_8U;
  if (plotted) WritePng(plot_out, ResponsePlot(response, frames));
  WriteFileAtomicByName(mask_out, [&](const std::string& tmp) {
    if (!cv::imwrite(tmp, m.mask)) throw FileError(tmp, "cannot write mask");
  });
  MergeSidecar side;
  side.frames = frames_json;
  side.camera = camera;
  side.focal_35mm = focal_35mm;
  side.response = response;
  side.raw = raw;
  side.aligned = align;
  side.unreliable_fraction = m.unreliable_fraction;
  side.clip_reach = clip_reach;
  side.output = out;
  side.mask = mask_out;
  side.half = half;
  side.response_plot = plotted ? plot_out : "";
  side.command = CommandLine(argc, argv);
  side.Write(sidecar);
  std::printf("merged %zu frames (%dx%d, %s) in %.2f s: %.2f %% of pixels unreliable\nwrote %s, %s, %s\n",
              files.size(), frames[0].cols, frames[0].rows, raw ? "RAW" : response.kind.c_str(), sw.Seconds(),
              100 * m.unreliable_fraction, out.c_str(), mask_out.c_str(), sidecar.c_str());
  return 0;
}

}  // namespace brdfshot
