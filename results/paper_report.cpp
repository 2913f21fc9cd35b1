#include "results/paper_report.hpp"

#include <fmt/format.h>

#include "results/text_format.hpp"
#include <fmt/ranges.h>  // fmt::join

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

namespace hyfal {
namespace {

using namespace text;


double ratio(double value, double first) {
  if (std::isnan(value) || std::isnan(first) || first == 0.0) return kNotReported;
  return value / first;
}

bool is_time_or_nodes(TableMetric metric) {
  return metric == TableMetric::nodes || metric == TableMetric::time_s;
}

std::string metric_key_of(const PaperColumn& column) {
  return column.metric_key.empty() ? std::string("coverage") : column.metric_key;
}

// The bound of a / b, where a and b are exact values or lower bounds.
Bound ratio_bound(Bound numerator, Bound denominator) {
  if (numerator == Bound::exact && denominator == Bound::exact) return Bound::exact;
  if (denominator == Bound::exact) return numerator;  // a lower bound over an exact value
  if (numerator == Bound::exact) return Bound::upper;  // an exact value over a lower bound
  return Bound::unknown;
}

PaperReportRow summarize_row(const PaperRow& paper_row, const std::vector<TrialRecord>& trials) {
  PaperReportRow row;
  row.label = paper_row.label;
  row.method = paper_row.method;
  row.settings = paper_row.settings;
  row.n = trials.size();
  std::vector<double> nodes, wall_s;
  for (const TrialRecord& trial : trials) {
    switch (trial.status) {
      case TrialStatus::falsified: ++row.falsified; break;
      case TrialStatus::not_found: ++row.not_found; break;
      case TrialStatus::timeout: ++row.timeouts; break;
      case TrialStatus::node_cap: ++row.node_caps; break;
      case TrialStatus::budget: ++row.budgets; break;
      case TrialStatus::error: ++row.errors; break;
    }
    // As summarize_trials: an error says nothing about how long the method needs.
    if (trial.status != TrialStatus::error) {
      nodes.push_back(static_cast<double>(trial.nodes));
      wall_s.push_back(trial.wall_s);
    }
  }
  if (row.n > 0) row.falsified_rate = static_cast<double>(row.falsified) / static_cast<double>(row.n);
  row.nodes = summarize(nodes);
  row.wall_s = summarize(wall_s);
  return row;
}

std::vector<CensoredValue> exact_values(const std::vector<double>& values) {
  std::vector<CensoredValue> observations;
  for (const double value : values) observations.push_back({value, false});
  return observations;
}

PaperReportCell make_cell(const PaperColumn& column, const PaperReportRow& row,
                          const std::vector<TrialRecord>& trials) {
  PaperReportCell cell;
  switch (column.metric) {
    case TableMetric::nodes:
      cell.sample = row.nodes;
      cell.observations = censored_sample(trials, TrialMeasure::nodes);
      break;
    case TableMetric::time_s:
      cell.sample = row.wall_s;
      cell.observations = censored_sample(trials, TrialMeasure::wall_s);
      break;
    case TableMetric::coverage: {
      const std::vector<double> values = metric_values(trials, metric_key_of(column));
      cell.sample = summarize(values);
      cell.observations = exact_values(values);
      break;
    }
    case TableMetric::falsified_rate:
      cell.sample.n = row.n;
      cell.sample.mean = row.falsified_rate;
      // The rate's test compares the 0/1 indicators (Gehan's test without censoring is the
      // Wilcoxon-Mann-Whitney test; on 0/1 values its tie-corrected permutation variance makes
      // it the two-proportion test). Errors count as not falsified, as in the rate.
      cell.observations = falsified_indicators(trials);
      if (row.n >= 2) {  // the std of the 0/1 sample, so every column's CSV line has one
        const std::vector<double> indicators = [&] {
          std::vector<double> v;
          for (const CensoredValue& o : cell.observations) v.push_back(o.value);
          return v;
        }();
        cell.sample.stddev = summarize(indicators).stddev;
      }
      break;
  }
  cell.ours = cell.sample.mean;
  if (is_time_or_nodes(column.metric) && row.censored() && !std::isnan(cell.ours)) cell.ours_bound = Bound::lower;
  return cell;
}

// --- formatting -------------------------------------------------------------------------------

// Our value of a column: node counts as whole numbers once they are large, rates with two decimals.
std::string format_ours(double value, TableMetric metric) {
  if (std::isnan(value)) return std::string(kMissing);
  switch (metric) {
    case TableMetric::nodes:
      return std::abs(value) >= 100.0 && std::abs(value) < 1e12 ? fmt::format("{:.0f}", value)
                                                                 : format_significant(value);
    case TableMetric::falsified_rate: return fmt::format("{:.2f}", value);
    case TableMetric::time_s:
    case TableMetric::coverage: return format_significant(value);
  }
  return format_significant(value);
}

// The paper's value as the paper gives it (shortest round-trip form).
std::string format_paper(double value) {
  if (std::isnan(value)) return "N/A";
  return fmt::format("{}", value);
}

std::string_view bound_mark(Bound bound) {
  switch (bound) {
    case Bound::exact: return "";
    case Bound::lower: return "≥";
    case Bound::upper: return "≤";
    case Bound::unknown: return "~";
  }
  return "";
}

std::string marked(std::string cell, Bound bound) {
  if (cell == kMissing || bound == Bound::exact) return cell;
  return fmt::format("{}{}", bound_mark(bound), cell);
}



std::string interval_text(const SampleSummary& s, TableMetric metric, bool censored) {
  if (std::isnan(s.ci_low)) return std::string(kMissing);
  return marked(fmt::format("[{}, {}]", format_ours(s.ci_low, metric), format_ours(s.ci_high, metric)),
                censored ? Bound::lower : Bound::exact);
}

std::string stopped_trials_cell(const PaperReportRow& row) {
  std::vector<std::string> parts;
  if (row.timeouts > 0) parts.push_back(fmt::format("{} ⏱", row.timeouts));
  if (row.node_caps > 0) parts.push_back(fmt::format("{} node cap", row.node_caps));
  if (row.budgets > 0) parts.push_back(fmt::format("{} budget", row.budgets));
  if (parts.empty()) return "0";
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string order_text(const PaperReport& report, const std::vector<std::size_t>& order,
                       const std::vector<bool>& tied, const std::vector<double>* values, std::string_view tie_mark) {
  std::string text;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0) text += tied[i] ? tie_mark : " < ";
    text += report.rows[order[i]].label;
    if (values && std::isnan((*values)[order[i]])) text += " (no value)";
  }
  return text.empty() ? std::string(kMissing) : text;
}


}  // namespace

std::string p_value_text(double p, bool exact) {
  const std::string_view relation = exact ? "=" : "≈";
  if (p < 0.001) return "p < 0.001";
  std::string text = format_significant(p, 2);
  // Two digits would show 0.0496 as 0.050 beside "holds": keep the side of α visible.
  if ((p < kSignificanceLevel) != (std::stod(text) < kSignificanceLevel)) text = format_significant(p, 4);
  return fmt::format("p {} {}", relation, text);
}


std::vector<double> metric_values(const std::vector<TrialRecord>& trials, const std::string& key) {
  std::vector<double> values;
  for (const TrialRecord& trial : trials) {
    const nlohmann::json metrics = nlohmann::json::parse(trial.metrics, nullptr, /*allow_exceptions=*/false);
    if (!metrics.is_object()) continue;
    const auto it = metrics.find(key);
    if (it == metrics.end() || !it->is_number()) continue;
    values.push_back(it->get<double>());
  }
  return values;
}

std::string_view to_string(OrderingVerdict verdict) {
  switch (verdict) {
    case OrderingVerdict::holds: return "holds";
    case OrderingVerdict::within_noise: return "within noise";
    case OrderingVerdict::reversed: return "reversed";
    case OrderingVerdict::differs: return "differs";
    case OrderingVerdict::too_few_trials: return "too few trials";
    case OrderingVerdict::not_checked: return "not checked";
  }
  return "not checked";
}

std::size_t OrderingCheck::count(OrderingVerdict wanted) const {
  return static_cast<std::size_t>(
      std::count_if(pairs.begin(), pairs.end(), [&](const OrderedPair& pair) { return pair.verdict == wanted; }));
}

const OrderedPair* OrderingCheck::pair_ending_at(std::size_t row) const {
  for (const OrderedPair& pair : pairs)
    if (pair.second == row) return &pair;
  return nullptr;
}

std::string pairs_text(const OrderingCheck& check, const std::vector<std::string>& row_labels) {
  std::vector<std::string> parts;
  for (const OrderedPair& pair : check.pairs) {
    std::string part = fmt::format("{} {} {}: {}", row_labels[pair.first], pair.paper_tied ? "=" : "<",
                                   row_labels[pair.second], to_string(pair.verdict));
    if (pair.verdict == OrderingVerdict::too_few_trials)
      part += fmt::format(" (n = {}, {})", pair.test.n_x, pair.test.n_y);
    else
      part += fmt::format(" ({})", p_value_text(pair.test.p_value, pair.test.p_exact));
    parts.push_back(std::move(part));
  }
  return parts.empty() ? std::string(kMissing) : fmt::format("{}", fmt::join(parts, "; "));
}

std::string verdict_counts_text(const std::vector<const OrderingCheck*>& checks) {
  const auto total = [&](OrderingVerdict verdict) {
    std::size_t sum = 0;
    for (const OrderingCheck* check : checks) sum += check->count(verdict);
    return sum;
  };
  std::string text = fmt::format("{} hold, {} within noise, {} reversed", total(OrderingVerdict::holds),
                                 total(OrderingVerdict::within_noise), total(OrderingVerdict::reversed));
  if (const std::size_t few = total(OrderingVerdict::too_few_trials); few > 0) text += fmt::format(", {} too few trials", few);
  if (const std::size_t differ = total(OrderingVerdict::differs); differ > 0) text += fmt::format(", {} differ", differ);
  return text;
}

OrderingCheck check_ordering(const std::vector<double>& paper, const std::vector<double>& ours,
                             const std::vector<std::vector<CensoredValue>>& samples, std::size_t column) {
  OrderingCheck check;
  check.column = column;
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < paper.size(); ++r)
    if (!std::isnan(paper[r])) rows.push_back(r);
  const auto ours_of = [&](std::size_t r) { return r < ours.size() ? ours[r] : kNotReported; };
  static const std::vector<CensoredValue> kNoSample;
  const auto sample_of = [&](std::size_t r) -> const std::vector<CensoredValue>& {
    return r < samples.size() ? samples[r] : kNoSample;
  };

  check.paper_order = rows;
  std::stable_sort(check.paper_order.begin(), check.paper_order.end(),
                   [&](std::size_t a, std::size_t b) { return paper[a] < paper[b]; });
  for (std::size_t i = 0; i < check.paper_order.size(); ++i)
    check.paper_tied_with_previous.push_back(i > 0 && paper[check.paper_order[i]] == paper[check.paper_order[i - 1]]);

  check.ours_order = rows;  // rows without a value of ours go last
  std::stable_sort(check.ours_order.begin(), check.ours_order.end(), [&](std::size_t a, std::size_t b) {
    const double x = ours_of(a), y = ours_of(b);
    if (std::isnan(x) || std::isnan(y)) return !std::isnan(x) && std::isnan(y);
    return x < y;
  });
  for (std::size_t i = 0; i < check.ours_order.size(); ++i) {
    bool tied = false;
    if (i > 0 && !std::isnan(ours_of(check.ours_order[i])) && !std::isnan(ours_of(check.ours_order[i - 1]))) {
      const SampleOrder order = compare_samples(sample_of(check.ours_order[i - 1]), sample_of(check.ours_order[i])).order;
      tied = order == SampleOrder::within_noise || order == SampleOrder::too_few_trials;
    }
    check.ours_tied_with_previous.push_back(tied);
  }

  if (rows.size() < 2) {
    check.why_not_checked = "fewer than two rows have a paper value";
    return check;
  }
  for (const std::size_t r : rows)
    if (std::isnan(ours_of(r))) {
      check.why_not_checked = fmt::format("row {} has no value of ours", r + 1);
      return check;
    }

  // Adjacent pairs of the paper's order: they carry every claim of a strict order, and a
  // reversal anywhere in ours shows up as a reversed or within-noise adjacent pair.
  for (std::size_t i = 1; i < check.paper_order.size(); ++i) {
    OrderedPair pair{.first = check.paper_order[i - 1], .second = check.paper_order[i],
                     .paper_tied = check.paper_tied_with_previous[i], .verdict = OrderingVerdict::too_few_trials,
                     .test = {}};
    const SampleComparison comparison = compare_samples(sample_of(pair.first), sample_of(pair.second));
    pair.test = comparison.test;
    switch (comparison.order) {
      case SampleOrder::too_few_trials: pair.verdict = OrderingVerdict::too_few_trials; break;
      case SampleOrder::within_noise:
        pair.verdict = pair.paper_tied ? OrderingVerdict::holds : OrderingVerdict::within_noise;
        break;
      case SampleOrder::x_smaller:
        pair.verdict = pair.paper_tied ? OrderingVerdict::differs : OrderingVerdict::holds;
        break;
      case SampleOrder::y_smaller:
        pair.verdict = pair.paper_tied ? OrderingVerdict::differs : OrderingVerdict::reversed;
        break;
    }
    check.pairs.push_back(pair);
  }
  if (check.count(OrderingVerdict::reversed) > 0)
    check.verdict = OrderingVerdict::reversed;
  else if (check.count(OrderingVerdict::differs) > 0)
    check.verdict = OrderingVerdict::differs;
  else if (check.count(OrderingVerdict::holds) == check.pairs.size())
    check.verdict = OrderingVerdict::holds;
  else if (check.count(OrderingVerdict::within_noise) > 0)
    check.verdict = OrderingVerdict::within_noise;
  else
    check.verdict = OrderingVerdict::too_few_trials;
  return check;
}

PaperReport make_paper_report(const PaperTable& table,
                              const std::vector<std::vector<TrialRecord>>& rows_trials) {
  if (rows_trials.size() != table.rows.size())
    throw std::invalid_argument(fmt::format("table '{}' has {} rows but {} sets of trials were given", table.id,
                                            table.rows.size(), rows_trials.size()));
  PaperReport report{table.id, table.title, table.source, table.suite, table.notes, table.columns, {}, {}};
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    PaperReportRow row = summarize_row(table.rows[r], rows_trials[r]);
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
      PaperReportCell cell = make_cell(table.columns[c], row, rows_trials[r]);
      cell.paper = c < table.rows[r].paper.size() ? table.rows[r].paper[c] : kNotReported;
      row.cells.push_back(std::move(cell));
    }
    report.rows.push_back(std::move(row));
  }
  if (!report.rows.empty()) {
    const PaperReportRow& first = report.rows.front();
    for (PaperReportRow& row : report.rows)
      for (std::size_t c = 0; c < table.columns.size(); ++c) {
        PaperReportCell& cell = row.cells[c];
        cell.paper_ratio = ratio(cell.paper, first.cells[c].paper);
        cell.ours_ratio = ratio(cell.ours, first.cells[c].ours);
        cell.ours_ratio_bound = &row == &first ? Bound::exact : ratio_bound(cell.ours_bound, first.cells[c].ours_bound);
        if (std::isnan(cell.ours_ratio)) cell.ours_ratio_bound = Bound::exact;
      }
  }
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    std::vector<double> paper, ours;
    std::vector<std::vector<CensoredValue>> samples;
    for (const PaperReportRow& row : report.rows) {
      paper.push_back(row.cells[c].paper);
      ours.push_back(row.cells[c].ours);
      samples.push_back(row.cells[c].observations);
    }
    report.orderings.push_back(check_ordering(paper, ours, samples, c));
  }
  return report;
}

std::string timeout_text(const ReportHeader& header) {
  std::string s = fmt::format("timeout {} s", header.timeout_s);
  if (header.row_timeout_s.empty()) return s;
  std::vector<std::string> caps;
  for (const auto& [row, seconds] : header.row_timeout_s) caps.push_back(fmt::format("{} {} s", row, seconds));
  return fmt::format("{} ({})", s, fmt::join(caps, ", "));
}

std::string run_lines(const ReportHeader& header) {
  return fmt::format("- machine: {}, nproc {}, {}; {} worker threads\n- date (UTC): {}\n- git commit: {}\n", header.host,
                     header.nproc, header.cpu_model, header.threads, header.date_utc, header.git_commit) +
         cpu_time_line(header);
}

std::string cpu_time_line(const ReportHeader& header) {
  if (header.trials_run == 0) return "";
  const double s = header.cpu_s;
  const std::string amount = s >= 3600.0 ? fmt::format("{:.2f} h", s / 3600.0)
                             : s >= 60.0 ? fmt::format("{:.1f} min", s / 60.0)
                                         : fmt::format("{:.1f} s", s);
  return fmt::format("- CPU time: {} over {} trials (their CPU seconds summed)\n", amount, header.trials_run);
}

static std::string ordering_section(const PaperReport& report);

std::string to_markdown(const PaperReport& report, const ReportHeader& header) {
  std::string md = fmt::format("# {}: {}\n\n", report.id, report.title);
  md += fmt::format("- source: {}\n", report.source.empty() ? std::string(kMissing) : report.source);
  md += fmt::format("- profile: {}: {} trials per row, {}, node cap {}, master seed {}; profile settings: {}\n",
                    header.profile, header.trials, timeout_text(header), header.max_nodes, header.seed,
                    settings_text(header.profile_settings));
  md += fmt::format("- suite: {}; experiment: {}\n", report.suite.empty() ? std::string(kMissing) : report.suite,
                    header.experiment.empty() ? std::string(kMissing) : header.experiment);
  md += run_lines(header);
  md += notes_line(report.notes);

  bool any_bound = false;
  for (std::size_t c = 0; c < report.columns.size(); ++c) {
    const PaperColumn& column = report.columns[c];
    md += fmt::format("\n## {}\n\n", column.name);
    md += markdown_row({"row", "method", "paper", "paper × of row 1", "ours", "ours × of row 1"});
    md += markdown_separator(2, 6);
    for (const PaperReportRow& row : report.rows) {
      const PaperReportCell& cell = row.cells[c];
      any_bound = any_bound || cell.ours_bound != Bound::exact || cell.ours_ratio_bound != Bound::exact;
      // A metric only some trials record (coverage after 5000 nodes: only trials that grew that
      // far) is the mean over those trials: the cell says how many, so a mean of 1 of 10 is seen.
      std::string ours = marked(format_ours(cell.ours, column.metric), cell.ours_bound);
      if (column.metric == TableMetric::coverage && cell.sample.n < row.n)
        ours += fmt::format(" ({} of {} trials)", cell.sample.n, row.n);
      md += markdown_row({markdown_cell(row.label), markdown_cell(row.method), format_paper(cell.paper),
                          format_significant(cell.paper_ratio), ours,
                          marked(format_significant(cell.ours_ratio), cell.ours_ratio_bound)});
    }
  }

  md += "\n## Trials\n\n";
  md += markdown_row({"row", "method", "settings", "n", "falsified", "falsified rate", "nodes mean", "nodes median",
                      "nodes std", "nodes 95% CI", "time mean (s)", "time median (s)", "time std (s)",
                      "time 95% CI (s)", "timeouts"});
  md += markdown_separator(3, 15);
  for (const PaperReportRow& row : report.rows) {
    const Bound b = row.censored() ? Bound::lower : Bound::exact;
    any_bound = any_bound || row.censored();
    md += markdown_row({markdown_cell(row.label), markdown_cell(row.method), markdown_cell(settings_text(row.settings)),
                        fmt::format("{}", row.n), fmt::format("{}", row.falsified),
                        std::isnan(row.falsified_rate) ? std::string(kMissing) : fmt::format("{:.2f}", row.falsified_rate),
                        marked(format_ours(row.nodes.mean, TableMetric::nodes), b),
                        marked(format_ours(row.nodes.median, TableMetric::nodes), b),
                        format_ours(row.nodes.stddev, TableMetric::nodes),
                        interval_text(row.nodes, TableMetric::nodes, row.censored()),
                        marked(format_ours(row.wall_s.mean, TableMetric::time_s), b),
                        marked(format_ours(row.wall_s.median, TableMetric::time_s), b),
                        format_ours(row.wall_s.stddev, TableMetric::time_s),
                        interval_text(row.wall_s, TableMetric::time_s, row.censored()), stopped_trials_cell(row)});
  }

  // A table of one row (seed 003's RRFT tables) has no order to check: no Ordering section.
  if (report.rows.size() >= 2) md += ordering_section(report);
  if (any_bound)
    md +=
        "\n≥ right-censored: the row has trials stopped by the time limit (⏱) or the node cap, counted with "
        "the time and nodes they had when stopped, so the true value is at least this (std and CI are of "
        "these recorded values). A ratio to a censored first row is an upper bound (≤), or neither bound (~) "
        "when both rows are censored. The ordering test treats the stopped trials as censored, not as exact.\n";
  return md;
}

static std::string ordering_section(const PaperReport& report) {
  std::string md = "\n## Ordering\n\n";
  std::vector<std::string> labels;
  for (const PaperReportRow& row : report.rows) labels.push_back(row.label);
  std::vector<const OrderingCheck*> checked;
  for (const OrderingCheck& check : report.orderings) {
    std::vector<double> ours;
    for (const PaperReportRow& row : report.rows) ours.push_back(row.cells[check.column].ours);
    md += fmt::format("- ordering ({}): paper {} — ours {} — ", report.columns[check.column].name,
                      order_text(report, check.paper_order, check.paper_tied_with_previous, nullptr, " = "),
                      order_text(report, check.ours_order, check.ours_tied_with_previous, &ours, " ≈ "));
    if (check.verdict == OrderingVerdict::not_checked) {
      md += fmt::format("not checked ({})\n", check.why_not_checked);
      continue;
    }
    checked.push_back(&check);
    md += fmt::format("{} — {}: {}\n", pairs_text(check, labels), to_string(check.verdict),
                      verdict_counts_text({&check}));
  }
  md += fmt::format("\nSummary over the columns' adjacent pairs: {}.\n", verdict_counts_text(checked));
  md += "\n";
  md += ordering_method_text();
  return md;
}

std::string ordering_method_text() {
  return fmt::format(
      "Orders are ascending (ours: by the value shown; ≈ not significantly different from the row before); rows "
      "the paper does not report (N/A) are left out. Each adjacent pair of the paper's order is tested on the two "
      "rows' trials with Gehan's generalized Wilcoxon test (Gehan 1965, Biometrika 52: 203-223; two-sided, α = {:g}; "
      "p = exact permutation p-value, counted by dynamic programming over the splits of the pooled trials, always "
      "for pairs of up to 100 trials together; p ≈ normal approximation with the permutation variance where the "
      "exact count would cost too much), which ranks a trial stopped by the time limit or "
      "node cap above every value it certainly exceeds and leaves its order against larger values open: holds = "
      "ours significantly in the paper's direction, reversed = significantly the other way, within noise = not "
      "significant, too few trials = a row has fewer than two trials. Where the paper ties (=), ours hold when "
      "within noise and differ when significantly different. A column holds when every pair holds.\n",
      kSignificanceLevel);
}

std::string to_csv(const PaperReport& report, const ReportHeader& header) {
  constexpr std::string_view kLineEnd = "\r\n";
  std::string csv =
      "table,profile,row,method,column,paper,ours,paper_ratio,ours_ratio,n,falsified_rate,median,ci_low,ci_high,"
      "timeouts,std,falsified,node_caps,nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high,time_mean_s,"
      "time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,paper_previous,verdict,p_value,budgets";
  csv += kLineEnd;
  for (std::size_t r = 0; r < report.rows.size(); ++r) {
    const PaperReportRow& row = report.rows[r];
    for (std::size_t c = 0; c < report.columns.size(); ++c) {
      const PaperReportCell& cell = row.cells[c];
      const OrderedPair* pair = c < report.orderings.size() ? report.orderings[c].pair_ending_at(r) : nullptr;
      const std::vector<std::string> fields{
          csv_field(report.id),         csv_field(header.profile),   csv_field(row.label),
          csv_field(row.method),        csv_field(report.columns[c].name), csv_number(cell.paper),
          csv_number(cell.ours),        csv_number(cell.paper_ratio), csv_number(cell.ours_ratio),
          fmt::format("{}", cell.sample.n), csv_number(row.falsified_rate), csv_number(cell.sample.median),
          csv_number(cell.sample.ci_low), csv_number(cell.sample.ci_high), fmt::format("{}", row.timeouts),
          csv_number(cell.sample.stddev), fmt::format("{}", row.falsified), fmt::format("{}", row.node_caps),
          csv_number(row.nodes.mean),   csv_number(row.nodes.median), csv_number(row.nodes.stddev),
          csv_number(row.nodes.ci_low), csv_number(row.nodes.ci_high), csv_number(row.wall_s.mean),
          csv_number(row.wall_s.median), csv_number(row.wall_s.stddev), csv_number(row.wall_s.ci_low),
          csv_number(row.wall_s.ci_high),
          pair ? csv_field(report.rows[pair->first].label) : std::string(),
          pair ? csv_field(to_string(pair->verdict)) : std::string(),
          pair && pair->verdict != OrderingVerdict::too_few_trials ? csv_number(pair->test.p_value) : std::string(),
          fmt::format("{}", row.budgets),
      };
      csv += fmt::format("{}", fmt::join(fields, ","));
      csv += kLineEnd;
    }
  }
  return csv;
}

std::string cpu_model_name() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string model = line.substr(colon + 1);
    const auto first = model.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    model.erase(0, first);
    while (!model.empty() && (model.back() == ' ' || model.back() == '\t' || model.back() == '\r')) model.pop_back();
    return model;
  }
  return "unknown";
}

}  // namespace hyfal
