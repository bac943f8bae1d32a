// One capture's results as a page people read: the photo and the sphere found
// in it, the fit's class and residuals, the reconstruction beside the photo,
// the BRDF relit under other probes (beside the truth when the capture is
// synthetic), and the wall time of each stage. It reads the results folder the
// Makefile writes (samples/Makefile): photo.exr/.json, probe.json,
// sphere.json, fit/, relit/, times.tsv — whatever of them exists.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace brdfshot {

struct CaptureReportOptions {
  std::string results;  // the results folder
  std::string capture;  // the capture folder ("" if unknown): its truth/, when synthetic, is compared against
  std::string title;    // default: the results folder's name
  std::string out;      // the markdown page; default <results>/report.md (pictures in <results>/report/)
};

struct CaptureReport {
  std::string page, pictures;  // where they were written
  // Relit error against the truth per probe (relative RMSE), synthetic captures only.
  std::vector<std::pair<std::string, double>> relit_error;
};

// FileError naming the folder when `results` is not one, or a file that
// cannot be read.
CaptureReport WriteCaptureReport(const CaptureReportOptions& options);

// The last logged time of each (command, output) in a BRDFSHOT_TIME_LOG file
// ("<seconds>\t<command line>" per line), in first-seen order: a stage re-run
// by make replaces its older time. The key is "<command> → <output file name>".
std::vector<std::pair<std::string, double>> StageTimes(const std::string& log_path);

}  // namespace brdfshot
