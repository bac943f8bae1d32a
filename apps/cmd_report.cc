// brdfshot report: one capture's results as a page people read
// (fit/capture_report.h).
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "fit/capture_report.h"

namespace brdfshot {
namespace po = boost::program_options;

int ReportMain(int argc, char** argv) {
  CaptureReportOptions o;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("results,r", po::value(&o.results)->required(), "the capture's results folder (the Makefile's, see samples/Makefile)")
      ("capture", po::value(&o.capture), "the capture folder (its truth/, if synthetic, is compared against)")
      ("title", po::value(&o.title), "report title (default: the results folder's name)")
      ("out,o", po::value(&o.out), "markdown report (default: <results>/report.md; pictures go to <results>/report/)");
  // clang-format on
  if (!ParseOptions("report", "--results DIR [--capture DIR] [options]", desc, argc, argv)) return 0;
  const CaptureReport report = WriteCaptureReport(o);
  const std::filesystem::path r(o.results);
  std::printf("\nBRDF (MERL format): %s\npreviews: %s/, %s/\nreport: %s (pictures in %s/)\n",
              (r / "fit" / "brdf.binary").string().c_str(), (r / "fit").string().c_str(),
              (r / "relit").string().c_str(), report.page.c_str(), report.pictures.c_str());
  if (!report.relit_error.empty()) {
    std::printf("relit error against the truth (relative RMSE):");
    for (size_t k = 0; k < report.relit_error.size(); ++k)
      std::printf("%s %s %.4f", k ? "," : "", report.relit_error[k].first.c_str(), report.relit_error[k].second);
    std::printf("\n");
  }
  return 0;
}

}  // namespace brdfshot
