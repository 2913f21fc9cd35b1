#include "results/table_writer.hpp"

#include <fmt/format.h>

#include "results/text_format.hpp"
#include <fmt/ranges.h>  // fmt::join

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>
#include <vector>

namespace hyfal {
namespace {

using namespace text;

constexpr std::string_view kAtLeast = "≥";

std::string format_count(double value) {
  if (std::isnan(value)) return std::string(kMissing);
  return fmt::format("{:.0f}", value);
}

using NumberFormat = std::string (*)(double);

std::string format_time(double value) { return format_significant(value); }

// "mean ± half-width"; only the mean when the interval is unknown (fewer than two values).
std::string format_mean_with_ci(const SampleSummary& summary, NumberFormat format) {
  if (std::isnan(summary.mean)) return std::string(kMissing);
  if (std::isnan(summary.ci_high)) return format(summary.mean);
  return fmt::format("{} ± {}", format(summary.mean), format(summary.ci_high - summary.mean));
}

// A cell whose value is a lower bound of the true one gets the "≥" mark.
std::string mark_censored(std::string cell, bool censored) {
  if (!censored || cell == kMissing) return cell;
  return fmt::format("{}{}", kAtLeast, cell);
}

bool is_censored(const GroupSummary& group) { return group.timeouts > 0 || group.node_caps > 0 || group.budgets > 0; }

std::string stopped_trials_cell(const GroupSummary& group) {
  std::vector<std::string> parts;
  if (group.timeouts > 0) parts.push_back(fmt::format("{} ⏱", group.timeouts));
  if (group.node_caps > 0) parts.push_back(fmt::format("{} node cap", group.node_caps));
  if (group.budgets > 0) parts.push_back(fmt::format("{} budget", group.budgets));
  if (parts.empty()) return "0";
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace

std::string to_markdown(std::span<const GroupSummary> groups) {
  const bool show_config =
      !groups.empty() && std::any_of(groups.begin(), groups.end(), [&](const GroupSummary& group) {
        return group.config != groups.front().config;
      });
  std::vector<std::string> header{"suite", "instance", "method"};
  if (show_config) header.emplace_back("config");
  std::vector<std::vector<std::string>> labels;
  for (const GroupSummary& group : groups) {
    labels.push_back({group.suite, group.instance, group.method});
    if (show_config) labels.back().push_back(group.config);
  }
  return to_markdown(groups, header, labels);
}

std::string to_markdown(std::span<const GroupSummary> groups, const std::vector<std::string>& label_header,
                        const std::vector<std::vector<std::string>>& labels) {
  std::vector<std::string> header = label_header;
  for (const char* name : {"n", "falsified", "rate", "time median (s)", "time mean ± 95% CI (s)",
                           "time std", "nodes median", "nodes mean ± 95% CI", "nodes std", "stopped"})
    header.emplace_back(name);
  // STL requirements: robustness and simulation-equivalents, where some group has them.
  const bool stl = std::any_of(groups.begin(), groups.end(), [](const GroupSummary& g) { return g.has_requirement_data(); });
  if (stl)
    for (const char* name : {"robustness median", "simulations median (falsified)", "simulations mean (falsified)"})
      header.emplace_back(name);

  std::string table = markdown_row(header);
  std::vector<std::string> separator;
  for (std::size_t column = 0; column < header.size(); ++column)
    separator.emplace_back(column < label_header.size() ? "---" : "--:");  // numbers right
  table += markdown_row(separator);

  bool any_censored = false;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const GroupSummary& group = groups[i];
    const bool censored = is_censored(group);
    any_censored = any_censored || censored;
    std::vector<std::string> row;
    for (const std::string& label : labels[i]) row.push_back(markdown_cell(label));
    row.push_back(fmt::format("{}", group.n));
    row.push_back(fmt::format("{}", group.falsified));
    row.push_back(fmt::format("{:.2f}", group.falsified_rate));
    row.push_back(mark_censored(format_time(group.wall_s.median), censored));
    row.push_back(mark_censored(format_mean_with_ci(group.wall_s, format_time), censored));
    row.push_back(format_time(group.wall_s.stddev));
    row.push_back(mark_censored(format_count(group.nodes.median), censored));
    row.push_back(mark_censored(format_mean_with_ci(group.nodes, format_count), censored));
    row.push_back(format_count(group.nodes.stddev));  // a spread, not a bound: never marked
    row.push_back(stopped_trials_cell(group));
    if (stl) {
      row.push_back(format_time(group.robustness.median));
      row.push_back(format_time(group.simulations.median));
      row.push_back(format_time(group.simulations.mean));
    }
    table += markdown_row(row);
  }

  if (any_censored)
    table += fmt::format(
        "\n{} right-censored: the group has trials stopped by the time limit (⏱), the node cap "
        "or the method's budget, counted with the time and nodes they had when stopped, so the "
        "true value is at least this.\n",
        kAtLeast);
  return table;
}

std::string to_csv(std::span<const GroupSummary> groups) { return to_csv(groups, {}); }

std::string to_csv(std::span<const GroupSummary> groups, std::span<const GroupPlace> places) {
  return to_csv(groups, places, {}, {});
}

std::string to_csv(std::span<const GroupSummary> groups, std::span<const GroupPlace> places,
                   const std::vector<std::string>& extra_header, const std::vector<std::vector<std::string>>& extra) {
  constexpr std::string_view kLineEnd = "\r\n";
  std::string csv = places.empty() ? "" : "block,row,column,";
  csv +=
      "suite,instance,method,config,n,falsified,validated,falsified_rate,timeouts,node_caps,budgets,"
      "not_found,errors,time_mean_s,time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,"
      "nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high";
  const bool stl = std::any_of(groups.begin(), groups.end(), [](const GroupSummary& g) { return g.has_requirement_data(); });
  if (stl) csv += ",robustness_median,simulations_n,simulations_mean,simulations_median";
  for (const std::string& name : extra_header) csv += "," + csv_field(name);
  csv += kLineEnd;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const GroupSummary& group = groups[i];
    if (!places.empty())
      csv += fmt::format("{},{},{},", csv_field(places[i].block), csv_field(places[i].row), csv_field(places[i].column));
    const std::vector<std::string> fields{
        csv_field(group.suite),
        csv_field(group.instance),
        csv_field(group.method),
        csv_field(group.config),
        fmt::format("{}", group.n),
        fmt::format("{}", group.falsified),
        fmt::format("{}", group.validated),
        csv_number(group.falsified_rate),
        fmt::format("{}", group.timeouts),
        fmt::format("{}", group.node_caps),
        fmt::format("{}", group.budgets),
        fmt::format("{}", group.not_found),
        fmt::format("{}", group.errors),
        csv_number(group.wall_s.mean),
        csv_number(group.wall_s.median),
        csv_number(group.wall_s.stddev),
        csv_number(group.wall_s.ci_low),
        csv_number(group.wall_s.ci_high),
        csv_number(group.nodes.mean),
        csv_number(group.nodes.median),
        csv_number(group.nodes.stddev),
        csv_number(group.nodes.ci_low),
        csv_number(group.nodes.ci_high),
    };
    csv += fmt::format("{}", fmt::join(fields, ","));
    if (stl)
      csv += fmt::format(",{},{},{},{}", csv_number(group.robustness.median),
                         group.simulations.n, csv_number(group.simulations.mean), csv_number(group.simulations.median));
    if (i < extra.size())
      for (const std::string& field : extra[i]) csv += "," + csv_field(field);
    csv += kLineEnd;
  }
  return csv;
}

std::string_view to_string(GroupMeasure measure) {
  switch (measure) {
    case GroupMeasure::falsified_rate: return "falsified_rate";
    case GroupMeasure::time_mean_s: return "time_mean_s";
    case GroupMeasure::time_median_s: return "time_median_s";
    case GroupMeasure::nodes_mean: return "nodes_mean";
    case GroupMeasure::nodes_median: return "nodes_median";
  }
  return "?";
}

std::string to_markdown(std::span<const GroupSummary> groups, std::span<const GroupPlace> places,
                        GroupMeasure measure) {
  // Labels in order of first appearance.
  const auto first_seen = [&](std::string GroupPlace::*field) {
    std::vector<std::string> labels;
    for (const GroupPlace& p : places)
      if (std::find(labels.begin(), labels.end(), p.*field) == labels.end()) labels.push_back(p.*field);
    return labels;
  };
  const std::vector<std::string> blocks = first_seen(&GroupPlace::block), rows = first_seen(&GroupPlace::row),
                                 columns = first_seen(&GroupPlace::column);
  const auto cell = [&](const GroupSummary& g, bool& marked) {
    const bool censored = measure != GroupMeasure::falsified_rate && is_censored(g);
    marked = marked || censored;
    switch (measure) {
      case GroupMeasure::falsified_rate: return g.n == 0 ? std::string(kMissing) : fmt::format("{:.2f}", g.falsified_rate);
      case GroupMeasure::time_mean_s: return mark_censored(format_time(g.wall_s.mean), censored);
      case GroupMeasure::time_median_s: return mark_censored(format_time(g.wall_s.median), censored);
      case GroupMeasure::nodes_mean: return mark_censored(format_count(g.nodes.mean), censored);
      case GroupMeasure::nodes_median: return mark_censored(format_count(g.nodes.median), censored);
    }
    return std::string(kMissing);
  };
  std::string md;
  bool marked = false;
  for (const std::string& block : blocks) {
    if (!(blocks.size() == 1 && block.empty())) md += fmt::format("### {}\n\n", block);
    std::vector<std::string> header{markdown_cell(std::string(to_string(measure)))};
    for (const auto& c : columns) header.push_back(markdown_cell(c));
    md += markdown_row(header);
    std::vector<std::string> separator{"---"};
    separator.resize(header.size(), "--:");
    md += markdown_row(separator);
    for (const std::string& row : rows) {
      std::vector<std::string> line{markdown_cell(row)};
      bool any = false;
      for (const std::string& column : columns) {
        std::string text(kMissing);
        for (std::size_t i = 0; i < places.size() && i < groups.size(); ++i)
          if (places[i].block == block && places[i].row == row && places[i].column == column) {
            text = cell(groups[i], marked);
            any = true;
          }
        line.push_back(text);
      }
      if (any) md += markdown_row(line);
    }
    md += "\n";
  }
  if (marked)
    md += fmt::format("{} right-censored: the cell has trials stopped by the time limit, the node cap or the method's "
                      "budget, counted with the time and nodes they had when stopped, so the true value is at least this.\n",
                      kAtLeast);
  return md;
}

}  // namespace hyfal
