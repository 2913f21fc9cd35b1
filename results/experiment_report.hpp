// Verdicts of an experiment's variants (`hyfal run FILE.toml`): in each block and column of the
// experiment's table, every row against the baseline row on wall time and nodes (Gehan's test of
// the censored samples, as the paper tables' orderings) and on the falsified rate (Fisher's
// exact test, compare_samples on falsified_indicators).
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/run/trial_record.hpp"
#include "results/statistics.hpp"
#include "results/table_writer.hpp"

namespace hyfal {

// One group against the baseline row's group of the same block and column. In each comparison x
// is the group's sample and y the baseline's: x_smaller reads "faster" (time), "fewer" (nodes),
// "lower" (falsified rate).
struct BaselineComparison {
  std::size_t group = 0, baseline = 0;  // indices into the experiment's groups
  SampleComparison time, nodes, falsified;
};

struct ExperimentVerdicts {
  std::string baseline;  // the baseline row's label
  // Every group outside the baseline row whose block and column hold a baseline group, in group order.
  std::vector<BaselineComparison> comparisons;
};

// trials[i] the trials of the group at places[i]. Groups of the baseline row are the reference,
// not compared; a group whose block and column have no baseline group is left out.
ExperimentVerdicts compare_with_baseline(std::span<const std::vector<TrialRecord>> trials,
                                         std::span<const GroupPlace> places, const std::string& baseline_row);

// "faster", "slower", "fewer", "more", "lower", "higher", "within noise", "too few trials".
enum class ComparedMeasure { time, nodes, falsified };
std::string_view verdict_word(ComparedMeasure measure, SampleOrder order);

// "faster (p = 0.002)", "within noise (p = 0.41)", "too few trials (n = 1, 3)".
std::string verdict_text(ComparedMeasure measure, const SampleComparison& comparison);

// "## Verdicts against BASELINE": one line per comparison (block where there are blocks, row,
// column, then time, nodes, falsified), and the paragraph saying how they are decided.
std::string to_markdown(const ExperimentVerdicts& verdicts, std::span<const GroupPlace> places);

// The CSV columns of the verdicts (verdict_csv_header) and each group's fields: the baseline row
// and, per measure, the verdict word and its p-value (empty for a baseline group, a group without
// a baseline and a p of too few trials).
std::vector<std::string> verdict_csv_header();
std::vector<std::vector<std::string>> verdict_csv_fields(const ExperimentVerdicts& verdicts, std::size_t groups);

}  // namespace hyfal
