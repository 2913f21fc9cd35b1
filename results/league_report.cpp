#include "results/league_report.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "results/experiment_report.hpp"
#include "results/text_format.hpp"

namespace hyfal {

namespace {

using namespace text;

LeagueCell make_cell(const std::vector<TrialRecord>& trials, double scale) {
  LeagueCell cell;
  cell.run = true;
  std::vector<double> simulations, nodes, wall, robustness;
  for (const TrialRecord& t : trials) {
    ++cell.n;
    switch (t.status) {
      case TrialStatus::falsified: ++cell.falsified; break;
      case TrialStatus::node_cap:  // the run's node cap: a budget too (ARCH-COMP counts none apart)
      case TrialStatus::budget: ++cell.budget_stops; break;
      case TrialStatus::timeout: ++cell.timeouts; break;
      case TrialStatus::not_found: ++cell.not_found; break;
      case TrialStatus::error: ++cell.errors; break;
    }
    if (t.validated) ++cell.validated;
    if (t.status == TrialStatus::error) continue;
    wall.push_back(t.wall_s);
    const std::vector<TrialRecord> one{t};
    const std::vector<double> sims = metric_values(one, "simulations");
    const std::vector<double> rob = metric_values(one, "robustness");
    if (!rob.empty() && std::isfinite(rob.front())) robustness.push_back(rob.front());
    if (t.status == TrialStatus::falsified && scale > 0.0 && !rob.empty() && std::abs(rob.front()) <= 0.01 * scale)
      ++cell.near_threshold;
    if (sims.empty()) continue;
    cell.observations.push_back({sims.front(), t.status != TrialStatus::falsified});
    if (t.status == TrialStatus::falsified) {
      simulations.push_back(sims.front());
      nodes.push_back(static_cast<double>(t.nodes));
    }
  }
  cell.simulations = summarize(simulations);
  cell.nodes = summarize(nodes);
  cell.wall_s = summarize(wall);
  cell.robustness = summarize(robustness);
  cell.falsified_indicators = falsified_indicators(trials);
  return cell;
}

// The row's leader: most falsified runs, ties to fewer mean simulations (then the earlier column).
LeagueRowVerdicts row_verdicts(const std::vector<LeagueCell>& row) {
  LeagueRowVerdicts v;
  for (std::size_t c = 0; c < row.size(); ++c) {
    if (!row[c].run || row[c].n == 0) continue;
    if (v.leader < 0) {
      v.leader = static_cast<std::ptrdiff_t>(c);
      continue;
    }
    const LeagueCell& best = row[static_cast<std::size_t>(v.leader)];
    const double mine = row[c].simulations.mean, theirs = best.simulations.mean;
    if (row[c].falsified > best.falsified || (row[c].falsified == best.falsified && row[c].falsified > 0 && mine < theirs))
      v.leader = static_cast<std::ptrdiff_t>(c);
  }
  v.against_leader.resize(row.size());
  if (v.leader >= 0 && row[static_cast<std::size_t>(v.leader)].falsified == 0) v.leader = -1;  // nobody falsified: no leader
  if (v.leader < 0) return v;
  const LeagueCell& best = row[static_cast<std::size_t>(v.leader)];
  for (std::size_t c = 0; c < row.size(); ++c) {
    if (static_cast<std::ptrdiff_t>(c) == v.leader || !row[c].run || !row[c].not_applicable.empty()) continue;
    v.against_leader[c].simulations = compare_samples(row[c].observations, best.observations);
    v.against_leader[c].rate = compare_samples(row[c].falsified_indicators, best.falsified_indicators);
  }
  return v;
}

std::string simulations_text(const SampleSummary& s) {
  return fmt::format("{} ({})", format_significant(s.mean), format_significant(s.median));
}

// "k/n · mean (median)" simulations, or "k/n" without a falsifying run.
std::string cell_text(const LeagueCell& cell) {
  if (!cell.run) return "not run";
  if (!cell.not_applicable.empty()) return "n/a";
  std::string text = fmt::format("{}/{}", cell.falsified, cell.n);
  if (cell.falsified > 0) text += " · " + simulations_text(cell.simulations);
  return text;
}

const PublishedCell* published_cell(const PublishedTool& tool, const std::string& row) {
  for (const PublishedCell& c : tool.cells)
    if (c.row == row) return &c;
  return nullptr;
}

std::string published_text(const PublishedCell* c) {
  if (!c) return std::string(kMissing);
  std::string text = fmt::format("{}/{}", c->falsified, c->runs);
  if (!std::isnan(c->mean_simulations) || !std::isnan(c->median_simulations))
    text += fmt::format(" · {} ({})", format_significant(c->mean_simulations), format_significant(c->median_simulations));
  if (!std::isnan(c->mean_s)) text += fmt::format(", {} s", format_significant(c->mean_s));
  return text;
}

std::string header_text(const LeagueReport& r, const ReportHeader& header) {
  std::string md = fmt::format("# {}: {}\n\n", r.id, r.title);
  md += fmt::format("- source: {}\n", r.source.empty() ? std::string(kMissing) : r.source);
  md += fmt::format("- profile: {}: {} runs per cell, {}, node cap {}, master seed {}; profile settings: {}\n",
                    header.profile, header.trials, timeout_text(header), header.max_nodes, header.seed,
                    settings_text(header.profile_settings));
  for (const auto& [label, settings] : header.column_settings)
    md += fmt::format("- column {} in this profile: {}\n", label, settings_text(settings));
  md += fmt::format("- experiment: {}\n", header.experiment);
  md += run_lines(header);
  md += notes_line(r.notes);
  return md;
}

std::string league_table(const LeagueReport& r) {
  std::string md =
      "\nCells: k/n runs falsified · mean (median) simulations of the falsifying runs (a tree's simulations are "
      "its simulated time over the requirement's horizon); **bold**: the row's leader (most falsified, then fewest "
      "mean simulations).\n\n";
  std::vector<std::string> head{"requirement", "suite"};
  for (const LeagueColumn& c : r.league.columns) head.push_back(markdown_cell(c.label));
  md += markdown_row(head) + markdown_separator(2, head.size());
  for (std::size_t i = 0; i < r.league.rows.size(); ++i) {
    if (r.cells[i].empty() || !r.cells[i].front().run) continue;
    std::vector<std::string> line{markdown_cell(r.league.rows[i].label), markdown_cell(r.league.rows[i].suite)};
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) {
      const std::string text = cell_text(r.cells[i][c]);
      line.push_back(static_cast<std::ptrdiff_t>(c) == r.verdicts[i].leader ? "**" + text + "**" : text);
    }
    md += markdown_row(line);
  }
  return md;
}

// The cells that do not apply, and why (each reason once, with its cells).
std::string not_applicable_lines(const LeagueReport& r) {
  std::vector<std::pair<std::string, std::vector<std::string>>> reasons;
  for (std::size_t i = 0; i < r.league.rows.size(); ++i)
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) {
      const LeagueCell& cell = r.cells[i][c];
      if (!cell.run || cell.not_applicable.empty()) continue;
      // The reason without its "method 'm' on suite 's': " prefix, so that a column's cells share it.
      const std::string& why = cell.not_applicable;
      const std::size_t colon = why.find("': ");
      const std::string reason = colon == std::string::npos ? why : why.substr(colon + 3);
      auto it = std::find_if(reasons.begin(), reasons.end(), [&](const auto& e) { return e.first == reason; });
      if (it == reasons.end()) it = reasons.insert(reasons.end(), {reason, {}});
      it->second.push_back(fmt::format("{} × {}", r.league.rows[i].label, r.league.columns[c].label));
    }
  if (reasons.empty()) return "";
  std::string md = "\nn/a: the column's method cannot drive the row's suite (no runs, in no verdict):\n";
  for (const auto& [reason, cells] : reasons) md += fmt::format("- {}: {}\n", fmt::join(cells, ", "), reason);
  return md;
}

std::string statistics_table(const LeagueReport& r) {
  std::string md =
      "\n## Statistics\n\nPer cell: runs, falsified, validated witnesses, stopped by the budget / the time limit, "
      "errors (a run whose witness the validator refused counts as an error, not as falsified); "
      "simulations of the falsifying runs (mean, median, std, 95 % CI); nodes of the falsifying runs (a tree's "
      "nodes, an optimiser's evaluations); mean wall time over the runs; median robustness (a falsifying run's "
      "witness's, else the lowest upper bound found).\n\n";
  const std::vector<std::string> head{"requirement", "method",         "n",           "falsified",  "validated",
                                      "budget",      "timeouts",       "errors",      "sims mean",   "sims median", "sims std",
                                      "sims 95 % CI", "nodes mean",    "time mean (s)", "robustness median"};
  md += markdown_row(head) + markdown_separator(2, head.size());
  for (std::size_t i = 0; i < r.league.rows.size(); ++i)
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) {
      const LeagueCell& cell = r.cells[i][c];
      if (!cell.run || !cell.not_applicable.empty()) continue;
      const SampleSummary& s = cell.simulations;
      md += markdown_row({markdown_cell(r.league.rows[i].label), markdown_cell(r.league.columns[c].label),
                          std::to_string(cell.n), std::to_string(cell.falsified), std::to_string(cell.validated),
                          std::to_string(cell.budget_stops), std::to_string(cell.timeouts), std::to_string(cell.errors),
                          format_significant(s.mean),
                          format_significant(s.median), format_significant(s.stddev),
                          std::isnan(s.ci_low) ? std::string(kMissing)
                                               : fmt::format("[{}, {}]", format_significant(s.ci_low),
                                                             format_significant(s.ci_high)),
                          format_significant(cell.nodes.mean), format_significant(cell.wall_s.mean),
                          format_significant(cell.robustness.median)});
    }
  return md;
}

// "more sims (p = 0.002), lower rate (p = 0.01)"; "within noise (sims p = 0.33, rate p = 1.0)".
std::string comparison_text(const LeagueComparison& c) {
  const auto part = [](const SampleComparison& s, ComparedMeasure m, std::string_view what) {
    if (s.order == SampleOrder::too_few_trials) return fmt::format("{}: too few runs", what);
    if (s.order == SampleOrder::within_noise) return std::string();
    return fmt::format("{} {} ({})", verdict_word(m, s.order), what, p_value_text(s.test.p_value, s.test.p_exact));
  };
  std::string sims = part(c.simulations, ComparedMeasure::nodes, "sims");
  std::string rate = part(c.rate, ComparedMeasure::falsified, "rate");
  if (sims.empty() && rate.empty())
    return fmt::format("within noise (sims {}, rate {})", p_value_text(c.simulations.test.p_value, c.simulations.test.p_exact),
                       p_value_text(c.rate.test.p_value, c.rate.test.p_exact));
  if (sims.empty()) return rate;
  if (rate.empty()) return sims;
  return sims + ", " + rate;
}

std::string verdict_lines(const LeagueReport& r) {
  std::string md = "\n## Verdicts\n\n";
  std::vector<std::string> head{"requirement", "leader"};
  for (const LeagueColumn& c : r.league.columns) head.push_back(markdown_cell(c.label));
  md += markdown_row(head) + markdown_separator(2, head.size());
  for (std::size_t i = 0; i < r.league.rows.size(); ++i) {
    if (r.cells[i].empty() || !r.cells[i].front().run) continue;
    const LeagueRowVerdicts& v = r.verdicts[i];
    std::vector<std::string> line{markdown_cell(r.league.rows[i].label),
                                  v.leader < 0 ? std::string(kMissing)
                                               : markdown_cell(r.league.columns[static_cast<std::size_t>(v.leader)].label)};
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) {
      if (static_cast<std::ptrdiff_t>(c) == v.leader) {
        line.emplace_back("leader");
        continue;
      }
      if (!r.cells[i][c].not_applicable.empty()) {
        line.emplace_back("n/a");
        continue;
      }
      if (v.leader < 0) {  // no run of the row falsified: nothing to compare against
        line.emplace_back(std::string(kMissing));
        continue;
      }
      line.push_back(comparison_text(v.against_leader[c]));
    }
    md += markdown_row(line);
  }
  md += fmt::format(
      "\nEach method against its row's leader, on the two cells' runs (two-sided, α = {:g}). Simulations: Gehan's "
      "generalized Wilcoxon test, a run that did not falsify counted as needing more than the simulations it ran "
      "(censored at the budget, or where the time limit stopped it); fewer / more: significantly below / above the "
      "leader. Rate: Fisher's exact test on falsified or not; lower / higher. within noise: not significant; p = "
      "exact permutation p-value.\n",
      kSignificanceLevel);
  return md;
}

// Per cell, how many witnesses lie within 1 % of the row's threshold scale (only where the rows'
// scales are known): ARCH-COMP re-simulates every falsifying input on the reference model, and a
// witness that close to 0 may not survive another simulator (the option `margin` asks for more).
std::string near_threshold_section(const LeagueReport& r) {
  bool any = false;
  for (std::size_t i = 0; i < r.cells.size(); ++i)
    any = any || (r.threshold_scale[i] > 0.0 && !r.cells[i].empty() && r.cells[i].front().run);
  if (!any) return "";
  std::string md = "\n## Witnesses near the threshold\n\nPer cell: of the falsifying runs, how many found a witness whose "
                   "robustness lies within 1 % of the requirement's threshold scale (its largest constant; e.g. AT2's "
                   "4750 rpm: 47.5), which a simulator a little off could refute; `margin` (a suite parameter) asks a "
                   "falsification to clear a margin. A requirement over signals of different units (AT6's rpm and "
                   "speed) gets its largest constant's scale: a crude measure there.\n\n| requirement | 1 % of the scale |";
  for (const LeagueColumn& c : r.league.columns) md += " " + c.label + " |";
  md += "\n| --- | --: |";
  for (std::size_t c = 0; c < r.league.columns.size(); ++c) md += " --: |";
  md += "\n";
  for (std::size_t i = 0; i < r.league.rows.size(); ++i) {
    if (r.cells[i].empty() || !r.cells[i].front().run || !(r.threshold_scale[i] > 0.0)) continue;
    md += fmt::format("| {} | {} |", r.league.rows[i].label, format_significant(0.01 * r.threshold_scale[i]));
    for (const LeagueCell& cell : r.cells[i])
      md += cell.not_applicable.empty() ? fmt::format(" {} of {} |", cell.near_threshold, cell.falsified) : " n/a |";
    md += "\n";
  }
  return md;
}

std::string published_section(const LeagueReport& r) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < r.league.rows.size(); ++i) {
    if (r.cells[i].empty() || !r.cells[i].front().run) continue;
    if (std::any_of(r.league.published.begin(), r.league.published.end(),
                    [&](const PublishedTool& t) { return published_cell(t, r.league.rows[i].label) != nullptr; }))
      rows.push_back(i);
  }
  if (rows.empty()) return "";
  std::string md =
      "\n## Published results beside ours\n\nTheirs: k/n · mean (median) simulations of the falsifying runs, mean "
      "seconds on their machine with Simulink where given; ours as in the league above, under this profile's "
      "settings. Their settings and sources are listed below the table.\n\n";
  std::vector<std::string> head{"requirement"};
  for (const LeagueColumn& c : r.league.columns) head.push_back(markdown_cell(c.label) + " (ours)");
  for (const PublishedTool& t : r.league.published) head.push_back(markdown_cell(t.label));
  md += markdown_row(head) + markdown_separator(1, head.size());
  for (const std::size_t i : rows) {
    std::vector<std::string> line{markdown_cell(r.league.rows[i].label)};
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) line.push_back(cell_text(r.cells[i][c]));
    for (const PublishedTool& t : r.league.published) line.push_back(published_text(published_cell(t, r.league.rows[i].label)));
    md += markdown_row(line);
  }
  md += "\n";
  for (const PublishedTool& t : r.league.published)
    md += fmt::format("- {}: {}; {}\n", t.label, t.settings, t.source);
  return md;
}

std::string verdict_word_or_empty(const SampleComparison& c, ComparedMeasure measure) {
  return std::string(verdict_word(measure, c.order));
}

std::string p_or_empty(const SampleComparison& c) {
  return c.order == SampleOrder::too_few_trials ? std::string() : csv_number(c.test.p_value);
}

}  // namespace

LeagueReport make_league_report(const PaperTable& table, const std::vector<std::vector<std::vector<TrialRecord>>>& trials,
                                const std::vector<bool>& run, const std::vector<double>& threshold_scale,
                                const std::vector<std::vector<std::string>>& not_applicable) {
  if (!table.league) throw std::invalid_argument("make_league_report: the table is not a league");
  const TableLeague& l = *table.league;
  if (trials.size() != l.rows.size() || run.size() != l.rows.size())
    throw std::invalid_argument("make_league_report: one list of cells per row expected");
  if (!threshold_scale.empty() && threshold_scale.size() != l.rows.size())
    throw std::invalid_argument("make_league_report: one threshold scale per row expected");
  if (!not_applicable.empty() && not_applicable.size() != l.rows.size())
    throw std::invalid_argument("make_league_report: one list of reasons per row expected");
  LeagueReport r{table.id, table.title, table.source, table.notes, l, {}, {}, {}};
  r.threshold_scale = threshold_scale.empty() ? std::vector<double>(l.rows.size(), 0.0) : threshold_scale;
  for (std::size_t i = 0; i < l.rows.size(); ++i) {
    if (trials[i].size() != l.columns.size())
      throw std::invalid_argument("make_league_report: one cell per column expected");
    std::vector<LeagueCell> row(l.columns.size());
    if (run[i])
      for (std::size_t c = 0; c < l.columns.size(); ++c) {
        row[c] = make_cell(trials[i][c], r.threshold_scale[i]);
        if (!not_applicable.empty()) {
          if (not_applicable[i].size() != l.columns.size())
            throw std::invalid_argument("make_league_report: one reason per column expected");
          row[c].not_applicable = not_applicable[i][c];
        }
      }
    r.verdicts.push_back(row_verdicts(row));
    r.cells.push_back(std::move(row));
  }
  return r;
}

std::string to_markdown(const LeagueReport& r, const ReportHeader& header) {
  return header_text(r, header) + league_table(r) + not_applicable_lines(r) + verdict_lines(r) + near_threshold_section(r) + published_section(r) +
         statistics_table(r);
}

std::string to_csv(const LeagueReport& r, const ReportHeader& header) {
  std::string csv =
      "table,profile,source,row,suite,column,method,n,falsified,validated,falsified_rate,budget_stops,timeouts,errors,"
      "simulations_mean,simulations_median,simulations_std,simulations_ci_low,simulations_ci_high,nodes_mean,"
      "time_mean_s,robustness_median,leader,simulations_verdict,simulations_p,rate_verdict,rate_p,near_threshold\r\n";
  for (std::size_t i = 0; i < r.league.rows.size(); ++i) {
    const LeagueRow& row = r.league.rows[i];
    if (r.cells[i].empty() || !r.cells[i].front().run) continue;
    const LeagueRowVerdicts& v = r.verdicts[i];
    for (std::size_t c = 0; c < r.league.columns.size(); ++c) {
      const LeagueCell& cell = r.cells[i][c];
      if (!cell.not_applicable.empty()) continue;  // no runs: no line
      const SampleSummary& s = cell.simulations;
      const bool leader = static_cast<std::ptrdiff_t>(c) == v.leader;
      const LeagueComparison& cmp = v.against_leader[c];
      csv += fmt::format("{},{},hyfal,{},{},{},{},{},{},{},{},{},{},{}", csv_field(r.id), csv_field(header.profile),
                         csv_field(row.label), csv_field(row.suite), csv_field(r.league.columns[c].label),
                         csv_field(r.league.columns[c].method), cell.n, cell.falsified, cell.validated,
                         csv_number(cell.n ? static_cast<double>(cell.falsified) / static_cast<double>(cell.n) : kNotReported),
                         cell.budget_stops, cell.timeouts, cell.errors);
      csv += fmt::format(",{},{},{},{},{},{},{},{}", csv_number(s.mean), csv_number(s.median), csv_number(s.stddev),
                         csv_number(s.ci_low), csv_number(s.ci_high), csv_number(cell.nodes.mean),
                         csv_number(cell.wall_s.mean), csv_number(cell.robustness.median));
      csv += fmt::format(",{},{},{},{},{},{}\r\n", leader ? "true" : "false",
                         leader || v.leader < 0 ? "" : verdict_word_or_empty(cmp.simulations, ComparedMeasure::nodes),
                         leader || v.leader < 0 ? "" : p_or_empty(cmp.simulations),
                         leader || v.leader < 0 ? "" : verdict_word_or_empty(cmp.rate, ComparedMeasure::falsified),
                         leader || v.leader < 0 ? "" : p_or_empty(cmp.rate),
                         r.threshold_scale[i] > 0.0 ? std::to_string(cell.near_threshold) : std::string());
    }
    for (const PublishedTool& t : r.league.published) {
      const PublishedCell* p = published_cell(t, row.label);
      if (!p) continue;
      csv += fmt::format("{},{},{},{},{},{},,{},{},,{},,,,{},{},,,,,{},,,,,,,\r\n", csv_field(r.id), csv_field(header.profile),
                         csv_field(t.label), csv_field(row.label), csv_field(row.suite), csv_field(t.label), p->runs,
                         p->falsified, csv_number(static_cast<double>(p->falsified) / p->runs),
                         csv_number(p->mean_simulations), csv_number(p->median_simulations), csv_number(p->mean_s));
    }
  }
  return csv;
}

}  // namespace hyfal
