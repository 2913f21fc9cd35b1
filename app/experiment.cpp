#include "app/experiment.hpp"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/experiment_file.hpp"
#include "app/runner.hpp"
#include "results/statistics.hpp"
#include "results/table_writer.hpp"

namespace fs = std::filesystem;

namespace hyfal::cli {

int cmd_run_experiment(const ExperimentArgs& a) {
  check_output_path(a.db, "--db");
  check_output_path(a.witness_dir, "--witness-dir");
  check_output_path(a.out_dir, "--out-dir");
  const ExperimentFile e = load_experiment_file(read_input_file(a.file), a.file);
  RunOptions options;
  options.threads = a.threads;
  options.db = a.db;
  options.witness_dir = a.witness_dir;
  options.shard = shard_option(a.shard);
  options.plan = a.plan;
  options.progress = !a.quiet && isatty(STDERR_FILENO);
  options.quiet = a.quiet;
  options.save_trees = a.save_trees;
  check_directory_creatable(a.out_dir, "--out-dir");
  check_directory_creatable(a.witness_dir, "--witness-dir");

  // Resolve every group (instances built, methods checked against them) before the database opens.
  std::vector<TrialGroup> groups;
  groups.reserve(e.groups.size());
  for (const ExperimentGroup& g : e.groups) {
    TrialGroupSpec spec;
    spec.experiment = e.name;
    spec.suite = g.suite;
    spec.method = g.method;
    spec.settings = g.settings;
    spec.trials = e.trials;
    spec.timeout_s = e.timeout_s;
    spec.max_nodes = e.max_nodes;
    spec.seed = e.seed;
    try {
      groups.push_back(resolve_trial_group(spec));
    } catch (const std::invalid_argument& error) {  // OptionError
      throw UsageError(fmt::format("{}: {} on {}: {}", a.file, g.method_label, g.suite->name, error.what()));
    } catch (const UsageError& error) {
      throw UsageError(fmt::format("{}: {} on {}: {}", a.file, g.method_label, g.suite->name, error.what()));
    }
  }
  std::vector<const TrialGroup*> ordered;
  for (const TrialGroup& g : groups) ordered.push_back(&g);
  const auto run = run_groups(fmt::format("experiment {} ({})", e.name, a.file), ordered, options);
  if (!run) return 0;  // --plan

  std::vector<GroupSummary> summaries;
  std::vector<GroupPlace> places;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const std::vector<GroupSummary> s = summarize_trials(run->trials[i]);
    GroupSummary summary;
    if (s.empty()) {  // no trial in this process's share (--shard)
      summary.suite = groups[i].base.suite;
      summary.instance = groups[i].base.instance;
      summary.method = groups[i].base.method;
      summary.config = groups[i].base.config;
    } else {
      summary = s.front();
    }
    summaries.push_back(std::move(summary));
    places.push_back(e.groups[i].place);
  }
  std::string md = fmt::format("# {}\n\n", e.name);
  md += fmt::format("- file: {}; {} groups, {} trials each, timeout {} s, node cap {}, master seed {}\n", a.file,
                    groups.size(), e.trials, e.timeout_s, e.max_nodes, e.seed);
  md += fmt::format("- database: {} (experiment {}); host {}; git commit {}\n\n", a.db, e.name, run->engine.host,
                    run->engine.git_commit);
  md += fmt::format("## {} (rows: {}; columns: {}{}{})\n\n", to_string(e.value), fmt::join(e.rows, ", "),
                    fmt::join(e.columns, ", "), e.blocks.empty() ? "" : "; blocks: ", fmt::join(e.blocks, ", "));
  md += to_markdown(summaries, places, e.value);
  md += "\n## Groups\n\n" + to_markdown(summaries);
  const fs::path out_dir(a.out_dir);
  const std::string md_path = (out_dir / (e.name + ".md")).string(), csv_path = (out_dir / (e.name + ".csv")).string();
  write_file_atomic(md_path, md);
  write_file_atomic(csv_path, to_csv(summaries, places));
  std::cout << md << std::flush;
  if (!a.quiet)
    fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run->total, run->run_now,
               md_path, csv_path, a.db);
  return run->errors ? 1 : 0;
}

}  // namespace hyfal::cli
