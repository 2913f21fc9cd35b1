#include "results/sweep_report.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "results/statistics.hpp"
#include "results/text_format.hpp"

namespace hyfal {
namespace {

using namespace text;

std::string paper_text(double v) {
  if (std::isnan(v)) return "N/A";
  if (std::isinf(v)) return "X";
  return fmt::format("{}", v);
}

// Ours: the mean time; "X" when every trial was stopped (the paper's mark for a timeout), "≥"
// when some were (a lower bound); "[k/n]" when not every trial falsified.
std::string ours_text(const SweepCell& c) {
  if (!c.run) return "";
  if (c.skipped) return "X (skipped)";
  if (c.n == 0) return std::string(kMissing);
  std::string s;
  if (c.all_stopped())
    s = fmt::format("X (≥{})", format_significant(c.value));
  else
    s = fmt::format("{}{}", c.censored() ? "≥" : "", format_significant(c.value));
  if (c.falsified < c.n) s += fmt::format(" [{}/{}]", c.falsified, c.n);
  return s;
}

std::string separator(std::size_t text_columns, std::size_t columns) {
  std::vector<std::string> sep;
  for (std::size_t c = 0; c < columns; ++c) sep.emplace_back(c < text_columns ? "---" : "--:");
  return markdown_row(sep);
}


}  // namespace

SweepReport make_sweep_report(const PaperTable& table,
                              const std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>& trials,
                              int columns_run, bool skip_after_all_stopped) {
  if (!table.sweep) throw std::invalid_argument("make_sweep_report: the table is not a sweep");
  TableProfile first;
  first.columns = columns_run;
  return make_sweep_report(table, trials, hyfal::columns_run(*table.sweep, first), skip_after_all_stopped);
}

SweepReport make_sweep_report(const PaperTable& table,
                              const std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>& trials,
                              const std::vector<bool>& run, bool skip_after_all_stopped) {
  if (!table.sweep) throw std::invalid_argument("make_sweep_report: the table is not a sweep");
  const TableSweep& sw = *table.sweep;
  const std::size_t blocks = sw.blocks.empty() ? 1 : sw.blocks.size();
  const std::size_t cols = sw.columns.size();
  if (run.size() != cols) throw std::invalid_argument("make_sweep_report: one run flag per column expected");
  if (trials.size() != blocks) throw std::invalid_argument("make_sweep_report: one trial set per block expected");
  SweepReport r;
  r.id = table.id;
  r.title = table.title;
  r.source = table.source;
  r.suite = table.suite;
  r.notes = table.notes;
  r.paper_timeout_s = sw.paper_timeout_s;
  r.median = sw.median;
  for (const PaperRow& row : table.rows) {
    r.rows.push_back(row.label);
    r.methods.push_back(row.method);
  }
  for (const SweepValue& c : sw.columns) r.columns.push_back(c.label);
  if (sw.blocks.empty())
    r.blocks.push_back("");
  else
    for (const SweepValue& b : sw.blocks) r.blocks.push_back(b.label);
  r.cells.assign(blocks, std::vector<std::vector<SweepCell>>(table.rows.size(), std::vector<SweepCell>(cols)));
  r.orderings.assign(blocks, {});
  for (std::size_t b = 0; b < blocks; ++b) {
    if (trials[b].size() != table.rows.size()) throw std::invalid_argument("make_sweep_report: one trial set per row expected");
    for (std::size_t i = 0; i < table.rows.size(); ++i) {
      if (trials[b][i].size() != cols) throw std::invalid_argument("make_sweep_report: one trial set per column expected");
      for (std::size_t c = 0; c < cols; ++c) {
        SweepCell& cell = r.cells[b][i][c];
        if (b < sw.paper.size() && i < sw.paper[b].size() && c < sw.paper[b][i].size()) cell.paper = sw.paper[b][i][c];
        cell.run = run[c];
        std::vector<double> times, nodes;
        for (const TrialRecord& t : trials[b][i][c]) {
          ++cell.n;
          switch (t.status) {
            case TrialStatus::falsified: ++cell.falsified; break;
            case TrialStatus::timeout: ++cell.timeouts; break;
            case TrialStatus::node_cap:
            case TrialStatus::budget: ++cell.node_caps; break;  // a cap either way: stopped, censored
            case TrialStatus::not_found: ++cell.not_found; break;
            case TrialStatus::error: ++cell.errors; break;
          }
          if (t.status != TrialStatus::error) {
            times.push_back(t.wall_s);
            nodes.push_back(static_cast<double>(t.nodes));
          }
        }
        cell.wall_s = summarize(times);
        cell.nodes = summarize(nodes);
        cell.observations = censored_sample(trials[b][i][c], TrialMeasure::wall_s);
        cell.mean_s = cell.wall_s.mean;
        cell.median_s = cell.wall_s.median;
        cell.value = sw.median ? cell.median_s : cell.mean_s;
        // Not run because an earlier column of the row was all stopped (skip_after_all_stopped).
        cell.skipped = skip_after_all_stopped && cell.run && cell.n == 0 &&
                       std::any_of(r.cells[b][i].begin(), r.cells[b][i].begin() + static_cast<std::ptrdiff_t>(c),
                                   [](const SweepCell& earlier) { return earlier.all_stopped() || earlier.skipped; });
      }
    }
    // Orderings per run column: the paper's "X" counts as its time limit (two X's tie), ours are
    // the cells' censored times.
    for (std::size_t c = 0; c < cols; ++c) {
      if (!run[c]) continue;
      std::vector<double> paper, ours;
      std::vector<std::vector<CensoredValue>> samples;
      for (std::size_t i = 0; i < table.rows.size(); ++i) {
        const SweepCell& cell = r.cells[b][i][c];
        paper.push_back(std::isinf(cell.paper) ? sw.paper_timeout_s : cell.paper);
        ours.push_back(cell.value);
        samples.push_back(cell.observations);
      }
      OrderingCheck check = check_ordering(paper, ours, samples, c);
      // A skipped cell has no trials: say why rather than "no value" (the row's X at our cap, in
      // an earlier column, says nothing about a time beyond that cap).
      std::vector<std::string> skipped;
      for (std::size_t i = 0; i < table.rows.size(); ++i)
        if (r.cells[b][i][c].skipped) skipped.push_back(table.rows[i].label);
      if (check.verdict == OrderingVerdict::not_checked && !skipped.empty() &&
          check.why_not_checked.find("has no value of ours") != std::string::npos)
        check.why_not_checked = fmt::format(
            "{} X (skipped): not run after a column where every trial reached its cap", fmt::join(skipped, ", "));
      r.orderings[b].push_back(std::move(check));
    }
  }
  return r;
}

namespace {

// Whether block b (or, with b = npos, any block) has a number of the paper's: a table of our own
// (no paper numbers) leaves out the paper's side rather than print a table of N/A.
bool has_paper_numbers(const SweepReport& r, std::size_t b = std::string::npos) {
  for (std::size_t k = 0; k < r.cells.size(); ++k)
    if (b == std::string::npos || k == b)
      for (const auto& row : r.cells[k])
        for (const SweepCell& cell : row)
          if (!std::isnan(cell.paper)) return true;
  return false;
}

std::string header_text(const SweepReport& r, const ReportHeader& header) {
  std::string md = fmt::format("# {}: {}\n\n", r.id, r.title);
  md += fmt::format("- source: {}\n", r.source.empty() ? std::string(kMissing) : r.source);
  md += fmt::format("- profile: {}: {} trial(s) per instance, {}, node cap {}, master seed {}; profile settings: {}{}\n",
                    header.profile, header.trials, timeout_text(header), header.max_nodes, header.seed,
                    settings_text(header.profile_settings),
                    header.skip_after_all_stopped
                        ? "; a row's columns after one where every trial was stopped are not run (X (skipped))"
                        : "");
  md += fmt::format("- suite: {}; experiment: {}\n", r.suite.empty() ? std::string(kMissing) : r.suite, header.experiment);
  md += run_lines(header);
  md += notes_line(r.notes);
  return md;
}

std::string cells_legend(const SweepReport& r, const ReportHeader& header) {
  return fmt::format(
      "\nCells: {} wall time in seconds over the cell's trials (one per instance). X: every trial was stopped by "
      "the time limit or node cap (ours: ≥ the time they ran); ≥: some were, so the value is a lower bound; "
      "[k/n]: k of n trials falsified.{}{}\n",
      r.median ? "median" : "mean",
      header.skip_after_all_stopped
          ? " X (skipped): not run, because in an earlier column of the row every trial was stopped."
          : "",
      has_paper_numbers(r) ? fmt::format(" Paper: X = timeout at {} s.", r.paper_timeout_s) : "");
}

// The columns the profile ran, in order.
std::vector<std::size_t> run_columns(const SweepReport& r) {
  std::vector<std::size_t> run;
  for (std::size_t c = 0; c < r.columns.size(); ++c)
    if (!r.cells.empty() && !r.cells[0].empty() && r.cells[0][0][c].run) run.push_back(c);
  return run;
}

// "ours" (the columns run) and, where the block has the paper's numbers, "paper" (every column).
std::string cell_tables(const SweepReport& r, std::size_t b, const std::vector<std::size_t>& run) {
  std::vector<std::size_t> all(r.columns.size());
  for (std::size_t c = 0; c < all.size(); ++c) all[c] = c;
  std::string md;
  for (const bool ours : {true, false}) {
    if (!ours && !has_paper_numbers(r, b)) break;
    md += ours ? "\nours\n\n" : "\npaper\n\n";
    std::vector<std::string> head{"method"};
    const std::vector<std::size_t>& shown = ours ? run : all;
    for (const std::size_t c : shown) head.push_back(markdown_cell(r.columns[c]));
    md += markdown_row(head);
    md += separator(1, head.size());
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
      std::vector<std::string> line{markdown_cell(r.rows[i])};
      for (const std::size_t c : shown)
        line.push_back(ours ? ours_text(r.cells[b][i][c]) : paper_text(r.cells[b][i][c].paper));
      md += markdown_row(line);
    }
  }
  return md;
}

// The first claim a scaling table makes: who is fastest per column (the paper's beside ours where
// the block has the paper's numbers).
std::string fastest_line(const SweepReport& r, std::size_t b, const std::vector<std::size_t>& run) {
  const bool paper = has_paper_numbers(r, b);
  std::string md = paper ? "\nfastest per column (paper / ours):" : "\nfastest per column (ours):";
  std::size_t agree = 0;
  for (const std::size_t c : run) {
    std::size_t pb = r.rows.size(), ob = r.rows.size();
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
      const SweepCell& x = r.cells[b][i][c];
      if (!std::isnan(x.paper) && (pb == r.rows.size() || x.paper < r.cells[b][pb][c].paper)) pb = i;
      const bool ok = x.n > 0 && !x.all_stopped();
      if (ok && (ob == r.rows.size() || x.value < r.cells[b][ob][c].value)) ob = i;
    }
    const std::string ps = pb < r.rows.size() ? r.rows[pb] : "–", os = ob < r.rows.size() ? r.rows[ob] : "none";
    agree += ps == os ? 1 : 0;
    md += paper ? fmt::format(" {} {} / {};", r.columns[c], ps, os) : fmt::format(" {} {};", r.columns[c], os);
  }
  if (paper) return md + fmt::format(" the same in {} of {} columns.\n", agree, run.size());
  md.back() = '.';
  return md + "\n";
}

// The second claim: where each method first times out everywhere (the paper's first X; ours:
// every trial stopped), and which columns ours cover.
std::string first_stopped_line(const SweepReport& r, std::size_t b, const std::vector<std::size_t>& run) {
  const bool paper = has_paper_numbers(r, b);
  std::string md = paper ? "\nfirst column where every trial timed out (paper X / ours X):"
                         : "\nfirst column where every trial timed out (ours X):";
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    std::string px = "none", ox = "none";
    for (std::size_t c = 0; c < r.columns.size(); ++c)
      if (std::isinf(r.cells[b][i][c].paper)) {
        px = r.columns[c];
        break;
      }
    for (const std::size_t c : run)
      if (r.cells[b][i][c].all_stopped() || r.cells[b][i][c].skipped) {
        ox = r.columns[c];
        break;
      }
    md += paper ? fmt::format(" {} {} / {};", r.rows[i], px, ox) : fmt::format(" {} {};", r.rows[i], ox);
  }
  bool prefix = true;  // the run columns are the first ones
  for (std::size_t k = 0; k < run.size(); ++k) prefix = prefix && run[k] == k;
  if (run.empty()) return md + " (ours: no column).\n";
  if (prefix) return md + fmt::format(" (ours only up to {}).\n", r.columns[run.back()]);
  std::vector<std::string> labels;
  for (const std::size_t c : run) labels.push_back(r.columns[c]);
  return md + fmt::format(" (ours only in {}).\n", fmt::join(labels, ", "));
}

std::string statistics_table(const SweepReport& r, std::size_t b, const std::vector<std::size_t>& run) {
  std::string md = "\nstatistics per cell (time in seconds; ≥: the cell has stopped trials, so mean and median are "
                   "lower bounds):\n\n";
  md += markdown_row({"method", "column", "n", "falsified", "stopped", "time mean", "time median", "time std",
                      "time 95% CI", "nodes mean", "nodes median", "nodes std", "nodes 95% CI"});
  md += separator(2, 13);
  for (std::size_t i = 0; i < r.rows.size(); ++i)
    for (const std::size_t c : run) {
      const SweepCell& x = r.cells[b][i][c];
      const auto bound = [&](std::string text) { return x.censored() && text != kMissing ? "≥" + text : text; };
      const auto interval = [&](const SampleSummary& s, auto format) {
        if (std::isnan(s.ci_low)) return std::string(kMissing);
        return bound(fmt::format("[{}, {}]", format(s.ci_low), format(s.ci_high)));
      };
      const auto time = [](double v) { return format_significant(v); };
      const auto count = [](double v) { return std::isnan(v) ? std::string(kMissing) : fmt::format("{:.0f}", v); };
      md += markdown_row({markdown_cell(r.rows[i]), markdown_cell(r.columns[c]), fmt::format("{}", x.n),
                          fmt::format("{}", x.falsified), fmt::format("{}", x.timeouts + x.node_caps),
                          bound(time(x.wall_s.mean)), bound(time(x.wall_s.median)), time(x.wall_s.stddev),
                          interval(x.wall_s, time), bound(count(x.nodes.mean)), bound(count(x.nodes.median)),
                          count(x.nodes.stddev), interval(x.nodes, count)});
    }
  return md;
}

// One line per run column: the paper's order, ours, and the verdicts of the paper's adjacent pairs.
std::string ordering_lines(const SweepReport& r, std::size_t b) {
  std::string md = "\nordering per column (ascending time; paper X = its time limit, two X's tie; ours ≈: not "
                   "significantly different from the row before; each adjacent pair of the paper's order tested, see "
                   "below):\n\n";
  for (const OrderingCheck& check : r.orderings[b]) {
    auto order = [&](const std::vector<std::size_t>& o, const std::vector<bool>& tied, std::string_view tie_mark) {
      std::string s;
      for (std::size_t k = 0; k < o.size(); ++k) {
        if (k > 0) s += tied[k] ? tie_mark : " < ";
        s += r.rows[o[k]];
      }
      return s.empty() ? std::string(kMissing) : s;
    };
    md += fmt::format("- {}: paper {} — ours {} — ", r.columns[check.column],
                      order(check.paper_order, check.paper_tied_with_previous, " = "),
                      order(check.ours_order, check.ours_tied_with_previous, " ≈ "));
    if (check.verdict == OrderingVerdict::not_checked)
      md += fmt::format("not checked ({})\n", check.why_not_checked);
    else
      md += fmt::format("{} — {}: {}\n", pairs_text(check, r.rows), to_string(check.verdict),
                        verdict_counts_text({&check}));
  }
  return md;
}

std::string verdict_summary(const SweepReport& r) {
  std::vector<const OrderingCheck*> checked;
  for (const auto& block : r.orderings)
    for (const OrderingCheck& check : block)
      if (check.verdict != OrderingVerdict::not_checked) checked.push_back(&check);
  return fmt::format("\nSummary over the table's adjacent pairs: {}.\n\n", verdict_counts_text(checked)) +
         ordering_method_text();
}

}  // namespace

std::string to_markdown(const SweepReport& r, const ReportHeader& header) {
  std::string md = header_text(r, header) + cells_legend(r, header);
  const std::vector<std::size_t> run = run_columns(r);
  for (std::size_t b = 0; b < r.blocks.size(); ++b) {
    if (!r.blocks[b].empty()) md += fmt::format("\n## {}\n", r.blocks[b]);
    md += cell_tables(r, b, run) + fastest_line(r, b, run) + first_stopped_line(r, b, run) +
          statistics_table(r, b, run);
    // Orderings test the paper's claims: none where the paper has no numbers.
    if (has_paper_numbers(r, b)) md += ordering_lines(r, b);
  }
  if (has_paper_numbers(r)) md += verdict_summary(r);
  return md;
}

std::string to_csv(const SweepReport& r, const ReportHeader& header) {
  std::string csv = "table,profile,block,row,method,column,paper,ours_mean,ours_median,n,falsified,falsified_rate,"
                    "timeouts,errors,time_std_s,time_ci_low_s,time_ci_high_s,nodes_mean,nodes_median,nodes_std,"
                    "nodes_ci_low,nodes_ci_high,paper_previous,verdict,p_value,skipped,statistic\r\n";
  for (std::size_t b = 0; b < r.blocks.size(); ++b)
    for (std::size_t i = 0; i < r.rows.size(); ++i)
      for (std::size_t c = 0; c < r.columns.size(); ++c) {
        const SweepCell& cell = r.cells[b][i][c];
        if (!cell.run) continue;
        const double rate = cell.n ? static_cast<double>(cell.falsified) / static_cast<double>(cell.n) : kNotReported;
        const OrderedPair* pair =
            b < r.orderings.size() && c < r.orderings[b].size() ? r.orderings[b][c].pair_ending_at(i) : nullptr;
        csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}", csv_field(r.id), csv_field(header.profile),
                           csv_field(r.blocks[b]), csv_field(r.rows[i]), csv_field(r.methods[i]),
                           csv_field(r.columns[c]), std::isinf(cell.paper) ? std::string("X") : csv_number(cell.paper),
                           csv_number(cell.mean_s), csv_number(cell.median_s), cell.n, cell.falsified,
                           csv_number(rate), cell.timeouts + cell.node_caps, cell.errors);
        csv += fmt::format(",{},{},{},{},{},{},{},{}", csv_number(cell.wall_s.stddev), csv_number(cell.wall_s.ci_low),
                           csv_number(cell.wall_s.ci_high), csv_number(cell.nodes.mean), csv_number(cell.nodes.median),
                           csv_number(cell.nodes.stddev), csv_number(cell.nodes.ci_low), csv_number(cell.nodes.ci_high));
        csv += fmt::format(",{},{},{},{},{}\r\n", pair ? csv_field(r.rows[pair->first]) : std::string(),
                           pair ? csv_field(to_string(pair->verdict)) : std::string(),
                           pair && pair->verdict != OrderingVerdict::too_few_trials ? csv_number(pair->test.p_value)
                                                                                    : std::string(),
                           cell.skipped ? "true" : "false", r.median ? "median" : "mean");
      }
  return csv;
}

}  // namespace hyfal
