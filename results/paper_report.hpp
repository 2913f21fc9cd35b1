// A paper table beside our trials: for each row and column the paper's value, ours, and both
// as ratios to the first row; per row the trial statistics; per column whether the paper's
// ordering of the rows holds for ours. `hyfal reproduce` writes it as Markdown and CSV.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/paper_table.hpp"
#include "core/trial_record.hpp"
#include "results/statistics.hpp"

namespace hyfal {

// How a value of ours relates to the true one. Nodes and wall times of trials stopped by the
// time limit or the node cap are lower bounds (right-censored), so a mean over them is too,
// and a ratio of such a mean to an exact one is a lower (or, in the denominator, upper) bound.
enum class Bound { exact, lower, upper, unknown };

struct PaperReportCell {
  double paper = kNotReported;
  double ours = kNotReported;        // mean over the row's trials (see PaperReportRow)
  double paper_ratio = kNotReported;  // paper / paper of the first row
  double ours_ratio = kNotReported;   // ours / ours of the first row
  Bound ours_bound = Bound::exact;
  Bound ours_ratio_bound = Bound::exact;
  // The sample behind `ours`: nodes or wall times (errors excluded), the metric's values (trials
  // that have it), or for falsified_rate every trial (median and CI then NaN: a 0/1 sample).
  SampleSummary sample;
};

struct PaperReportRow {
  std::string label;
  std::string method;
  Settings settings;  // the row's own settings, as the table states them
  std::size_t n = 0;  // trials
  std::size_t falsified = 0, timeouts = 0, node_caps = 0, not_found = 0, errors = 0;
  double falsified_rate = kNotReported;  // falsified / n (errors count as not falsified)
  SampleSummary nodes;   // errors excluded
  SampleSummary wall_s;  // errors excluded
  bool censored() const { return timeouts > 0 || node_caps > 0; }
  std::vector<PaperReportCell> cells;  // one per column
};

// The paper's order of the rows by one column against ours. Rows whose paper value is NaN are
// left out of both. Values in `paper_order` / `ours_order` are row indices, ascending by value
// (ties keep the table's row order); `*_tied_with_previous[i]` says whether the i-th row of the
// order equals the one before (paper: exactly; ours: within `kOrderingTolerance`).
enum class OrderingVerdict { holds, does_not_hold, not_checked };

inline constexpr double kOrderingTolerance = 0.01;  // relative: ours within 1 % are equal

struct OrderingCheck {
  std::size_t column = 0;
  std::vector<std::size_t> paper_order, ours_order;
  std::vector<bool> paper_tied_with_previous, ours_tied_with_previous;
  OrderingVerdict verdict = OrderingVerdict::not_checked;
  std::string why_not_checked;  // for not_checked: fewer than two rows, or a row has no value
};

struct PaperReport {
  std::string id, title, source, suite, notes;
  std::vector<PaperColumn> columns;
  std::vector<PaperReportRow> rows;
  std::vector<OrderingCheck> orderings;  // one per column
};

// Builds the report of `table` from the trials of each row (rows_trials[i] for table.rows[i]).
// Throws std::invalid_argument if rows_trials does not have one entry per row. A paper vector
// shorter than the columns reads as NaN for the missing columns.
PaperReport make_paper_report(const PaperTable& table,
                              const std::vector<std::vector<TrialRecord>>& rows_trials);

// The values of the per-trial metric `key` (a number in TrialRecord::metrics) of the trials that
// have it, in trial order. Trials whose metrics are not a JSON object, or lack the key, or hold
// a non-number under it, are skipped.
std::vector<double> metric_values(const std::vector<TrialRecord>& trials, const std::string& key);

// Pairwise: for every two rows with a paper value, the sign of paper_i - paper_j must be the
// sign of ours_i - ours_j, where ours within `kOrderingTolerance` (relative) compare equal.
OrderingCheck check_ordering(const std::vector<double>& paper, const std::vector<double>& ours,
                             std::size_t column = 0);

// How and where the table was run: the header of the report.
struct ReportHeader {
  std::string profile;
  int trials = 0;  // per row
  double timeout_s = 0.0;
  std::int64_t max_nodes = 0;
  Settings profile_settings;
  std::uint64_t seed = 0;
  int threads = 0;
  std::string host;
  int nproc = 0;
  std::string cpu_model;
  std::string date_utc;
  std::string git_commit;
  std::string experiment;
};

// A Markdown document: title, the header lines, one table per column (row, method, paper,
// paper × of row 1, ours, ours × of row 1), a table of trial statistics per row, one ordering
// line per column, and a footnote explaining "≥" / "≤" when a value is a bound.
std::string to_markdown(const PaperReport& report, const ReportHeader& header);

// RFC 4180 CSV (CRLF, fields quoted as needed), one line per (row, column), with header
// table,profile,row,method,column,paper,ours,paper_ratio,ours_ratio,n,falsified_rate,median,
// ci_low,ci_high,timeouts. n, median and CI are of the column's sample (PaperReportCell::sample);
// numbers have full precision; NaN is an empty field.
std::string to_csv(const PaperReport& report, const ReportHeader& header);

// "model name" from /proc/cpuinfo, or "unknown".
std::string cpu_model_name();

}  // namespace hyfal
