#include "app/reproduce.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "app/experiment_file.hpp"
#include "app/plot.hpp"
#include "core/requirements/requirement.hpp"
#include "results/league_report.hpp"
#include "results/paper_report.hpp"
#include "results/sweep_report.hpp"
#include "results/text_format.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace fs = std::filesystem;

namespace hyfal::cli {

PaperTable find_table(const std::string& id_or_path) {
  const bool is_path = id_or_path.find('/') != std::string::npos ||
                       (id_or_path.size() >= 5 && id_or_path.compare(id_or_path.size() - 5, 5, ".toml") == 0);
  if (is_path) return load_paper_table(read_input_file(id_or_path), id_or_path);
  if (const PaperTable* t = find_builtin_paper_table(id_or_path)) return *t;
  throw UsageError(fmt::format("unknown table '{}' (see 'hyfal list'; a table file's path ends in .toml)", id_or_path));
}

// --- reproduce --------------------------------------------------------------------------------

namespace {

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec);
}

// A table's profiles: smoke, quick, full (optional) and paper (a league: published, optional).
std::string profile_names(const PaperTable& table) {
  std::string names = "smoke, quick";
  if (table.full) names += ", full";
  if (!table.league) names += ", paper";
  if (table.published) names += ", published";
  return names;
}

const TableProfile& profile_of(const PaperTable& table, const std::string& name) {
  const TableProfile* p = nullptr;
  if (name == "smoke") p = &table.smoke;
  if (name == "quick") p = &table.quick;
  if (name == "paper" && !table.league) p = &table.paper;
  if (name == "full" && table.full) p = &*table.full;
  if (name == "published" && table.published) p = &*table.published;
  if (p) return *p;
  if (name == "smoke" || name == "quick" || name == "full" || name == "paper" || name == "published")
    throw UsageError(fmt::format("--profile {}: table '{}' has no {} profile (it has {})", name, table.id, name,
                                 profile_names(table)));
  throw UsageError(fmt::format("--profile {}: expected one of {} (table '{}')", name, profile_names(table), table.id));
}

// A shard's table holds only what its database holds: until the shards are merged, a partial one.
void print_shard_note(const ReproduceArgs& a) {
  if (a.shard.empty()) return;
  fmt::print(stderr,
             "[hyfal] note: --shard {}: the table covers only the trials in {} (this shard and any stored before); "
             "merge the shard databases (hyfal merge merged.sqlite ...) and run 'hyfal reproduce {} --profile {} "
             "--db merged.sqlite' for the full table\n",
             a.shard, a.db, a.id, a.profile);
}

ReportHeader make_header(const ReproduceArgs& a, const TableProfile& profile, const EngineOptions& eo,
                         const std::string& experiment) {
  ReportHeader h;
  h.profile = a.profile;
  h.trials = profile.trials;
  h.timeout_s = profile.timeout_s;
  h.row_timeout_s = profile.row_timeout_s;
  h.skip_after_all_stopped = profile.skip_after_all_stopped;
  h.max_nodes = profile.max_nodes;
  h.profile_settings = profile.settings;
  h.column_settings = profile.column_settings;
  h.seed = a.seed;
  h.threads = a.threads > 0 ? a.threads : default_thread_count();
  h.host = eo.host;
  h.nproc = static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN));
  h.cpu_model = cpu_model_name();
  h.date_utc = utc_now();
  h.git_commit = eo.git_commit;
  h.experiment = experiment;
  return h;
}

void add_cpu_time(ReportHeader& header, const std::vector<TrialRecord>& trials) {
  for (const TrialRecord& t : trials) {
    header.cpu_s += t.cpu_s;
    ++header.trials_run;
  }
}

// Everything about where a reproduce writes, checked before anything is opened.
void check_reproduce_outputs(const ReproduceArgs& a, const std::string& experiment) {
  (void)shard_option(a.shard);  // a bad --shard is refused before anything is opened
  check_output_path(a.db, "--db");
  check_output_path(a.witness_dir, "--witness-dir");
  check_output_path(a.out_dir, "--out-dir");
  check_experiment_name(experiment);
  check_directory_creatable(a.out_dir, "--out-dir");
  check_directory_creatable(a.witness_dir, "--witness-dir");
}

// A sweep table: one trial group per (block, row, column, instance); all jobs in one pool.
int reproduce_sweep(const ReproduceArgs& a, const SuiteEntry* suite, const PaperTable& table,
                    const TableProfile& profile, const std::string& experiment) {
  const TableSweep& sw = *table.sweep;
  if (profile.instances < 1)
    throw UsageError(fmt::format("table '{}' profile '{}': instances must be >= 1", table.id, a.profile));
  const std::size_t blocks = sw.blocks.empty() ? 1 : sw.blocks.size();
  const std::size_t cols = sw.columns.size();
  const std::vector<bool> run = columns_run(sw, profile);
  struct Cell {
    std::size_t b, row, col;
    TrialGroup group;
  };
  std::vector<Cell> cells;
  for (std::size_t b = 0; b < blocks; ++b)
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const PaperRow& row = table.rows[r];
      const MethodEntry* method = find_method(row.method);
      if (!method)
        throw UsageError(fmt::format("table '{}' row '{}': method '{}' is not registered", table.id, row.label, row.method));
      for (std::size_t c = 0; c < cols; ++c)
        for (int k = 0; k < profile.instances && run[c]; ++k) {
          TrialGroupSpec spec;
          spec.experiment = experiment;
          spec.suite = suite;
          spec.method = method;
          spec.settings = profile.settings;  // then block, column, instance and row: later layers win
          if (!sw.blocks.empty()) overlay_settings(spec.settings, sw.blocks[b].settings);
          overlay_settings(spec.settings, sw.columns[c].settings);
          if (!sw.instance_key.empty()) overlay_settings(spec.settings, {{sw.instance_key, std::to_string(k)}});
          overlay_settings(spec.settings, row.settings);
          spec.trials = profile.trials;
          spec.timeout_s = profile.timeout_for(row.label);
          spec.max_nodes = profile.max_nodes;
          spec.seed = a.seed;
          // A sweep's columns grow (|Q| from 1^2 to 1024^2, N from 10 to 20): the later a column,
          // the longer its trials, so they start first and no rank is left with one at the end.
          spec.priority = static_cast<int>(c);
          try {
            cells.push_back({b, r, c, resolve_trial_group(spec)});
          } catch (const std::invalid_argument& e) {
            throw UsageError(fmt::format("table '{}' row '{}': {}", table.id, row.label, e.what()));
          }
        }
    }

  std::vector<std::vector<std::vector<std::vector<TrialRecord>>>> trials(
      blocks, std::vector<std::vector<std::vector<TrialRecord>>>(table.rows.size(),
                                                                 std::vector<std::vector<TrialRecord>>(cols)));
  const std::string what = fmt::format("table {} --profile {}", table.id, a.profile);
  RunOptions options = run_options_of(a);
  // Column waves (skip_after_all_stopped): a row's column runs only while every earlier column of
  // the row had a trial that was not stopped. A shard cannot know the other shards' outcomes, and
  // --plan sizes the whole table, so both take every cell.
  const bool waves = profile.skip_after_all_stopped && options.shard.whole() && !options.plan;
  std::optional<GroupsRun> run_info;
  std::size_t total = 0, run_now = 0, errors = 0;
  // Runs the cells `chosen` (indices into cells) and appends their stored trials to their cells,
  // one group per instance, in instance order.
  const auto run_cells = [&](std::vector<std::size_t> chosen) {
    // The largest columns first, so that the pool does not end waiting on one long trial.
    std::stable_sort(chosen.begin(), chosen.end(), [&](std::size_t x, std::size_t y) { return cells[x].col > cells[y].col; });
    std::vector<const TrialGroup*> ordered;
    for (const std::size_t i : chosen) ordered.push_back(&cells[i].group);
    run_info = run_groups(what, ordered, options);
    if (!run_info) return false;  // --plan
    total += run_info->total;
    run_now += run_info->run_now;
    errors += run_info->errors;
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const Cell& cell = cells[chosen[k]];
      auto& into = trials[cell.b][cell.row][cell.col];
      into.insert(into.end(), run_info->trials[k].begin(), run_info->trials[k].end());
    }
    return true;
  };
  if (!waves) {
    std::vector<std::size_t> all(cells.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    if (!run_cells(std::move(all))) return 0;
  } else {
    std::vector<std::vector<bool>> stopped(blocks, std::vector<bool>(table.rows.size(), false));
    for (std::size_t c = 0; c < cols; ++c) {
      std::vector<std::size_t> wave;
      for (std::size_t i = 0; i < cells.size(); ++i)
        if (cells[i].col == c && !stopped[cells[i].b][cells[i].row]) wave.push_back(i);
      if (wave.empty()) continue;  // a column the profile does not run, or every row stopped
      (void)run_cells(std::move(wave));
      options.quiet = true;  // one "resuming" note is enough
      for (std::size_t b = 0; b < blocks; ++b)
        for (std::size_t r = 0; r < table.rows.size(); ++r) {
          const auto& cell = trials[b][r][c];
          stopped[b][r] = stopped[b][r] || (!cell.empty() && std::all_of(cell.begin(), cell.end(), [](const TrialRecord& t) {
                                              return is_right_censored(t.status);
                                            }));
        }
    }
  }
  const EngineOptions& eo = run_info->engine;
  SweepReport report = make_sweep_report(table, trials, run, profile.skip_after_all_stopped);
  if (report.suite.empty()) report.suite = suite->name;
  ReportHeader header = make_header(a, profile, eo, experiment);
  for (const auto& block : trials)
    for (const auto& row : block)
      for (const auto& cell : row) add_cpu_time(header, cell);
  const std::string markdown = to_markdown(report, header);
  const fs::path out_dir(a.out_dir);
  write_file_atomic((out_dir / (table.id + ".md")).string(), markdown);
  write_file_atomic((out_dir / (table.id + ".csv")).string(), to_csv(report, header));
  std::cout << markdown << std::flush;
  fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", total, run_now,
             (out_dir / (table.id + ".md")).string(), (out_dir / (table.id + ".csv")).string(), a.db);
  write_table_figures(a.out_dir, table.id);
  print_shard_note(a);
  return errors ? 1 : 0;
}

// A league table: one trial group per (row run, column), each row its own suite instance; all
// cells in one pool, every method with the same runs, caps and profile settings.
int reproduce_league(const ReproduceArgs& a, const PaperTable& table, const TableProfile& profile,
                     const std::string& experiment) {
  const TableLeague& l = *table.league;
  std::vector<bool> run(l.rows.size());
  for (std::size_t i = 0; i < l.rows.size(); ++i)
    run[i] = profile.row_labels.empty() ||
             std::find(profile.row_labels.begin(), profile.row_labels.end(), l.rows[i].label) != profile.row_labels.end();
  std::vector<TrialGroup> groups;
  std::vector<std::pair<std::size_t, std::size_t>> places;  // (row, column) of groups[k]
  // Why a column's method cannot drive a row's suite (a cell that does not apply: "n/a").
  std::vector<std::vector<std::string>> not_applicable(l.rows.size(), std::vector<std::string>(l.columns.size()));
  for (std::size_t i = 0; i < l.rows.size(); ++i) {
    if (!run[i]) continue;
    const SuiteEntry* suite = find_suite(l.rows[i].suite);
    if (!suite) throw UsageError(fmt::format("table '{}' row '{}': unknown suite '{}'", table.id, l.rows[i].label, l.rows[i].suite));
    for (std::size_t c = 0; c < l.columns.size(); ++c) {
      const MethodEntry* method = find_method(l.columns[c].method);
      if (!method)
        throw UsageError(fmt::format("table '{}' column '{}': method '{}' is not registered", table.id,
                                     l.columns[c].label, l.columns[c].method));
      TrialGroupSpec spec;
      spec.experiment = experiment;
      spec.suite = suite;
      spec.method = method;
      spec.settings = profile.settings;  // then the row's (the instance) and the column's (the method)
      overlay_settings(spec.settings, l.rows[i].settings);
      overlay_settings(spec.settings, l.columns[c].settings);
      for (const auto& [label, settings] : profile.column_settings)
        if (label == l.columns[c].label) overlay_settings(spec.settings, settings);
      spec.trials = profile.trials;
      spec.timeout_s = profile.timeout_s;
      spec.max_nodes = profile.max_nodes;
      spec.seed = a.seed;
      try {
        groups.push_back(resolve_trial_group(spec));
      } catch (const MethodNotApplicable& e) {
        not_applicable[i][c] = e.what();
        continue;
      } catch (const std::invalid_argument& e) {
        throw UsageError(fmt::format("table '{}' cell '{}' x '{}': {}", table.id, l.rows[i].label, l.columns[c].label, e.what()));
      }
      places.emplace_back(i, c);
    }
  }
  std::vector<const TrialGroup*> ordered;
  for (const TrialGroup& g : groups) ordered.push_back(&g);
  auto run_info = run_groups(fmt::format("table {} --profile {}", table.id, a.profile), ordered, run_options_of(a));
  if (!run_info) return 0;  // --plan
  std::vector<std::vector<std::vector<TrialRecord>>> trials(l.rows.size(),
                                                            std::vector<std::vector<TrialRecord>>(l.columns.size()));
  for (std::size_t k = 0; k < groups.size(); ++k) trials[places[k].first][places[k].second] = run_info->trials[k];
  // Each row's threshold scale, from its requirement (any of its cells' systems: they share it).
  std::vector<double> scales(l.rows.size(), 0.0);
  for (std::size_t k = 0; k < groups.size(); ++k)
    if (const auto& requirement = groups[k].system->info().requirement)
      scales[places[k].first] = stl::threshold_scale(requirement->formula);
  const LeagueReport report = make_league_report(table, trials, run, scales, not_applicable);
  ReportHeader header = make_header(a, profile, run_info->engine, experiment);
  for (const auto& cells : run_info->trials) add_cpu_time(header, cells);
  const std::string markdown = to_markdown(report, header);
  const fs::path out_dir(a.out_dir);
  write_file_atomic((out_dir / (table.id + ".md")).string(), markdown);
  write_file_atomic((out_dir / (table.id + ".csv")).string(), to_csv(report, header));
  std::cout << markdown << std::flush;
  fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run_info->total, run_info->run_now,
             (out_dir / (table.id + ".md")).string(), (out_dir / (table.id + ".csv")).string(), a.db);
  write_table_figures(a.out_dir, table.id);
  print_shard_note(a);
  return run_info->errors ? 1 : 0;
}

}  // namespace

int cmd_reproduce(const ReproduceArgs& a) {
  // Everything is checked before the database is opened, so a bad input writes nothing.
  const PaperTable loaded = find_table(a.id);
  const PaperTable* table = &loaded;
  if (table->league) {
    const TableProfile& profile = profile_of(*table, a.profile);
    const std::string experiment = fmt::format("{}/{}", table->id, a.profile);
    check_reproduce_outputs(a, experiment);
    return reproduce_league(a, *table, profile, experiment);
  }
  const SuiteEntry* suite = find_suite(table->suite);
  if (!suite) throw UsageError(fmt::format("table '{}': unknown suite '{}'", table->id, table->suite));
  const TableProfile& profile = profile_of(*table, a.profile);
  if (profile.trials < 1 || !(profile.timeout_s > 0.0) || profile.max_nodes < 1)
    throw UsageError(fmt::format("table '{}' profile '{}': trials, timeout and max_nodes must be positive",
                                 table->id, a.profile));
  if (table->rows.empty()) throw UsageError(fmt::format("table '{}' has no rows", table->id));
  const std::string experiment = fmt::format("{}/{}", table->id, a.profile);
  check_reproduce_outputs(a, experiment);
  if (table->sweep) return reproduce_sweep(a, suite, *table, profile, experiment);

  std::vector<TrialGroup> groups;
  for (const PaperRow& row : table->rows) {
    const MethodEntry* method = find_method(row.method);
    if (!method)
      throw UsageError(fmt::format("table '{}' row '{}': method '{}' is not registered (see 'hyfal list')",
                                   table->id, row.label, row.method));
    TrialGroupSpec spec;
    spec.experiment = experiment;
    spec.suite = suite;
    spec.method = method;
    spec.settings = profile.settings;  // then the row's own, which wins
    overlay_settings(spec.settings, row.settings);
    spec.trials = profile.trials;
    spec.timeout_s = profile.timeout_for(row.label);
    spec.max_nodes = profile.max_nodes;
    spec.seed = a.seed;
    try {
      groups.push_back(resolve_trial_group(spec));
    } catch (const std::invalid_argument& e) {  // an InputError, or a suite's own refusal
      throw UsageError(fmt::format("table '{}' row '{}': {}", table->id, row.label, e.what()));
    }
  }

  std::vector<const TrialGroup*> ordered;
  for (const TrialGroup& g : groups) ordered.push_back(&g);
  auto run_info =
      run_groups(fmt::format("table {} --profile {}", table->id, a.profile), ordered, run_options_of(a));
  if (!run_info) return 0;  // --plan
  const EngineOptions& eo = run_info->engine;
  const std::vector<std::vector<TrialRecord>>& rows_trials = run_info->trials;

  PaperReport report = make_paper_report(*table, rows_trials);
  if (report.suite.empty()) report.suite = suite->name;
  ReportHeader header = make_header(a, profile, eo, experiment);
  for (const auto& row : rows_trials) add_cpu_time(header, row);

  const std::string markdown = to_markdown(report, header);
  const fs::path out_dir(a.out_dir);
  write_file_atomic((out_dir / (table->id + ".md")).string(), markdown);
  write_file_atomic((out_dir / (table->id + ".csv")).string(), to_csv(report, header));
  for (const std::string& name : table->series) {  // per-trial series, e.g. Fig. 6's sorted n_j
    std::string csv = "row,trial_index,x,y\r\n";
    for (std::size_t r = 0; r < groups.size(); ++r)
      for (const TrialRecord& record : rows_trials[r])
        for (const auto& [x, y] : run_info->store.series_of(record.key, name))
          csv += fmt::format("{},{},{},{}\r\n", text::csv_field(table->rows[r].label), record.key.trial_index,
                             text::csv_number(x), text::csv_number(y));
    std::string file = name;  // a series name may hold '/', e.g. "coverage/tree0"
    std::replace(file.begin(), file.end(), '/', '-');
    write_file_atomic((out_dir / (table->id + "-" + file + ".csv")).string(), csv);
  }
  std::cout << markdown << std::flush;
  fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run_info->total,
             run_info->run_now, (out_dir / (table->id + ".md")).string(), (out_dir / (table->id + ".csv")).string(), a.db);
  write_table_figures(a.out_dir, table->id);
  print_shard_note(a);
  return run_info->errors ? 1 : 0;
}

}  // namespace hyfal::cli
