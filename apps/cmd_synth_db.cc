// brdfshot synth-db / nbrdf-db: a database as MERL-format .binary files, one
// material at a time (the full basis matrix is never needed for this).
#include <cstdio>
#include <filesystem>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/nbrdf.h"
#include "fit/standin.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

namespace {
struct DbWriteArgs {
  DatabaseArgs db;
  std::string out;
};

bool ParseDbWrite(const char* command, int argc, char** argv, DbWriteArgs* a) {
  po::options_description desc("options");
  // clang-format off
  desc.add_options()("out,o", po::value(&a->out)->required(), "output folder (created)");
  // clang-format on
  a->db.Add(desc);
  if (!ParseOptions(command, "--out DIR [options]", desc, argc, argv)) return false;
  MakeOutputDir(a->out);
  return true;
}

std::string OutPath(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / (name + ".binary")).string();
}
}  // namespace

int SynthDbMain(int argc, char** argv) {
  DbWriteArgs a;
  if (!ParseDbWrite("synth-db", argc, argv, &a)) return 0;
  DatabaseOptions opt = a.db.ToOptions(true);
  opt.kind = "standin";
  std::string folder;
  ResolveDatabaseKind(opt, &folder);
  const auto table = ReadStandinTable(folder + "/materials.tsv");
  std::vector<std::string> names;
  for (const auto& m : table) names.push_back(m.name);
  const std::vector<int> keep = SelectMaterials(names, opt);
  Progress progress("synth-db", keep.size(), true);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < static_cast<int>(keep.size()); ++i) {
    table[keep[i]].ToMerl(opt.grid).Write(OutPath(a.out, names[keep[i]]));
    progress.Step();
  }
  std::printf("wrote %zu stand-in (analytic) materials, grid %dx%dx%d, to %s\n", keep.size(), opt.grid.n_th,
              opt.grid.n_td, opt.grid.n_pd, a.out.c_str());
  return 0;
}

int NbrdfDbMain(int argc, char** argv) {
  DbWriteArgs a;
  if (!ParseDbWrite("nbrdf-db", argc, argv, &a)) return 0;
  DatabaseOptions opt = a.db.ToOptions(true);
  opt.kind = "nbrdf";
  std::string folder;
  ResolveDatabaseKind(opt, &folder);
  const std::vector<std::string> names = ReadLines(folder + "/materials.txt");
  const std::vector<int> keep = SelectMaterials(names, opt);
  Progress progress("nbrdf-db", keep.size(), true);
  for (int k : keep) {
    const NbrdfNetwork net = NbrdfNetwork::Load(folder + "/npy", names[k]);
    NbrdfToMerl(net, opt.grid).Write(OutPath(a.out, names[k]));
    progress.Step();
  }
  std::printf("wrote %zu materials of MERL (NBRDF approximation), grid %dx%dx%d, to %s\n", keep.size(), opt.grid.n_th,
              opt.grid.n_td, opt.grid.n_pd, a.out.c_str());
  return 0;
}

}  // namespace brdfshot
