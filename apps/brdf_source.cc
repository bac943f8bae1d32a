#include "apps/brdf_source.h"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "fit/database.h"
#include "fit/photo_fit.h"
#include "fit/nbrdf.h"
#include "fit/standin.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace po = boost::program_options;

void BrdfSourceArgs::Add(po::options_description& d) {
  // clang-format off
  d.add_options()
      ("merl", po::value(&merl), "a MERL .binary file")
      ("standin", po::value(&standin), "a stand-in material by name (e.g. metal-01)")
      ("nbrdf", po::value(&nbrdf), "a MERL material by name, from its neural fit (e.g. chrome)")
      ("weights", po::value(&weights), "fit.json from 'brdfshot fit' (its database is reloaded)");
  // clang-format on
}

MerlBrdf BrdfSourceArgs::Load(const DatabaseArgs& db, std::string* label) const {
  const int given = !merl.empty() + !standin.empty() + !nbrdf.empty() + !weights.empty();
  if (given != 1) throw Error("give exactly one of --merl, --standin, --nbrdf, --weights");
  if (!merl.empty()) {
    *label = merl;
    return MerlBrdf::Read(merl);
  }
  DatabaseOptions opt = db.ToOptions(false);
  if (!weights.empty()) {
    std::string what;
    const MerlBrdf brdf = BrdfOfFit(FitRecord::Read(weights), opt, &what);
    *label = weights + " (" + what + ")";
    return brdf;
  }
  std::string folder;
  if (!standin.empty()) {
    opt.kind = "standin";
    ResolveDatabaseKind(opt, &folder);
    // The data folder's table first, then the repository's demo materials.
    std::vector<std::string> tables = {folder + "/materials.tsv"};
    if (const std::string own = AssetPath("standin/materials.tsv"); !own.empty()) tables.push_back(own);
    for (const std::string& table : tables)
      for (const auto& m : ReadStandinTable(table))
        if (m.name == standin) {
          *label = standin + " (stand-in)";
          return m.ToMerl(opt.grid);
        }
    throw Error("no stand-in material '" + standin + "' in " + tables[0] +
                (tables.size() > 1 ? " nor " + tables[1] : std::string()));
  }
  opt.kind = "nbrdf";
  ResolveDatabaseKind(opt, &folder);
  *label = nbrdf + " (MERL, NBRDF approximation)";
  return NbrdfToMerl(NbrdfNetwork::Load(folder + "/npy", nbrdf), opt.grid);
}

std::string BrdfSourceArgs::ToArgs(const DatabaseArgs& db) const {
  if (!merl.empty()) return "--merl " + std::filesystem::absolute(merl).string();
  std::string args = !standin.empty() ? "--standin " + standin
                     : !nbrdf.empty() ? "--nbrdf " + nbrdf
                                      : "--weights " + std::filesystem::absolute(weights).string();
  if (!db.data.empty()) args += " --data " + std::filesystem::absolute(db.data).string();
  if (!db.merl_dir.empty()) args += " --merl-dir " + std::filesystem::absolute(db.merl_dir).string();
  return args + " --grid " + db.grid;
}

}  // namespace brdfshot
