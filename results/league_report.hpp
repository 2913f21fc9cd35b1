// A league table (PaperTable::league, ARCH-COMP's falsification table) from its trials: per
// requirement (row) and method (column) the falsification rate k/n and the simulations the
// falsifying runs took (ARCH-COMP's measure: mean and median over the successful runs), beside
// the published tools' numbers; per row, which method leads and how each other one compares with
// it on simulations (Gehan's test, runs that did not falsify censored at the simulations they had:
// the budget) and on the rate (Fisher's exact test).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/run/paper_table.hpp"
#include "core/run/trial_record.hpp"
#include "results/paper_report.hpp"
#include "results/statistics.hpp"

namespace hyfal {

struct LeagueCell {
  bool run = false;  // the profile ran this row
  // Why the column's method cannot drive the row's suite (e.g. a search over input signals on a
  // suite with none): the cell does not apply ("n/a"), has no runs and is in no verdict. Empty: it applies.
  std::string not_applicable;
  std::size_t n = 0, falsified = 0, validated = 0, budget_stops = 0, timeouts = 0, not_found = 0, errors = 0;
  SampleSummary simulations;  // of the falsified runs
  SampleSummary nodes;        // of the falsified runs (a tree's nodes; an optimiser's evaluations)
  SampleSummary wall_s;       // every run but errors
  SampleSummary robustness;   // every run but errors: the witness's, else the lowest bound found
  // Falsified runs whose witness's robustness lies within 1 % of the row's threshold scale
  // (LeagueReport::threshold_scale): witnesses a simulator a little off could refute.
  std::size_t near_threshold = 0;
  // Simulations of every run but errors, a run that did not falsify censored at what it had.
  std::vector<CensoredValue> observations;
  std::vector<CensoredValue> falsified_indicators;
};

// A column against its row's leader.
struct LeagueComparison {
  SampleComparison simulations, rate;
};

struct LeagueRowVerdicts {
  std::ptrdiff_t leader = -1;  // the column with most falsified runs, ties to fewer mean simulations; -1: none (or no run falsified)
  std::vector<LeagueComparison> against_leader;  // per column (the leader's own is empty)
};

struct LeagueReport {
  std::string id, title, source, notes;
  TableLeague league;
  std::vector<std::vector<LeagueCell>> cells;  // [row][column]
  std::vector<LeagueRowVerdicts> verdicts;      // per row
  // Per row: its requirement's threshold scale (stl::threshold_scale; 0: not known, no count).
  std::vector<double> threshold_scale;
};

// trials[row][column]: the trials of that cell; `run[row]` whether the profile ran the row;
// threshold_scale[row] (optional: empty, or one per row) the scale its witnesses are measured
// against; not_applicable[row][column] (optional: empty, or one per cell) why a cell does not apply
// (empty: it does). Throws std::invalid_argument when the shape does not match the league.
LeagueReport make_league_report(const PaperTable& table, const std::vector<std::vector<std::vector<TrialRecord>>>& trials,
                                const std::vector<bool>& run, const std::vector<double>& threshold_scale = {},
                                const std::vector<std::vector<std::string>>& not_applicable = {});

// Markdown: the header, the league (rows x columns, "k/n · mean (median)" simulations), the
// statistics of every cell, the verdicts per row, and the published tools beside ours where they
// have numbers for a row run (with their sources and settings).
std::string to_markdown(const LeagueReport& report, const ReportHeader& header);

// RFC 4180 CSV, one line per (row run, column) of ours and per published cell of a row run:
// table,profile,source,row,suite,column,method,n,falsified,validated,falsified_rate,budget_stops,
// timeouts,errors,simulations_mean,simulations_median,simulations_std,simulations_ci_low,
// simulations_ci_high,nodes_mean,time_mean_s,robustness_median,leader,simulations_verdict,
// simulations_p,rate_verdict,rate_p,near_threshold (source "hyfal", or the published tool's label
// with the verdict fields empty; NaN an empty field; near_threshold empty where the row's scale is
// not known).
std::string to_csv(const LeagueReport& report, const ReportHeader& header);

}  // namespace hyfal
