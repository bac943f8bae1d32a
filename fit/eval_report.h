// What `brdfshot eval` writes: the rows as CSV, the tables as markdown, and
// the plots — everything computed from an Evaluation, nothing recomputed.
#pragma once

#include <string>
#include <vector>

#include "fit/evaluation.h"

namespace brdfshot {

// The methods of an evaluation, in table order: the order they first appear
// in, the floor (relit-oracle) last.
std::vector<std::string> EvaluationMethods(const Evaluation& ev);

// Per-method aggregates over the rows.
struct MethodSummary {
  std::string method;
  double relit = 0, relit_directional = -1, brdf = 0, insample = 0;  // medians (-1 / NaN: not scored)
  double fits_with_negative_bins = -1;  // share of fits with any negative sampled bin (-1: not counted)
  double negative_bins = -1;            // share of (bin, channel) pairs below zero, over all fits
};
std::vector<MethodSummary> SummariseMethods(const Evaluation& ev);

// The per-material comparisons the goals are stated in (mean relit error over
// the probes a material was fitted under).
struct DefaultVersusBaselines {
  int materials = 0;
  int beats_lsq = 0, beats_paper = 0;
  int within_5_percent = 0;  // ≤ 1.05 × min(lsq, ours)
  double spearman = 0;       // predicted vs actual relit error of "auto", over all fits
  // The same for auto's held-out error, its prior sensitivity
  // (fit_confidence.h), and the held-out error times the sensitivity: how
  // much ranking each adds.
  double spearman_held_out = 0, spearman_sensitivity = 0, spearman_product = 0;
};
DefaultVersusBaselines CompareDefault(const Evaluation& ev);

// Two photos against one (LooOptions::joint): every "auto-joint" row against
// the two "auto-one" rows of its pair, all scored under the probes neither
// photo was taken under.
struct JointVersusSingle {
  int pairs = 0;
  int beats_both = 0;                         // the joint fit's relit error below both single photos'
  int beats_mean = 0;                         // below the mean of the two
  double median_joint = -1, median_one = -1;  // relit error
  double median_joint_directional = -1, median_one_directional = -1;  // under the suns
  int materials = 0, materials_beating_mean = 0;                      // per material, mean over its pairs
};
JointVersusSingle CompareJoint(const Evaluation& ev);

void WriteEvaluationCsv(const Evaluation& ev, const std::string& path);  // atomic
// `settings`: one line describing how the evaluation was run.
std::string EvaluationMarkdown(const Evaluation& ev, const std::string& settings, double fixed_lambda);
// relit_per_material.png and relit_per_group.png in `dir`; returns their paths.
std::vector<std::string> WriteEvaluationPlots(const Evaluation& ev, const std::string& dir);

// eval.csv, eval.md and the plots in `dir`; returns the markdown and, in
// `written`, every file.
std::string WriteEvaluationReport(const Evaluation& ev, const std::string& settings, double fixed_lambda,
                                  const std::string& dir, std::vector<std::string>* written);

}  // namespace brdfshot
