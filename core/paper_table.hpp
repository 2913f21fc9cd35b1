// A paper table to reproduce: which rows (method + settings) run on which suite, the paper's
// reference numbers, and the three run profiles. Suites declare their tables next to their
// model (suites/<suite>.cpp); `hyfal reproduce ID --profile P` runs one and writes
// results/tables/<ID>.md and .csv with the paper's numbers beside ours.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace hyfal {

using Settings = std::vector<std::pair<std::string, std::string>>;  // --set key=value pairs

// A column the paper reports, and how ours is computed from the trials of a row.
enum class TableMetric {
  nodes,        // mean nodes over trials
  time_s,       // mean wall time, seconds
  coverage,     // mean of the per-trial metric "coverage" (see PlannerOutcome::metrics)
  falsified_rate,
};

struct PaperColumn {
  std::string name;    // header, e.g. "nodes", "time (s)", "coverage after 5000 nodes"
  TableMetric metric;
  std::string metric_key;  // for TableMetric::coverage: the per-trial metric name
};

struct PaperRow {
  std::string label;     // as the paper names the row, e.g. "t2go"
  std::string method;    // registered method name
  Settings settings;     // instance parameters and method options of this row
  std::vector<double> paper;  // one value per column; NaN = not reported (N/A)
};

struct TableProfile {
  int trials = 10;
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
  Settings settings;  // applied to every row before the row's own settings
};

struct PaperTable {
  std::string id;        // e.g. "kim-table1"
  std::string title;
  std::string source;    // e.g. "seed 000 Table I (10 trials, 1 GHz PC)"
  std::string suite;
  std::vector<PaperColumn> columns;
  std::vector<PaperRow> rows;
  TableProfile smoke, quick, paper;
  std::string notes;     // what differs from the paper's set-up, and why
  // Per-trial series (PlannerOutcome::series names) exported to <id>-<name>.csv, e.g. the
  // sorted n_j of seed 000 Fig. 6 or coverage against nodes.
  std::vector<std::string> series = {};
};

inline constexpr double kNotReported = std::numeric_limits<double>::quiet_NaN();

}  // namespace hyfal
