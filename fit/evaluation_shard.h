// One shard of an evaluation, on disk: what `eval --shard i/n` writes (its
// rows and everything the tables need) and `eval --merge` reads. The shards
// of one run, merged, give the rows — and so the tables — of the same run in
// one process: each material is fitted by one shard only, and nothing in a
// material's fits depends on the others'.
//
// JSON, format "brdfshot-eval-shard-1"; one writer (WriteEvaluationShard),
// one reader (ReadEvaluationShard).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/evaluation.h"

namespace brdfshot {

// `settings` and `fixed_lambda` are what the markdown states about the run.
struct EvaluationShard {
  Evaluation evaluation;
  std::string settings;
  double fixed_lambda = 0.5;

  nlohmann::json ToJson() const;
  // FileError naming `source` for another format or a missing field.
  static EvaluationShard FromJson(const nlohmann::json& j, const std::string& source);
};

void WriteEvaluationShard(const EvaluationShard& shard, const std::string& path);  // atomic
EvaluationShard ReadEvaluationShard(const std::string& path);

// The shards 0 … n−1 of one run (any order), merged: rows in the order one
// process writes them, seconds summed. Error naming the files when a shard is
// missing or repeated, or the shards are of different runs (database,
// materials, probes or settings differ).
EvaluationShard MergeEvaluationShards(const std::vector<EvaluationShard>& shards,
                                      const std::vector<std::string>& sources);

}  // namespace brdfshot
