#include "fit/eval_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "util/plots.h"
#include "util/atomic_file.h"
#include "util/image_io.h"

namespace brdfshot {

namespace {
std::string Format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}
std::string Cell(double v) { return v < 0 || std::isnan(v) ? "—" : Format("%.4f", v); }
std::string Percent(double share) { return share < 0 ? "—" : Format("%.1f %%", 100 * share); }

// method → material → relit error summed over the probes it was fitted under.
std::map<std::string, std::map<std::string, double>> PerMaterial(const Evaluation& ev) {
  std::map<std::string, std::map<std::string, double>> out;
  for (const LooRow& row : ev.result.rows) out[row.method][row.material] += row.relit_mean;
  return out;
}

// Per group: its material count and each method's median relit error (in
// the order of `methods`).
struct GroupSummary {
  int materials = 0;
  std::vector<double> median_relit;
};
std::vector<GroupSummary> SummariseGroups(const Evaluation& ev, const std::vector<std::string>& methods) {
  std::vector<GroupSummary> out(ev.groups.size());
  for (const auto& m : ev.materials) out[ev.group_of.at(m)].materials++;
  for (size_t k = 0; k < out.size(); ++k)
    for (const auto& meth : methods) {
      std::vector<double> v;
      for (const LooRow& row : ev.result.rows)
        if (row.method == meth && ev.group_of.at(row.material) == static_cast<int>(k)) v.push_back(row.relit_mean);
      out[k].median_relit.push_back(Median(v));
    }
  return out;
}
}  // namespace

std::vector<std::string> EvaluationMethods(const Evaluation& ev) {
  std::vector<std::string> out;
  for (const LooRow& row : ev.result.rows)
    if (std::find(out.begin(), out.end(), row.method) == out.end()) out.push_back(row.method);
  // Rows that come after the floor's (the joint fits, made after every single
  // photo of a material) still list before it.
  const auto floor = std::find(out.begin(), out.end(), "relit-oracle");
  if (floor != out.end()) std::rotate(floor, floor + 1, out.end());
  return out;
}

JointVersusSingle CompareJoint(const Evaluation& ev) {
  // material and pair → the rows of its two single photos
  std::map<std::pair<std::string, std::string>, std::vector<const LooRow*>> singles;
  for (const LooRow& row : ev.result.rows) {
    if (row.method != "auto-one") continue;
    const size_t open = row.probe.find(" (");
    if (open == std::string::npos || row.probe.back() != ')') continue;
    singles[{row.material, row.probe.substr(open + 2, row.probe.size() - open - 3)}].push_back(&row);
  }
  JointVersusSingle d;
  std::vector<double> joint, one, joint_dir, one_dir;
  std::map<std::string, std::pair<double, double>> per_material;  // Σ joint, Σ mean of singles
  for (const LooRow& row : ev.result.rows) {
    if (row.method != "auto-joint") continue;
    const auto it = singles.find({row.material, row.probe});
    if (it == singles.end() || it->second.size() != 2) continue;
    const LooRow& a = *it->second[0];
    const LooRow& b = *it->second[1];
    ++d.pairs;
    d.beats_both += row.relit_mean < std::min(a.relit_mean, b.relit_mean);
    d.beats_mean += row.relit_mean < 0.5 * (a.relit_mean + b.relit_mean);
    joint.push_back(row.relit_mean);
    one.push_back(a.relit_mean), one.push_back(b.relit_mean);
    if (row.relit_directional >= 0) {
      joint_dir.push_back(row.relit_directional);
      one_dir.push_back(a.relit_directional), one_dir.push_back(b.relit_directional);
    }
    auto& m = per_material[row.material];
    m.first += row.relit_mean, m.second += 0.5 * (a.relit_mean + b.relit_mean);
  }
  if (!d.pairs) return d;
  d.median_joint = Median(joint), d.median_one = Median(one);
  if (!joint_dir.empty()) d.median_joint_directional = Median(joint_dir), d.median_one_directional = Median(one_dir);
  d.materials = static_cast<int>(per_material.size());
  for (const auto& [name, sums] : per_material) d.materials_beating_mean += sums.first < sums.second;
  return d;
}

std::vector<MethodSummary> SummariseMethods(const Evaluation& ev) {
  std::vector<MethodSummary> out;
  for (const std::string& m : EvaluationMethods(ev)) {
    std::vector<double> relit, directional, brdf, insample;
    double negative = 0;
    int counted = 0, with_negative = 0;
    for (const LooRow& row : ev.result.rows) {
      if (row.method != m) continue;
      relit.push_back(row.relit_mean);
      if (row.relit_directional >= 0) directional.push_back(row.relit_directional);
      brdf.push_back(row.brdf);
      insample.push_back(row.insample);
      if (row.negative_bins >= 0) negative += row.negative_bins, ++counted, with_negative += row.negative_bins > 0;
    }
    MethodSummary s;
    s.method = m;
    s.relit = Median(relit);
    s.relit_directional = directional.empty() ? -1 : Median(directional);
    s.brdf = Median(brdf);
    s.insample = Median(insample);
    if (counted) s.fits_with_negative_bins = double(with_negative) / counted, s.negative_bins = negative / counted;
    out.push_back(s);
  }
  return out;
}

DefaultVersusBaselines CompareDefault(const Evaluation& ev) {
  auto per = PerMaterial(ev);
  DefaultVersusBaselines d;
  d.materials = static_cast<int>(ev.materials.size());
  for (const std::string& m : ev.materials) {
    const double a = per["auto"][m];
    d.beats_lsq += a < per["lsq"][m];
    d.beats_paper += a < per["paper"][m];
    d.within_5_percent += a <= 1.05 * std::min(per["lsq"][m], per["ours"][m]);
  }
  std::vector<double> predicted, held_out, sensitivity, product, actual;
  for (const LooRow& row : ev.result.rows)
    if (row.method == "auto") {
      predicted.push_back(row.predicted);
      held_out.push_back(row.held_out);
      sensitivity.push_back(row.prior_sensitivity);
      product.push_back(row.held_out * row.prior_sensitivity);
      actual.push_back(row.relit_mean);
    }
  d.spearman = SpearmanCorrelation(predicted, actual);
  d.spearman_held_out = SpearmanCorrelation(held_out, actual);
  d.spearman_sensitivity = SpearmanCorrelation(sensitivity, actual);
  d.spearman_product = SpearmanCorrelation(product, actual);
  return d;
}

void WriteEvaluationCsv(const Evaluation& ev, const std::string& path) {
  WriteFileAtomic(path, [&](std::ostream& o) {
    o << "# database: " << ev.database_label << "\n";
    o << "material,group,probe,method,chosen_class,lambda,predicted,held_out,relit_mean,relit_median,"
         "relit_directional,brdf,insample,negative_bins,prior_sensitivity,condition_bound\n";
    for (const LooRow& row : ev.result.rows)
      o << row.material << "," << ev.group_of.at(row.material) << "," << row.probe << "," << row.method << ","
        << row.chosen_class << "," << row.lambda << "," << row.predicted << "," << row.held_out << "," << row.relit_mean
        << "," << row.relit_median << "," << row.relit_directional << "," << row.brdf << "," << row.insample << ","
        << row.negative_bins << "," << row.prior_sensitivity << "," << row.condition_bound << "\n";
  });
}

std::string EvaluationMarkdown(const Evaluation& ev, const std::string& settings, double fixed_lambda) {
  const bool ood = !ev.targets_label.empty();
  const std::vector<std::string> methods = EvaluationMethods(ev);
  std::ostringstream md;
  md << (ood ? "# Out-of-database evaluation — " + ev.targets_label + " fitted with " : "# Leave-one-out evaluation — ")
     << ev.database_label << "\n\n"
     << "Settings: " << settings << ". Probes fitted from and scored under:";
  for (const auto& p : ev.probes) md << " " << p;
  md << "; scored only (directional light):";
  for (const auto& p : ev.directional_probes) md << " " << p;
  if (ev.directional_probes.empty()) md << " none";
  md << ". Each row: fit under probe A, scored relit under the other probes and under the directional ones.\n\n";
  md << "| method | median relit error | median relit error, directional | median BRDF error (cos-weighted) "
        "| median in-sample residual | fits with a negative bin | negative bins |\n|---|---|---|---|---|---|---|\n";
  for (const MethodSummary& s : SummariseMethods(ev))
    md << "| " << s.method << " | " << Cell(s.relit) << " | " << Cell(s.relit_directional) << " | " << Cell(s.brdf)
       << " | " << Cell(s.insample) << " | " << Percent(s.fits_with_negative_bins) << " | "
       << (s.negative_bins < 0 ? "—" : Format("%.3g %%", 100 * s.negative_bins)) << " |\n";
  if (ev.lowest_basis_value < 0)
    md << "\nThe database's own tables go below zero (lowest sampled value " << ev.lowest_basis_value
       << "): non-negative weights cannot guarantee a non-negative BRDF.\n";
  const DefaultVersusBaselines d = CompareDefault(ev);
  const double M = std::max(1, d.materials);
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      "\nPer material (mean relit error over probes): auto beats plain least squares on **%d / %d** (%.0f %%), "
      "the paper as written on **%d / %d** (%.0f %%); within 1.05× the better of least squares and "
      "λ = %g on **%d / %d** (%.0f %%). Spearman rank correlation of auto's predicted and actual relit "
      "error over all fits: **%.3f** (of its held-out error alone: %.3f; of its prior sensitivity: %.3f; of the "
      "held-out error times the sensitivity: %.3f).",
      d.beats_lsq, d.materials, 100 * d.beats_lsq / M, d.beats_paper, d.materials, 100 * d.beats_paper / M,
      fixed_lambda, d.within_5_percent, d.materials, 100 * d.within_5_percent / M, d.spearman, d.spearman_held_out,
      d.spearman_sensitivity, d.spearman_product);
  md << buf;
  const JointVersusSingle joint = CompareJoint(ev);
  if (joint.pairs) {
    std::snprintf(
        buf, sizeof buf,
        "\n\nTwo photos of one material (auto-joint: the photos under probes A and B fitted as one; auto-one: each "
        "photo's own default fit; both scored under the probes neither photo was taken under): median relit error "
        "**%.4f** joint against **%.4f** one photo (under the suns %.4f against %.4f); the joint fit relights better "
        "than both of its photos on **%d / %d** pairs (%.0f %%), better than their mean on %d / %d (%.0f %%), and "
        "per material (mean over its pairs) better than the single photos' mean on **%d / %d**.",
        joint.median_joint, joint.median_one, joint.median_joint_directional, joint.median_one_directional,
        joint.beats_both, joint.pairs, 100.0 * joint.beats_both / joint.pairs, joint.beats_mean, joint.pairs,
        100.0 * joint.beats_mean / joint.pairs, joint.materials_beating_mean, joint.materials);
    md << buf;
  }
  md << "\n\nλ chosen by auto:";
  std::map<double, int> lambda_count;
  for (const LooRow& row : ev.result.rows)
    if (row.method == "auto") lambda_count[row.lambda]++;
  for (const auto& [l, n] : lambda_count) md << " " << l << " (" << n << ")";
  md << "\n\n"
     << (ood ? std::string("Per family of the targets")
             : "Per class of the full-database model (class sizes " + ev.class_sizes + ")")
     << ", median relit error:\n\n| group | materials |";
  for (const auto& m : methods) md << " " << m << " |";
  md << "\n|---|---|";
  for (size_t i = 0; i < methods.size(); ++i) md << "---|";
  md << "\n";
  const std::vector<GroupSummary> groups = SummariseGroups(ev, methods);
  for (size_t k = 0; k < groups.size(); ++k) {
    md << "| " << ev.groups[k] << " | " << groups[k].materials << " |";
    for (double median : groups[k].median_relit) md << " " << Cell(median) << " |";
    md << "\n";
  }
  std::snprintf(
      buf, sizeof buf,
      "\nTime: database %.1f s, Gram matrices %.1f s, basis images %.1f s for %zu scenes, fits %.1f s "
      "(%zu materials × %zu probes, %zu methods; %.1f ms per fit of all methods, thread time). "
      "Total %.1f s.\n",
      ev.seconds_database, ev.seconds_grams, ev.seconds_basis, ev.probes.size() + ev.directional_probes.size(),
      ev.seconds_fits, ev.materials.size(), ev.probes.size(), methods.size(),
      1000 * ev.result.seconds_solve / std::max<size_t>(1, ev.materials.size() * ev.probes.size()), ev.seconds_total);
  md << buf;
  return md.str();
}

std::vector<std::string> WriteEvaluationPlots(const Evaluation& ev, const std::string& dir) {
  const std::vector<std::string> methods = EvaluationMethods(ev);
  auto per = PerMaterial(ev);
  // The floor (the last method) first: the materials are sorted by it, so the
  // gap to it reads directly.
  std::vector<std::string> order = {methods.back()};
  order.insert(order.end(), methods.begin(), methods.end() - 1);
  std::vector<std::vector<double>> series;
  for (const auto& meth : order) {
    std::vector<double> s;
    for (const auto& mat : ev.materials) s.push_back(per[meth][mat] / ev.probes.size());
    series.push_back(s);
  }
  std::vector<std::vector<double>> bars;
  std::vector<std::string> groups;
  const std::vector<GroupSummary> summary = SummariseGroups(ev, methods);
  for (size_t k = 0; k < summary.size(); ++k) {
    bars.push_back(summary[k].median_relit);
    groups.push_back(ev.groups[k] + " (" + std::to_string(summary[k].materials) + ")");
  }
  const std::string per_material = dir + "/relit_per_material.png", per_group = dir + "/relit_per_group.png";
  WritePng(per_material, LinePlotLog(series, order, "relit error per material (mean over probes), " + ev.database_label,
                                     "materials, sorted by " + methods.back() + " error"));
  WritePng(per_group, BarPlot(bars, groups, methods, "Median relit error per group, " + ev.database_label));
  return {per_material, per_group};
}

std::string WriteEvaluationReport(const Evaluation& ev, const std::string& settings, double fixed_lambda,
                                  const std::string& dir, std::vector<std::string>* written) {
  const std::string report = EvaluationMarkdown(ev, settings, fixed_lambda);
  WriteEvaluationCsv(ev, dir + "/eval.csv");
  WriteFileAtomic(dir + "/eval.md", [&](std::ostream& o) { o << report; });
  *written = {dir + "/eval.csv", dir + "/eval.md"};
  for (const std::string& p : WriteEvaluationPlots(ev, dir)) written->push_back(p);
  return report;
}

}  // namespace brdfshot
