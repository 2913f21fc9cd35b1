#include "results/experiment_report.hpp"

#include <fmt/format.h>

#include "results/paper_report.hpp"  // p_value_text
#include "results/text_format.hpp"

namespace hyfal {
namespace {

using namespace text;

constexpr ComparedMeasure kMeasures[] = {ComparedMeasure::time, ComparedMeasure::nodes, ComparedMeasure::falsified};

const SampleComparison& of(const BaselineComparison& c, ComparedMeasure measure) {
  switch (measure) {
    case ComparedMeasure::time: return c.time;
    case ComparedMeasure::nodes: return c.nodes;
    case ComparedMeasure::falsified: return c.falsified;
  }
  return c.time;
}

}  // namespace

ExperimentVerdicts compare_with_baseline(std::span<const std::vector<TrialRecord>> trials,
                                         std::span<const GroupPlace> places, const std::string& baseline_row) {
  ExperimentVerdicts verdicts;
  verdicts.baseline = baseline_row;
  for (std::size_t i = 0; i < places.size() && i < trials.size(); ++i) {
    if (places[i].row == baseline_row) continue;
    for (std::size_t b = 0; b < places.size() && b < trials.size(); ++b) {
      if (places[b].row != baseline_row || places[b].block != places[i].block || places[b].column != places[i].column)
        continue;
      BaselineComparison c{.group = i, .baseline = b, .time = {}, .nodes = {}, .falsified = {}};
      c.time = compare_samples(censored_sample(trials[i], TrialMeasure::wall_s),
                               censored_sample(trials[b], TrialMeasure::wall_s));
      c.nodes = compare_samples(censored_sample(trials[i], TrialMeasure::nodes),
                                censored_sample(trials[b], TrialMeasure::nodes));
      c.falsified = compare_samples(falsified_indicators(trials[i]), falsified_indicators(trials[b]));
      verdicts.comparisons.push_back(c);
      break;
    }
  }
  return verdicts;
}

std::string_view verdict_word(ComparedMeasure measure, SampleOrder order) {
  switch (order) {
    case SampleOrder::within_noise: return "within noise";
    case SampleOrder::too_few_trials: return "too few trials";
    case SampleOrder::x_smaller:
      return measure == ComparedMeasure::time ? "faster" : measure == ComparedMeasure::nodes ? "fewer" : "lower";
    case SampleOrder::y_smaller:
      return measure == ComparedMeasure::time ? "slower" : measure == ComparedMeasure::nodes ? "more" : "higher";
  }
  return "?";
}

std::string verdict_text(ComparedMeasure measure, const SampleComparison& comparison) {
  const std::string_view word = verdict_word(measure, comparison.order);
  if (comparison.order == SampleOrder::too_few_trials)
    return fmt::format("{} (n = {}, {})", word, comparison.test.n_x, comparison.test.n_y);
  return fmt::format("{} ({})", word, p_value_text(comparison.test.p_value, comparison.test.p_exact));
}

std::string to_markdown(const ExperimentVerdicts& verdicts, std::span<const GroupPlace> places) {
  bool blocks = false;
  for (const GroupPlace& p : places) blocks = blocks || !p.block.empty();
  std::string md = fmt::format("## Verdicts against {}\n\n", markdown_cell(verdicts.baseline));
  std::vector<std::string> header;
  if (blocks) header.emplace_back("block");
  for (const char* name : {"row", "column", "time", "nodes", "falsified rate"}) header.emplace_back(name);
  md += markdown_row(header);
  md += markdown_row(std::vector<std::string>(header.size(), "---"));
  for (const BaselineComparison& c : verdicts.comparisons) {
    const GroupPlace& at = places[c.group];
    std::vector<std::string> line;
    if (blocks) line.push_back(markdown_cell(at.block));
    line.push_back(markdown_cell(at.row));
    line.push_back(markdown_cell(at.column));
    for (const ComparedMeasure m : kMeasures) line.push_back(verdict_text(m, of(c, m)));
    md += markdown_row(line);
  }
  if (verdicts.comparisons.empty()) md += "(no group sits beside a group of the baseline row)\n";
  md += fmt::format(
      "\nEach row against {} in the same column, on the two groups' trials (two-sided, α = {:g}): time and nodes "
      "by Gehan's generalized Wilcoxon test (Gehan 1965), which counts a trial stopped by the time limit or node "
      "cap as at least the value it had (censored); the falsified rate by Fisher's exact test. p = exact p-value "
      "(the permutation distribution, for up to 100 trials together), p ≈ normal approximation beyond. faster / "
      "fewer / lower: significantly below the baseline; slower / more / higher: significantly above; within noise: "
      "not significant; too few trials: a group has fewer than two trials.\n",
      markdown_cell(verdicts.baseline), kSignificanceLevel);
  return md;
}

std::vector<std::string> verdict_csv_header() {
  return {"baseline", "time_verdict", "time_p", "nodes_verdict", "nodes_p", "falsified_verdict", "falsified_p"};
}

std::vector<std::vector<std::string>> verdict_csv_fields(const ExperimentVerdicts& verdicts, std::size_t groups) {
  std::vector<std::vector<std::string>> fields(groups, std::vector<std::string>(verdict_csv_header().size()));
  for (const BaselineComparison& c : verdicts.comparisons) {
    if (c.group >= groups) continue;
    std::vector<std::string>& f = fields[c.group];
    f[0] = verdicts.baseline;
    for (std::size_t k = 0; k < std::size(kMeasures); ++k) {
      const SampleComparison& s = of(c, kMeasures[k]);
      f[1 + 2 * k] = std::string(verdict_word(kMeasures[k], s.order));
      if (s.order != SampleOrder::too_few_trials) f[2 + 2 * k] = csv_number(s.test.p_value);
    }
  }
  return fields;
}

}  // namespace hyfal
