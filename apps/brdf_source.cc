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

void BrdfSourceArgs::Add(po::options_description& d, bool several) {
  // A vector without composing() refuses a second occurrence with the
  // parser's own message; with it, each occurrence adds one.
  const auto value = [several](std::vector<std::string>* v) {
    auto* x = po::value(v);
    return several ? x->composing() : x;
  };
  // clang-format off
  d.add_options()
      ("merl", value(&merl), "a MERL .binary file")
      ("standin", value(&standin), "a stand-in material by name (e.g. metal-01)")
      ("nbrdf", value(&nbrdf), "a MERL material by name, from its neural fit (e.g. chrome)")
      ("weights", value(&weights), "fit.json from 'brdfshot fit' (its database is reloaded)");
  // clang-format on
}

std::vector<BrdfSource> BrdfSourceArgs::Given(const std::vector<std::string>& given) const {
  const std::pair<const char*, const std::vector<std::string>*> kinds[] = {
      {"merl", &merl}, {"standin", &standin}, {"nbrdf", &nbrdf}, {"weights", &weights}};
  size_t next[4] = {};
  std::vector<BrdfSource> out;
  for (const std::string& name : given)
    for (int k = 0; k < 4; ++k)
      if (name == kinds[k].first) {
        BRDFSHOT_CHECK(next[k] < kinds[k].second->size(), "--" << name << " given more often than parsed");
        out.push_back({name, (*kinds[k].second)[next[k]++]});
      }
  BRDFSHOT_CHECK(out.size() == merl.size() + standin.size() + nbrdf.size() + weights.size(),
                 "the sources parsed are not those named on the command line");
  return out;
}

BrdfSource BrdfSourceArgs::One() const {
  const size_t given = merl.size() + standin.size() + nbrdf.size() + weights.size();
  if (given != 1) throw Error("give exactly one of --merl, --standin, --nbrdf, --weights");
  return !merl.empty() ? BrdfSource{"merl", merl[0]}
         : !standin.empty() ? BrdfSource{"standin", standin[0]}
         : !nbrdf.empty()   ? BrdfSource{"nbrdf", nbrdf[0]}
                            : BrdfSource{"weights", weights[0]};
}

MerlBrdf BrdfSourceArgs::Load(const DatabaseArgs& db, std::string* label) const { return Load(One(), db, label); }

MerlBrdf BrdfSourceArgs::Load(const BrdfSource& source, const DatabaseArgs& db, std::string* label) {
  const std::string& v = source.value;
  if (source.option == "merl") {
    *label = v;
    return MerlBrdf::Read(v);
  }
  DatabaseOptions opt = db.ToOptions(false);
  if (source.option == "weights") {
    std::string what;
    const MerlBrdf brdf = BrdfOfFit(FitRecord::Read(v), opt, &what);
    *label = v + " (" + what + ")";
    return brdf;
  }
  std::string folder;
  if (source.option == "standin") {
    opt.kind = "standin";
    ResolveDatabaseKind(opt, &folder);
    // The data folder's table first, then the repository's demo materials.
    std::vector<std::string> tables = {folder + "/materials.tsv"};
    if (const std::string own = AssetPath("standin/materials.tsv"); !own.empty()) tables.push_back(own);
    for (const std::string& table : tables)
      for (const auto& m : ReadStandinTable(table))
        if (m.name == v) {
          *label = v + " (stand-in)";
          return m.ToMerl(opt.grid);
        }
    throw Error("no stand-in material '" + v + "' in " + tables[0] +
                (tables.size() > 1 ? " nor " + tables[1] : std::string()));
  }
  BRDFSHOT_CHECK(source.option == "nbrdf", "unknown BRDF source --" << source.option);
  opt.kind = "nbrdf";
  ResolveDatabaseKind(opt, &folder);
  *label = v + " (MERL, NBRDF approximation)";
  return NbrdfToMerl(NbrdfNetwork::Load(folder + "/npy", v), opt.grid);
}

std::string BrdfSourceArgs::ToArgs(const DatabaseArgs& db) const {
  const BrdfSource s = One();
  if (s.option == "merl") return "--merl " + std::filesystem::absolute(s.value).string();
  std::string args = s.option == "weights" ? "--weights " + std::filesystem::absolute(s.value).string()
                                           : "--" + s.option + " " + s.value;
  if (!db.data.empty()) args += " --data " + std::filesystem::absolute(db.data).string();
  if (!db.merl_dir.empty()) args += " --merl-dir " + std::filesystem::absolute(db.merl_dir).string();
  return args + " --grid " + db.grid;
}

}  // namespace brdfshot
