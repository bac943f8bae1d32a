#include "fit/evaluation_shard.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {
namespace {

constexpr const char* kShardFormat = "brdfshot-eval-shard-3";

// A row's numbers by name: one list for the writer and the reader. A number
// that does not apply is NaN (the BRDF error of a target outside the
// database): JSON's null, read back as NaN.
const std::pair<const char*, double LooRow::*> kRowNumbers[] = {{"lambda", &LooRow::lambda},
                                                                {"predicted", &LooRow::predicted},
                                                                {"held_out", &LooRow::held_out},
                                                                {"relit_mean", &LooRow::relit_mean},
                                                                {"relit_median", &LooRow::relit_median},
                                                                {"brdf", &LooRow::brdf},
                                                                {"insample", &LooRow::insample},
                                                                {"relit_directional", &LooRow::relit_directional},
                                                                {"negative_bins", &LooRow::negative_bins},
                                                                {"prior_sensitivity", &LooRow::prior_sensitivity},
                                                                {"condition_bound", &LooRow::condition_bound}};

nlohmann::json RowJson(const LooRow& r) {
  nlohmann::json j = {
      {"material", r.material}, {"probe", r.probe}, {"method", r.method}, {"chosen_class", r.chosen_class}};
  for (const auto& [key, field] : kRowNumbers)
    j[key] = std::isnan(r.*field) ? nlohmann::json(nullptr) : nlohmann::json(r.*field);
  return j;
}

LooRow RowOf(const nlohmann::json& j) {
  LooRow r;
  r.material = j.at("material");
  r.probe = j.at("probe");
  r.method = j.at("method");
  r.chosen_class = j.at("chosen_class");
  for (const auto& [key, field] : kRowNumbers) {
    const nlohmann::json& v = j.at(key);
    r.*field = v.is_null() ? std::nan("") : v.get<double>();
  }
  return r;
}

// Everything but the rows, the shard's place and the timings: equal for the
// shards of one run.
nlohmann::json RunIdentity(const EvaluationShard& shard) {
  const Evaluation& e = shard.evaluation;
  return {{"format", kShardFormat},
          {"settings", shard.settings},
          {"fixed_lambda", shard.fixed_lambda},
          {"database_label", e.database_label},
          {"targets_label", e.targets_label},
          {"grid", {e.grid.n_th, e.grid.n_td, e.grid.n_pd}},
          {"materials", e.materials},
          {"probes", e.probes},
          {"directional_probes", e.directional_probes},
          {"pixels", e.pixels},
          {"group_kind", e.group_kind},
          {"class_sizes", e.class_sizes},
          {"groups", e.groups},
          {"group_of", e.group_of},
          {"lowest_basis_value", e.lowest_basis_value},
          {"shard_count", e.shard_count}};
}

}  // namespace

nlohmann::json EvaluationShard::ToJson() const {
  const Evaluation& e = evaluation;
  nlohmann::json j = RunIdentity(*this);
  nlohmann::json rows = nlohmann::json::array();
  for (const LooRow& r : e.result.rows) rows.push_back(RowJson(r));
  j["shard_index"] = e.shard_index;
  j["seconds"] = {{"database", e.seconds_database}, {"grams", e.seconds_grams}, {"basis", e.seconds_basis},
                  {"fits", e.seconds_fits},         {"total", e.seconds_total}, {"cluster", e.result.seconds_cluster},
                  {"solve", e.result.seconds_solve}};
  j["rows"] = std::move(rows);
  return j;
}

EvaluationShard EvaluationShard::FromJson(const nlohmann::json& j, const std::string& source) {
  if (!HasFormat(j, kShardFormat))
    throw FileError(source, std::string("is not an evaluation shard (") + kShardFormat + ")");
  try {
    EvaluationShard s;
    s.settings = j.at("settings");
    s.fixed_lambda = j.at("fixed_lambda");
    Evaluation& e = s.evaluation;
    e.database_label = j.at("database_label");
    e.targets_label = j.at("targets_label");
    const std::vector<int> g = j.at("grid");
    if (g.size() != 3) throw FileError(source, "grid must have three sizes");
    e.grid = MerlGrid{g[0], g[1], g[2]};
    e.materials = j.at("materials").get<std::vector<std::string>>();
    e.probes = j.at("probes").get<std::vector<std::string>>();
    e.directional_probes = j.at("directional_probes").get<std::vector<std::string>>();
    e.pixels = j.at("pixels");
    e.group_kind = j.at("group_kind");
    e.class_sizes = j.at("class_sizes");
    e.groups = j.at("groups").get<std::vector<std::string>>();
    e.group_of = j.at("group_of").get<std::map<std::string, int>>();
    e.lowest_basis_value = j.at("lowest_basis_value");
    e.shard_index = j.at("shard_index");
    e.shard_count = j.at("shard_count");
    if (!(e.shard_count >= 1 && e.shard_index >= 0 && e.shard_index < e.shard_count))
      throw FileError(source, "shard " + std::to_string(e.shard_index) + " of " + std::to_string(e.shard_count));
    const nlohmann::json& t = j.at("seconds");
    e.seconds_database = t.at("database"), e.seconds_grams = t.at("grams"), e.seconds_basis = t.at("basis");
    e.seconds_fits = t.at("fits"), e.seconds_total = t.at("total");
    e.result.seconds_cluster = t.at("cluster"), e.result.seconds_solve = t.at("solve");
    for (const nlohmann::json& r : j.at("rows")) {
      e.result.rows.push_back(RowOf(r));
      if (!e.group_of.count(e.result.rows.back().material))
        throw FileError(source, "row of material '" + e.result.rows.back().material + "', which has no group");
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw FileError(source, std::string("incomplete evaluation shard: ") + e.what());
  }
}

void WriteEvaluationShard(const EvaluationShard& shard, const std::string& path) {
  const std::string text = shard.ToJson().dump(1);
  WriteFileAtomic(path, [&](std::ostream& o) { o << text << "\n"; });
}

EvaluationShard ReadEvaluationShard(const std::string& path) {
  return EvaluationShard::FromJson(ReadJsonFile(path), path);
}

EvaluationShard MergeEvaluationShards(const std::vector<EvaluationShard>& shards,
                                      const std::vector<std::string>& sources) {
  BRDFSHOT_CHECK(shards.size() == sources.size());
  if (shards.empty()) throw Error("eval --merge: no shards given");
  const int n = shards[0].evaluation.shard_count;
  const nlohmann::json identity = RunIdentity(shards[0]);
  std::vector<int> seen(n, -1);
  for (size_t i = 0; i < shards.size(); ++i) {
    const Evaluation& e = shards[i].evaluation;
    if (RunIdentity(shards[i]) != identity)
      throw FileError(sources[i], "is a shard of another run than " + sources[0] +
                                      " (database, materials, probes or settings differ)");
    if (seen[e.shard_index] >= 0)
      throw FileError(sources[i],
                      "repeats shard " + std::to_string(e.shard_index) + " of " + sources[seen[e.shard_index]]);
    seen[e.shard_index] = static_cast<int>(i);
  }
  for (int k = 0; k < n; ++k)
    if (seen[k] < 0)
      throw Error("eval --merge: shard " + std::to_string(k) + " of " + std::to_string(n) + " is missing");
  EvaluationShard merged = shards[0];
  Evaluation& m = merged.evaluation;
  m.shard_index = 0, m.shard_count = 1;
  m.result = LooResult{};
  m.seconds_database = m.seconds_grams = m.seconds_basis = m.seconds_fits = m.seconds_total = 0;
  // Rows in a one-process run's order: material by material (in the run's
  // material order), each material's rows as its shard wrote them.
  std::map<std::string, std::vector<const LooRow*>> by_material;
  for (const EvaluationShard& s : shards) {
    const Evaluation& e = s.evaluation;
    for (const LooRow& r : e.result.rows) by_material[r.material].push_back(&r);
    m.seconds_database += e.seconds_database, m.seconds_grams += e.seconds_grams, m.seconds_basis += e.seconds_basis;
    m.seconds_fits += e.seconds_fits, m.seconds_total += e.seconds_total;
    m.result.seconds_cluster += e.result.seconds_cluster, m.result.seconds_solve += e.result.seconds_solve;
  }
  for (const std::string& material : m.materials)
    for (const LooRow* r : by_material[material]) m.result.rows.push_back(*r);
  return merged;
}

}  // namespace brdfshot
