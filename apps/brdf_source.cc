#include "apps/brdf_source.h"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "fit/database.h"
#include "fit/nbrdf.h"
#include "fit/standin.h"
#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

void BrdfSourceArgs::Add(po::options_description& d) {
  d.add_options()
      ("merl", po::value(&merl), "a MERL .binary file")
      ("standin", po::value(&standin), "a stand-in material by name (e.g. metal-01)")
      ("nbrdf", po::value(&nbrdf), "a MERL material by name, from its neural fit (e.g. chrome)")
      ("weights", po::value(&weights), "fit.json from 'brdfshot fit' (its database is reloaded)");
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
    const nlohmann::json j = ReadJsonFile(weights);
    try {
      opt.kind = j.at("database_kind");
      const auto g = j.at("grid");
      opt.grid = MerlGrid{g.at(0), g.at(1), g.at(2)};
      const auto names = j.at("bases").get<std::vector<std::string>>();
      const auto w = j.at("weights").get<std::vector<std::array<double, 3>>>();
      opt.only = MaterialsOfBases(names);
      const BasisDatabase base = LoadDatabase(opt);
      if (static_cast<size_t>(base.num_bases()) != w.size()) throw FileError(weights, "weights do not match the bases");
      Eigen::MatrixXd W(w.size(), 3);
      for (size_t i = 0; i < w.size(); ++i)
        for (int c = 0; c < 3; ++c) W(i, c) = w[i][c];
      *label = "fit " + weights + " over " + base.label;
      return CombineBases(base, W);
    } catch (const nlohmann::json::exception& e) {
      throw FileError(weights, std::string("not a fit.json: ") + e.what());
    }
  }
  std::string folder;
  if (!standin.empty()) {
    opt.kind = "standin";
    ResolveDatabaseKind(opt, &folder);
    for (const auto& m : ReadStandinTable(folder + "/materials.tsv"))
      if (m.name == standin) {
        *label = standin + " (stand-in)";
        return m.ToMerl(opt.grid);
      }
    throw Error("no stand-in material '" + standin + "'");
  }
  opt.kind = "nbrdf";
  ResolveDatabaseKind(opt, &folder);
  *label = nbrdf + " (MERL, NBRDF approximation)";
  return NbrdfToMerl(NbrdfNetwork::Load(folder + "/npy", nbrdf), opt.grid);
}

std::string BrdfSourceArgs::ToArgs() const {
  if (!standin.empty()) return "--standin " + standin;
  if (!nbrdf.empty()) return "--nbrdf " + nbrdf;
  if (!merl.empty()) return "--merl " + std::filesystem::absolute(merl).string();
  return "--weights " + std::filesystem::absolute(weights).string();
}

}  // namespace brdfshot
