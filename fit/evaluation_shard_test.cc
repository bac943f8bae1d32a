#include "fit/evaluation_shard.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fit/eval_report.h"
#include "fit/test_databases.h"
#include "util/check.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

EvaluationOptions SmallRun() {
  EvaluationOptions o;
  for (const char* p : {"forest_256.exr", "studio_256.exr"})
    o.probes.push_back(LatLongProbe::Read(std::string(BRDFSHOT_SOURCE_DIR) + "/samples/assets/envmaps/" + p));
  o.directional = false;
  o.sphere = 16;
  o.quality.theta_samples = 8, o.quality.phi_samples = 12;
  o.count_negative_bins = false;
  return o;
}

std::string Csv(const Evaluation& ev) {
  const fs::path p = fs::temp_directory_path() / "brdfshot_eval_shard_test.csv";
  WriteEvaluationCsv(ev, p.string());
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  fs::remove(p);
  return s.str();
}

// The markdown without its wall-time line (the shards' times are summed).
std::string WithoutTimes(const std::string& md) {
  std::istringstream in(md);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("Time: ", 0) != 0) out += line + "\n";
  return out;
}

}  // namespace

// Three shards of the leave-one-out over the 16 demo stand-ins, written,
// read back and merged in another order, give the one-process run's table
// row for row and its markdown; a missing or foreign shard is refused.
TEST(EvaluationShard, MergedShardsGiveTheOneProcessTables) {
  const DatabaseOptions db = DemoStandins();
  const Evaluation whole = RunEvaluation(db, SmallRun());
  ASSERT_FALSE(whole.result.rows.empty());
  std::vector<EvaluationShard> shards;
  std::vector<std::string> names;
  for (int k : {2, 0, 1}) {
    EvaluationOptions o = SmallRun();
    o.loo.shard_index = k, o.loo.shard_count = 3;
    EvaluationShard s{RunEvaluation(db, o), "settings", 0.5};
    EXPECT_LT(s.evaluation.result.rows.size(), whole.result.rows.size());
    const std::string path = (fs::temp_directory_path() / ("brdfshot_shard_" + std::to_string(k) + ".json")).string();
    WriteEvaluationShard(s, path);
    shards.push_back(ReadEvaluationShard(path));
    names.push_back(path);
    fs::remove(path);
  }
  const EvaluationShard merged = MergeEvaluationShards(shards, names);
  EXPECT_EQ(Csv(merged.evaluation), Csv(whole));
  EXPECT_EQ(WithoutTimes(EvaluationMarkdown(merged.evaluation, "settings", 0.5)),
            WithoutTimes(EvaluationMarkdown(whole, "settings", 0.5)));

  try {
    MergeEvaluationShards({shards[0], shards[1]}, {names[0], names[1]});
    ADD_FAILURE() << "a missing shard is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shard 1 of 3 is missing"), std::string::npos) << e.what();
  }
  EvaluationShard foreign = shards[2];
  foreign.settings = "another λ";
  try {
    MergeEvaluationShards({shards[0], shards[1], foreign}, names);
    ADD_FAILURE() << "a shard of another run is refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(names[2] + ": is a shard of another run"), std::string::npos) << e.what();
  }
}

// A number that does not apply (NaN: the BRDF error of a target outside the
// database, set b) is written as null and read back as NaN, so shards of an
// out-of-database run merge too.
TEST(EvaluationShard, NumbersThatDoNotApplyRoundTripAsNaN) {
  EvaluationShard s;
  s.settings = "settings";
  Evaluation& e = s.evaluation;
  e.materials = {"m"};
  e.group_of = {{"m", 0}};
  LooRow row;
  row.material = "m", row.probe = "p", row.method = "auto", row.relit_mean = 0.25;
  row.brdf = std::nan("");
  e.result.rows = {row};
  const nlohmann::json j = nlohmann::json::parse(s.ToJson().dump());
  EXPECT_TRUE(j.at("rows").at(0).at("brdf").is_null());
  const EvaluationShard back = EvaluationShard::FromJson(j, "shard.json");
  ASSERT_EQ(back.evaluation.result.rows.size(), 1u);
  EXPECT_TRUE(std::isnan(back.evaluation.result.rows[0].brdf));
  EXPECT_EQ(back.evaluation.result.rows[0].relit_mean, 0.25);
  EXPECT_EQ(back.evaluation.result.rows[0].method, "auto");
}

}  // namespace brdfshot
