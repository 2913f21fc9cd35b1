// Writers of group summaries: a Markdown table for reading, a CSV file for further analysis.
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "results/statistics.hpp"

namespace hyfal {

// A GitHub Markdown table, one row per group, columns
//   suite | instance | method | [config] | n | falsified | rate | time median (s) |
//   time mean ± 95% CI (s) | time std | nodes median | nodes mean ± 95% CI | nodes std | timeouts
// The config column appears only when the groups differ in config. A group with timed-out or
// node-capped trials has its time and nodes medians and means prefixed with "≥" (they are lower
// bounds) and its "stopped" cell reads e.g. "3 ⏱" (plus "2 node cap" for node caps, "4 budget" for trials that
// spent their method's budget); a footnote line below the table then explains "≥". Missing statistics (e.g. a CI of one trial) read "–".
std::string to_markdown(std::span<const GroupSummary> groups);

// The same table with the identifying columns (suite | instance | method | [config]) replaced by
// `label_header` and labels[i] for groups[i] (e.g. an experiment's row, column and the settings
// that tell its groups apart).
std::string to_markdown(std::span<const GroupSummary> groups, const std::vector<std::string>& label_header,
                        const std::vector<std::vector<std::string>>& labels);

// RFC 4180 CSV (CRLF line ends, fields with a comma, quote or line break quoted, quotes doubled)
// with a header row: suite,instance,method,config,n,falsified,validated,falsified_rate,timeouts,
// node_caps,budgets,not_found,errors,time_mean_s,time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,
// nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high. Numbers are written with full
// (round-trip) precision; a NaN statistic is an empty field.
std::string to_csv(std::span<const GroupSummary> groups);

// Where a group sits in an experiment's table (experiment files: `[table]` rows, columns, blocks).
struct GroupPlace {
  std::string block, row, column;
};

// What a laid-out table shows per cell.
enum class GroupMeasure { falsified_rate, time_mean_s, time_median_s, nodes_mean, nodes_median };

// "falsified_rate", "time_mean_s", "time_median_s", "nodes_mean", "nodes_median".
std::string_view to_string(GroupMeasure measure);

// groups[i] laid out at places[i]: per block (in order of first appearance; a "### block" heading
// unless the only block is "") one Markdown table, rows x columns in order of first appearance,
// each cell the group's `measure` ("≥" when the group has stopped trials and the measure is a
// time or node count, as in to_markdown; "–" where no group sits), and the "≥" footnote if used.
std::string to_markdown(std::span<const GroupSummary> groups, std::span<const GroupPlace> places,
                        GroupMeasure measure);

// to_csv with the columns block,row,column of places[i] in front of each group's line.
std::string to_csv(std::span<const GroupSummary> groups, std::span<const GroupPlace> places);
// The same with the columns extra_header after each line, extra[i] the fields of groups[i]
// (quoted here as needed).
std::string to_csv(std::span<const GroupSummary> groups, std::span<const GroupPlace> places,
                   const std::vector<std::string>& extra_header, const std::vector<std::vector<std::string>>& extra);

}  // namespace hyfal
