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

PaperReportCell make_cell(const PaperColumn& column, const PaperReportRow& row,
                          const std::vector<TrialRecord>& trials) {
  PaperReportCell cell;
  switch (column.metric) {
    case TableMetric::nodes: cell.sample = row.nodes; break;
    case TableMetric::time_s: cell.sample = row.wall_s; break;
    case TableMetric::coverage: cell.sample = summarize(metric_values(trials, metric_key_of(column))); break;
    case TableMetric::falsified_rate:
      cell.sample.n = row.n;
      cell.sample.mean = row.falsified_rate;
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

std::string markdown_separator(std::size_t text_columns, std::size_t columns) {
  std::vector<std::string> separator;
  for (std::size_t c = 0; c < columns; ++c) separator.emplace_back(c < text_columns ? "---" : "--:");
  return markdown_row(separator);
}

std::string settings_text(const Settings& settings) {
  if (settings.empty()) return std::string(kMissing);
  std::vector<std::string> parts;
  for (const auto& [key, value] : settings) parts.push_back(fmt::format("{}={}", key, value));
  return fmt::format("{}", fmt::join(parts, ", "));
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
  if (parts.empty()) return "0";
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string order_text(const PaperReport& report, const std::vector<std::size_t>& order,
                       const std::vector<bool>& tied, const std::vector<double>* values) {
  std::string text;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0) text += tied[i] ? " = " : " < ";
    text += report.rows[order[i]].label;
    if (values && std::isnan((*values)[order[i]])) text += " (no value)";
  }
  return text.empty() ? std::string(kMissing) : text;
}

std::string_view verdict_text(OrderingVerdict verdict) {
  switch (verdict) {
    case OrderingVerdict::holds: return "holds";
    case OrderingVerdict::does_not_hold: return "does not hold";
    case OrderingVerdict::not_checked: return "not checked";
  }
  return "not checked";
}

}  // namespace

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

OrderingCheck check_ordering(const std::vector<double>& paper, const std::vector<double>& ours,
                             std::size_t column) {
  OrderingCheck check;
  check.column = column;
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < paper.size(); ++r)
    if (!std::isnan(paper[r])) rows.push_back(r);
  const auto ours_of = [&](std::size_t r) { return r < ours.size() ? ours[r] : kNotReported; };
  const auto ours_equal = [](double a, double b) {
    return std::abs(a - b) <= kOrderingTolerance * std::max(std::abs(a), std::abs(b));
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
    const double x = ours_of(check.ours_order[i]);
    const bool tied = i > 0 && !std::isnan(x) && !std::isnan(ours_of(check.ours_order[i - 1])) &&
                      ours_equal(x, ours_of(check.ours_order[i - 1]));
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
  const auto sign = [](double d) { return (d > 0) - (d < 0); };
  check.verdict = OrderingVerdict::holds;
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = i + 1; j < rows.size(); ++j) {
      const int paper_sign = sign(paper[rows[i]] - paper[rows[j]]);
      const double a = ours_of(rows[i]), b = ours_of(rows[j]);
      const int ours_sign = ours_equal(a, b) ? 0 : sign(a - b);
      if (paper_sign != ours_sign) check.verdict = OrderingVerdict::does_not_hold;
    }
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
    for (const PaperReportRow& row : report.rows) {
      paper.push_back(row.cells[c].paper);
      ours.push_back(row.cells[c].ours);
    }
    report.orderings.push_back(check_ordering(paper, ours, c));
  }
  return report;
}

std::string to_markdown(const PaperReport& report, const ReportHeader& header) {
  std::string md = fmt::format("# {}: {}\n\n", report.id, report.title);
  md += fmt::format("- source: {}\n", report.source.empty() ? std::string(kMissing) : report.source);
  md += fmt::format("- profile: {}: {} trials per row, timeout {} s, node cap {}, master seed {}; profile settings: {}\n",
                    header.profile, header.trials, header.timeout_s, header.max_nodes, header.seed,
                    settings_text(header.profile_settings));
  md += fmt::format("- suite: {}; experiment: {}\n", report.suite.empty() ? std::string(kMissing) : report.suite,
                    header.experiment.empty() ? std::string(kMissing) : header.experiment);
  md += fmt::format("- machine: {}, nproc {}, {}; {} worker threads\n", header.host, header.nproc, header.cpu_model,
                    header.threads);
  md += fmt::format("- date (UTC): {}\n", header.date_utc);
  md += fmt::format("- git commit: {}\n", header.git_commit);
  if (!report.notes.empty()) {
    std::string notes = report.notes;
    while (!notes.empty() && (notes.back() == '\n' || notes.back() == ' ')) notes.pop_back();
    std::string indented;
    for (const char c : notes) {
      indented += c;
      if (c == '\n') indented += "  ";
    }
    md += fmt::format("- notes: {}\n", indented);
  }

  bool any_bound = false;
  for (std::size_t c = 0; c < report.columns.size(); ++c) {
    const PaperColumn& column = report.columns[c];
    md += fmt::format("\n## {}\n\n", column.name);
    md += markdown_row({"row", "method", "paper", "paper × of row 1", "ours", "ours × of row 1"});
    md += markdown_separator(2, 6);
    for (const PaperReportRow& row : report.rows) {
      const PaperReportCell& cell = row.cells[c];
      any_bound = any_bound || cell.ours_bound != Bound::exact || cell.ours_ratio_bound != Bound::exact;
      md += markdown_row({markdown_cell(row.label), markdown_cell(row.method), format_paper(cell.paper),
                          format_significant(cell.paper_ratio),
                          marked(format_ours(cell.ours, column.metric), cell.ours_bound),
                          marked(format_significant(cell.ours_ratio), cell.ours_ratio_bound)});
    }
  }

  md += "\n## Trials\n\n";
  md += markdown_row({"row", "method", "settings", "n", "falsified rate", "nodes median", "nodes 95% CI",
                      "time median (s)", "time 95% CI (s)", "timeouts"});
  md += markdown_separator(3, 10);
  for (const PaperReportRow& row : report.rows) {
    const Bound b = row.censored() ? Bound::lower : Bound::exact;
    any_bound = any_bound || row.censored();
    md += markdown_row({markdown_cell(row.label), markdown_cell(row.method), markdown_cell(settings_text(row.settings)),
                        fmt::format("{}", row.n),
                        std::isnan(row.falsified_rate) ? std::string(kMissing) : fmt::format("{:.2f}", row.falsified_rate),
                        marked(format_ours(row.nodes.median, TableMetric::nodes), b),
                        interval_text(row.nodes, TableMetric::nodes, row.censored()),
                        marked(format_ours(row.wall_s.median, TableMetric::time_s), b),
                        interval_text(row.wall_s, TableMetric::time_s, row.censored()), stopped_trials_cell(row)});
  }

  md += "\n## Ordering\n\n";
  for (const OrderingCheck& check : report.orderings) {
    std::vector<double> ours;
    for (const PaperReportRow& row : report.rows) ours.push_back(row.cells[check.column].ours);
    std::string verdict(verdict_text(check.verdict));
    if (check.verdict == OrderingVerdict::not_checked) verdict += fmt::format(" ({})", check.why_not_checked);
    md += fmt::format("- ordering ({}): paper {} — ours {} — {}\n", report.columns[check.column].name,
                      order_text(report, check.paper_order, check.paper_tied_with_previous, nullptr),
                      order_text(report, check.ours_order, check.ours_tied_with_previous, &ours), verdict);
  }
  md += fmt::format(
      "\nOrders are ascending; rows the paper does not report (N/A) are left out. The ordering holds iff every "
      "two rows compare the same way in ours as in the paper, with ours within {:g} % counted as equal.\n",
      kOrderingTolerance * 100.0);
  if (any_bound)
    md +=
        "\n≥ right-censored: the row has trials stopped by the time limit (⏱) or the node cap, counted with "
        "the time and nodes they had when stopped, so the true value is at least this. A ratio to a censored "
        "first row is an upper bound (≤), or neither bound (~) when both rows are censored.\n";
  return md;
}

std::string to_csv(const PaperReport& report, const ReportHeader& header) {
  constexpr std::string_view kLineEnd = "\r\n";
  std::string csv =
      "table,profile,row,method,column,paper,ours,paper_ratio,ours_ratio,n,falsified_rate,median,ci_low,ci_high,"
      "timeouts";
  csv += kLineEnd;
  for (const PaperReportRow& row : report.rows)
    for (std::size_t c = 0; c < report.columns.size(); ++c) {
      const PaperReportCell& cell = row.cells[c];
      const std::vector<std::string> fields{
          csv_field(report.id),         csv_field(header.profile),   csv_field(row.label),
          csv_field(row.method),        csv_field(report.columns[c].name), csv_number(cell.paper),
          csv_number(cell.ours),        csv_number(cell.paper_ratio), csv_number(cell.ours_ratio),
          fmt::format("{}", cell.sample.n), csv_number(row.falsified_rate), csv_number(cell.sample.median),
          csv_number(cell.sample.ci_low), csv_number(cell.sample.ci_high), fmt::format("{}", row.timeouts),
      };
      csv += fmt::format("{}", fmt::join(fields, ","));
      csv += kLineEnd;
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
