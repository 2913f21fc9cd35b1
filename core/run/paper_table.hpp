// A paper table to reproduce: which rows (method + settings) run on which suite, the paper's
// reference numbers, and the three run profiles. Suites declare their tables next to their
// model (suites/<suite>.cpp); `hyfal reproduce ID --profile P` runs one and writes
// results/tables/<ID>.md and .csv with the paper's numbers beside ours.
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hyfal {

using Settings = std::vector<std::pair<std::string, std::string>>;  // --set key=value pairs

inline constexpr double kNotReported = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kPaperTimeout = std::numeric_limits<double>::infinity();

// A column the paper reports, and how ours is computed from the trials of a row.
enum class TableMetric {
  nodes,     // mean nodes over trials
  time_s,    // mean wall time, seconds
  coverage,  // mean of the per-trial metric "coverage" (see PlannerOutcome::metrics)
  falsified_rate,
};

struct PaperColumn {
  std::string name;  // header, e.g. "nodes", "time (s)", "coverage after 5000 nodes"
  TableMetric metric;
  std::string metric_key;  // for TableMetric::coverage: the per-trial metric name
};

struct PaperRow {
  std::string label;          // as the paper names the row, e.g. "t2go"
  std::string method;         // registered method name
  Settings settings;          // instance parameters and method options of this row
  std::vector<double> paper;  // one value per column; NaN = not reported (N/A)
};

struct TableProfile {
  int trials = 10;
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
  Settings settings;  // applied to every row before the row's own settings
  // Sweep tables only (PaperTable::sweep): instances per cell (values 0..instances-1 of the
  // sweep's instance_key) and the columns to run (the first `columns`; -1 = all).
  int instances = 1;
  int columns = -1;
  // Or the columns to run by label, in the sweep's order (non-empty: `columns` is not used); e.g.
  // the paper profile runs exactly the paper's columns and leaves out one the paper does not have.
  std::vector<std::string> column_labels = {};
  // League tables only (PaperTable::league): the rows to run, by label; empty = every row.
  std::vector<std::string> row_labels = {};
  // League tables only: settings for one column in this profile (column label -> settings),
  // applied after the column's own; e.g. FalStar's adaptive search on FalStar's own 1 s input
  // grid in the published profile, where the other columns keep the published 7.5 s pieces.
  std::vector<std::pair<std::string, Settings>> column_settings = {};
  // Per-row time limits (row label -> seconds) replacing timeout_s for that row: a table states
  // each method's cap, as the paper's X's imply one per method (seed 002 Table 1).
  std::vector<std::pair<std::string, double>> row_timeout_s = {};
  // Sweep tables only: once every trial of a row's cell was stopped (our "X"), the row's later
  // (larger) columns are not run and read "X (skipped)", as the paper stops a method at its
  // first X. Columns then run one after another (each column a wave of trials).
  bool skip_after_all_stopped = false;

  // The time limit of the row labelled `label`.
  double timeout_for(const std::string& label) const {
    for (const auto& [row, seconds] : row_timeout_s)
      if (row == label) return seconds;
    return timeout_s;
  }
};

// A table whose columns (and blocks) are values of instance parameters — seed 002 Table 1:
// rows are methods, columns |Q| = n², one block per driver, and each cell aggregates one trial
// per safety property (instance_key = "property", values 0..k-1). A cell's time is the mean
// wall time over its trials; a timed-out trial counts with the time limit (a lower bound).
struct SweepValue {
  std::string label;  // header, e.g. "32²" or "RandomDriver"
  Settings settings;  // the instance settings it stands for, e.g. {{"n", "32"}}
};
struct TableSweep {
  std::vector<SweepValue> columns;
  std::vector<SweepValue> blocks;  // empty: one block
  std::string instance_key;        // e.g. "property"; empty: one instance per cell
  // The paper's values, [block][row][column], seconds; kPaperTimeout = the paper's "X".
  std::vector<std::vector<std::vector<double>>> paper;
  double paper_timeout_s = 0.0;  // the paper's time limit behind "X"
  bool median = false;           // cells are medians over the instances (seed 002 Table 2), not means
};

// Which of the sweep's columns `profile` runs: column_labels when given, else the first `columns`
// (-1 = all).
inline std::vector<bool> columns_run(const TableSweep& sweep, const TableProfile& profile) {
  std::vector<bool> run(sweep.columns.size(), false);
  for (std::size_t c = 0; c < run.size(); ++c) {
    if (profile.column_labels.empty())
      run[c] = profile.columns < 0 || c < static_cast<std::size_t>(profile.columns);
    else
      for (const std::string& label : profile.column_labels) run[c] = run[c] || label == sweep.columns[c].label;
  }
  return run;
}

// A league table (ARCH-COMP's falsification table): rows are requirements, each a suite instance
// of its own (suite and settings, e.g. requirement = "AT1"); columns are methods with options;
// each cell the falsification rate over the runs and the simulations the falsifying runs took.
// `hyfal reproduce` runs every row with every column (results/league_report.hpp).
struct LeagueRow {
  std::string label;  // e.g. "AT1" or "CC3 (instance 2)"
  std::string suite;
  Settings settings;  // the instance: its requirement and input instance
};
struct LeagueColumn {
  std::string label;  // e.g. "RRT (guided)"
  std::string method;
  Settings settings;  // method options
};
// Another tool's published numbers on one row (../shared/arch/published.md), shown beside ours.
struct PublishedCell {
  std::string row;  // a LeagueRow label
  int falsified = 0, runs = 0;
  double mean_simulations = kNotReported, median_simulations = kNotReported, mean_s = kNotReported;
};
struct PublishedTool {
  std::string label;     // e.g. "Breach CMA-ES"
  std::string source;    // where the numbers are from
  std::string settings;  // under which settings (runs, budget, control points)
  std::vector<PublishedCell> cells;
};
struct TableLeague {
  std::vector<LeagueRow> rows;
  std::vector<LeagueColumn> columns;
  std::vector<PublishedTool> published;
};

struct PaperTable {
  std::string id;  // e.g. "kim-table1"
  std::string title;
  std::string source;  // e.g. "seed 000 Table I (10 trials, 1 GHz PC)"
  std::string suite;
  std::vector<PaperColumn> columns;
  std::vector<PaperRow> rows;
  TableProfile smoke, quick, paper;
  // Between quick and paper: the committed tables' profile (larger samples, every column, per-row
  // caps); optional in a table file.
  std::optional<TableProfile> full = {};
  std::string notes;  // what differs from the paper's set-up, and why
  // Per-trial series (PlannerOutcome::series names) exported to <id>-<name>.csv, e.g. the
  // sorted n_j of seed 000 Fig. 6 or coverage against nodes.
  std::vector<std::string> series = {};
  // When set, the table is a sweep (rows x sweep columns per block) and `columns`/`paper` of
  // the rows are not used.
  std::optional<TableSweep> sweep = {};
  // When set, the table is a league (rows x columns of TableLeague): `suite`, `columns` and `rows`
  // are not used, and the optional `published` profile runs the league in the published tools'
  // settings.
  std::optional<TableLeague> league = {};
  std::optional<TableProfile> published = {};
};

}  // namespace hyfal
