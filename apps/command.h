// The subcommand table (after COLMAP's): each command parses its own options
// struct with Boost.Program_options, calls the libraries, and writes files.
#pragma once

#include <boost/program_options.hpp>
#include <functional>
#include <string>
#include <vector>

namespace brdfshot {

struct Command {
  const char* name;
  const char* summary;
  std::function<int(int argc, char** argv)> run;
  // Benchmarks and the evaluation: listed apart from the stages a user runs
  // (docs/benchmarks.md).
  bool developer_tool = false;
};

const std::vector<Command>& Commands();

// "brdfshot <command> <args…>" from a subcommand's argc/argv: the provenance
// line sidecars record and the stage-time log keys on.
std::string CommandLine(int argc, char** argv);

// Parses argv against `desc` (plus --help). Returns false after printing help,
// throws brdfshot::Error with the parser's message on a bad option. `given`,
// where asked for: the long names of the options given, in command-line order
// (what pairs the n-th of one repeated option with the n-th of another).
bool ParseOptions(const std::string& command, const std::string& usage,
                  boost::program_options::options_description& desc, int argc, char** argv,
                  boost::program_options::positional_options_description* positional = nullptr,
                  std::vector<std::string>* given = nullptr);

int SynthDbMain(int argc, char** argv);
int SynthCaptureMain(int argc, char** argv);
int ReportMain(int argc, char** argv);
int NbrdfDbMain(int argc, char** argv);
int ClusterMain(int argc, char** argv);
int EvalMain(int argc, char** argv);
int BasisMain(int argc, char** argv);
int BenchMergeMain(int argc, char** argv);
int BenchDetectMain(int argc, char** argv);
int RenderMain(int argc, char** argv);
int FitMain(int argc, char** argv);
int CompareMain(int argc, char** argv);
int ScoreMain(int argc, char** argv);
int BenchBasisMain(int argc, char** argv);
int MergeMain(int argc, char** argv);
int MergeCheckMain(int argc, char** argv);
int NormalsMain(int argc, char** argv);
int CalibMain(int argc, char** argv);
int RemapMain(int argc, char** argv);

}  // namespace brdfshot
