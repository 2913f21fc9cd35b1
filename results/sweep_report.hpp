// A sweep table (PaperTable::sweep, e.g. seed 002 Table 1) beside our trials: per block (driver),
// rows = methods, columns = the swept instance values (|Q|); each cell the mean wall time over
// its trials (one per safety property), the paper's value beside it, and per column whether
// the paper's order of the rows holds for ours.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/run/paper_table.hpp"
#include "core/run/trial_record.hpp"
#include "results/paper_report.hpp"
#include "results/statistics.hpp"

namespace hyfal {

struct SweepCell {
  bool run = false;               // the profile ran this column
  bool skipped = false;           // not run: an earlier column of the row had every trial stopped
  double paper = kNotReported;    // seconds; kPaperTimeout for the paper's "X"
  std::size_t n = 0, falsified = 0, timeouts = 0, node_caps = 0, not_found = 0, errors = 0;
  // Wall seconds over the trials (errors excluded); a stopped trial counts with the time it had,
  // so a cell with stopped trials is a lower bound (censored()).
  double mean_s = kNotReported, median_s = kNotReported;
  double value = kNotReported;  // what the table shows: mean_s, or median_s for a median table
  SampleSummary wall_s, nodes;  // mean, median, std, 95 % CI of the cell's trials (errors excluded)
  // The wall times as the ordering test sees them: stopped trials censored at the time they had.
  std::vector<CensoredValue> observations;
  bool censored() const { return timeouts > 0 || node_caps > 0; }
  bool all_stopped() const { return n > 0 && timeouts + node_caps == n; }  // our "X"
};

struct SweepReport {
  std::string id, title, source, suite, notes;
  std::vector<std::string> rows, methods, columns, blocks;
  double paper_timeout_s = 0.0;
  bool median = false;
  std::vector<std::vector<std::vector<SweepCell>>> cells;      // [block][row][column]
  // [block][column], run columns: the paper's order by time (its "X" counts as its time limit)
  // against ours, each adjacent pair of the paper's order tested on the cells' trials
  // (check_ordering: Gehan's test of the censored wall times).
  std::vector<std::vector<OrderingCheck>> orderings;
};

// trials[block][row][column]: the trials of that cell (any instance); with skip_after_all_stopped,
// a run cell without trials after one of its row where every trial was stopped is `skipped`. Throws
// std::invalid_argument when the shape does not match the table's sweep.
SweepReport make_sweep_report(const PaperTable& table,
                              const std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>& trials,
                              int columns_run, bool skip_after_all_stopped = false);
// The same with the columns run given one flag each (columns_run of core/run/paper_table.hpp).
SweepReport make_sweep_report(const PaperTable& table,
                              const std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>& trials,
                              const std::vector<bool>& run, bool skip_after_all_stopped = false);

// Markdown: per block our cells and the paper's, the fastest method and first X per column, a
// statistics table (per row and run column: n, falsified, stopped, then mean, median, std and
// 95 % CI of time and of nodes), and one ordering line per run column with its pair verdicts;
// then the verdict counts over the table and how they are decided. A block without a number of
// the paper's (a table of our own, e.g. ompl-navigation) has no paper table, its fastest and
// first-X lines show ours only, and it has no ordering lines; a table without any has no verdict
// counts either.
std::string to_markdown(const SweepReport& report, const ReportHeader& header);
// RFC 4180 CSV, one line per (block, row, column run): table,profile,block,row,method,column,
// paper,ours_mean,ours_median,n,falsified,falsified_rate,timeouts,errors,time_std_s,
// time_ci_low_s,time_ci_high_s,nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high,
// paper_previous,verdict,p_value,skipped,statistic (NaN empty, X = inf; timeouts counts every
// stopped trial; paper_previous, verdict and p_value: the ordering test against the row before
// this one in the paper's order of the column, empty for the first; statistic: "mean" or
// "median", which of ours_mean and ours_median the table's cells show, so that a figure drawn
// from the CSV plots the table's statistic).
std::string to_csv(const SweepReport& report, const ReportHeader& header);

}  // namespace hyfal
