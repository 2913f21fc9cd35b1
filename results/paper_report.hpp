// A paper table beside our trials: for each row and column the paper's value, ours, and both
// as ratios to the first row; per row the trial statistics; per column whether the paper's
// ordering of the rows holds for ours. `hyfal reproduce` writes it as Markdown and CSV.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/run/paper_table.hpp"
#include "core/run/trial_record.hpp"
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
  // The same sample as the ordering test sees it: nodes and times of stopped trials censored at
  // the value they had (is_right_censored); metric values and the falsified indicator (1 or 0
  // per trial) exact.
  std::vector<CensoredValue> observations;
};

struct PaperReportRow {
  std::string label;
  std::string method;
  Settings settings;  // the row's own settings, as the table states them
  std::size_t n = 0;  // trials
  std::size_t falsified = 0, timeouts = 0, node_caps = 0, budgets = 0, not_found = 0, errors = 0;
  double falsified_rate = kNotReported;  // falsified / n (errors count as not falsified)
  SampleSummary nodes;   // errors excluded
  SampleSummary wall_s;  // errors excluded
  bool censored() const { return timeouts > 0 || node_caps > 0 || budgets > 0; }
  std::vector<PaperReportCell> cells;  // one per column
};

// Whether the paper's ordering of the rows by one column holds for ours. Rows whose paper value
// is NaN are left out. `paper_order` / `ours_order` hold row indices, ascending by value (ours:
// by the cell's `ours`; ties keep the table's row order); `paper_tied_with_previous[i]`: the
// i-th row of the paper's order has the same paper value as the one before;
// `ours_tied_with_previous[i]`: the i-th row of our order is not significantly different from
// the one before (compare_samples: within noise or too few trials).
//
// Each adjacent pair (a, b) of the paper's order, paper(a) <= paper(b), gets a verdict from
// compare_samples on the two rows' observations (Gehan's test, two-sided, kSignificanceLevel):
//   holds           the paper has a < b and ours are significantly smaller in a than in b;
//   reversed        the paper has a < b and ours are significantly larger in a than in b;
//   within_noise    the paper has a < b and the test does not reject (not significant);
//   too_few_trials  a row has fewer than two values (no test can tell);
// and where the paper ties, a = b: holds when ours are within noise (ours cannot tell them apart
// either), differs when ours are significantly different.
// The column's verdict: reversed if a pair is reversed, else differs if one differs, else holds
// if every pair holds, else within_noise if a pair is within noise, else too_few_trials;
// not_checked (why_not_checked) when fewer than two rows have a paper value or a row has no value
// of ours.
enum class OrderingVerdict { holds, within_noise, reversed, differs, too_few_trials, not_checked };

struct OrderedPair {
  std::size_t first = 0, second = 0;  // row indices; paper(first) <= paper(second)
  bool paper_tied = false;
  OrderingVerdict verdict = OrderingVerdict::too_few_trials;
  GehanTest test;  // x = first row's observations, y = second's
};

struct OrderingCheck {
  std::size_t column = 0;
  std::vector<std::size_t> paper_order, ours_order;
  std::vector<bool> paper_tied_with_previous, ours_tied_with_previous;
  std::vector<OrderedPair> pairs;  // adjacent pairs of paper_order, in that order
  OrderingVerdict verdict = OrderingVerdict::not_checked;
  std::string why_not_checked;  // for not_checked: fewer than two rows, or a row has no value
  std::size_t count(OrderingVerdict verdict) const;  // pairs with this verdict
  // The pair whose second row is `row` (the row's verdict against the one before it in the
  // paper's order), or nullptr: the first of the order, a row left out, or not checked.
  const OrderedPair* pair_ending_at(std::size_t row) const;
};

// "holds", "within noise", "reversed", "differs", "too few trials", "not checked".
std::string_view to_string(OrderingVerdict verdict);

// "A < B: holds (p = 0.002); B < C: within noise (p = 0.41)" (paper ties read "A = B").
std::string pairs_text(const OrderingCheck& check, const std::vector<std::string>& row_labels);

// A test's p-value as the tables print it: "p = 0.041" for an exact permutation p-value, "p ≈ …"
// for the normal approximation (GehanTest::p_exact), "p < 0.001"; enough digits to show which
// side of kSignificanceLevel it is on.
std::string p_value_text(double p, bool exact);

// "3 hold, 1 within noise, 0 reversed" (+ ", k too few trials", ", k differ" where k > 0), the
// pair verdicts of `checks` counted together.
std::string verdict_counts_text(const std::vector<const OrderingCheck*>& checks);

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

// The check above of one column: paper[r] the paper's value of row r, ours[r] ours (the order
// shown), samples[r] the observations the test compares. A row with a NaN paper value is left
// out; ours or samples shorter than paper read as missing.
OrderingCheck check_ordering(const std::vector<double>& paper, const std::vector<double>& ours,
                             const std::vector<std::vector<CensoredValue>>& samples, std::size_t column = 0);

// The paragraph under a table's orderings that says how the verdicts are decided.
std::string ordering_method_text();

// How and where the table was run: the header of the report.
struct ReportHeader {
  std::string profile;
  int trials = 0;  // per row
  double timeout_s = 0.0;
  std::vector<std::pair<std::string, double>> row_timeout_s;  // per-row caps (TableProfile)
  bool skip_after_all_stopped = false;
  std::int64_t max_nodes = 0;
  Settings profile_settings;
  std::vector<std::pair<std::string, Settings>> column_settings;  // league: per column label (TableProfile)
  // The table's trials: how many, and their CPU seconds summed (what the table cost to make).
  std::size_t trials_run = 0;
  double cpu_s = 0.0;
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
// paper × of row 1, ours, ours × of row 1), a table of trial statistics per row (n, falsified,
// rate, then mean, median, std and 95 % CI of nodes and of time, and the stopped trials), one
// ordering line per column with its pair verdicts and their counts, a summary of the counts over
// all columns, how the verdicts are decided, and a footnote explaining "≥" / "≤" when a value is
// a bound.
std::string to_markdown(const PaperReport& report, const ReportHeader& header);

// The header's time limit with the per-row caps, e.g. "timeout 120 s (RRT 30 s, RRT[D*] 30 s)".
std::string timeout_text(const ReportHeader& header);
// The lines every table's header ends with: machine, date, git commit, then cpu_time_line.
std::string run_lines(const ReportHeader& header);
// "- CPU time: 1.52 h over 1,200 trials (their CPU seconds summed)\n", or "" with no trials.
std::string cpu_time_line(const ReportHeader& header);

// RFC 4180 CSV (CRLF, fields quoted as needed), one line per (row, column), with header
// table,profile,row,method,column,paper,ours,paper_ratio,ours_ratio,n,falsified_rate,median,
// ci_low,ci_high,timeouts,std,falsified,node_caps,nodes_mean,nodes_median,nodes_std,
// nodes_ci_low,nodes_ci_high,time_mean_s,time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,
// paper_previous,verdict,p_value,budgets (trials that spent the method's budget). n, median, CI and std are of the column's sample
// (PaperReportCell::sample), nodes_* and time_* of the row's trials; paper_previous is the row
// before this one in the paper's order of the column and verdict, p_value the ordering test of
// that pair (empty for the first row of the order and rows the paper leaves out); numbers have
// full precision; NaN is an empty field.
std::string to_csv(const PaperReport& report, const ReportHeader& header);

// "model name" from /proc/cpuinfo, or "unknown".
std::string cpu_model_name();

}  // namespace hyfal
