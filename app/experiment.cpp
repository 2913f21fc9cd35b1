#include "app/experiment.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/experiment_file.hpp"
#include "app/plot.hpp"
#include "app/runner.hpp"
#include "core/run/option_spec.hpp"
#include "results/experiment_report.hpp"
#include "results/statistics.hpp"
#include "results/table_writer.hpp"

namespace fs = std::filesystem;

namespace hyfal::cli {
namespace {

// One summary per group, in group order (a group without a trial in this process's share,
// --shard, keeps its keys and no statistics).
std::vector<GroupSummary> group_summaries(const std::vector<TrialGroup>& groups,
                                          const std::vector<std::vector<TrialRecord>>& trials) {
  std::vector<GroupSummary> summaries;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const std::vector<GroupSummary> s = summarize_trials(trials[i]);
    GroupSummary summary;
    if (s.empty()) {
      summary.suite = groups[i].base.suite;
      summary.instance = groups[i].base.instance;
      summary.method = groups[i].base.method;
      summary.config = groups[i].base.config;
    } else {
      summary = s.front();
    }
    summaries.push_back(std::move(summary));
  }
  return summaries;
}

const OptionSpec* spec_of(const ExperimentGroup& g, const std::string& key) {
  for (const OptionSpec& p : g.suite->parameters)
    if (p.key == key) return &p;
  for (const OptionSpec& o : g.method->options)
    if (o.key == key) return &o;
  return nullptr;
}

// The settings that tell a group apart: those whose value varies between the groups or differs
// from its default (every default spelled out, as the stored config has it, would hide them).
std::string telling_settings(const ExperimentFile& e, const ExperimentGroup& g) {
  const auto value_in = [](const ExperimentGroup& other, const std::string& key) -> std::optional<std::string> {
    for (const auto& [k, v] : other.settings)
      if (k == key) return v;
    return std::nullopt;
  };
  std::vector<std::string> shown;
  for (const auto& [key, value] : g.settings) {
    const bool varies = std::any_of(e.groups.begin(), e.groups.end(),
                                    [&](const ExperimentGroup& other) { return value_in(other, key) != value; });
    const OptionSpec* spec = spec_of(g, key);
    const bool non_default = !spec || parse_setting(*spec, value) != spec->default_value;
    if (varies || non_default) shown.push_back(fmt::format("{}={}", key, value));
  }
  return shown.empty() ? std::string("–") : fmt::format("{}", fmt::join(shown, ", "));
}

// The groups' statistics, each named by its place in the table and its telling settings.
std::string groups_table(const ExperimentFile& e, const std::vector<GroupSummary>& summaries) {
  const bool blocks = !e.blocks.empty();
  std::vector<std::string> header;
  if (blocks) header.emplace_back("block");
  for (const char* name : {"row", "column", "settings"}) header.emplace_back(name);
  std::vector<std::vector<std::string>> labels;
  for (const ExperimentGroup& g : e.groups) {
    labels.emplace_back();
    if (blocks) labels.back().push_back(g.place.block);
    labels.back().insert(labels.back().end(), {g.place.row, g.place.column, telling_settings(e, g)});
  }
  return to_markdown(summaries, header, labels);
}

}  // namespace

int cmd_run_experiment(const ExperimentArgs& a) {
  check_output_path(a.db, "--db");
  check_output_path(a.witness_dir, "--witness-dir");
  check_output_path(a.out_dir, "--out-dir");
  const ExperimentFile e = load_experiment_file(read_input_file(a.file), a.file);
  const RunOptions options = run_options_of(a);
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
    } catch (const std::invalid_argument& error) {  // an InputError, or a suite's own refusal
      throw UsageError(fmt::format("{}: {} on {}: {}", a.file, g.method_label, g.suite->name, error.what()));
    }
  }
  std::vector<const TrialGroup*> ordered;
  for (const TrialGroup& g : groups) ordered.push_back(&g);
  const auto run = run_groups(fmt::format("experiment {} ({})", e.name, a.file), ordered, options);
  if (!run) return 0;  // --plan

  const std::vector<GroupSummary> summaries = group_summaries(groups, run->trials);
  std::vector<GroupPlace> places;
  for (const ExperimentGroup& g : e.groups) places.push_back(g.place);
  const ExperimentVerdicts verdicts = compare_with_baseline(run->trials, places, e.baseline);
  std::string md = fmt::format("# {}\n\n", e.name);
  md += fmt::format("- file: {}; {} groups, {} trials each, timeout {} s, node cap {}, master seed {}\n", a.file,
                    groups.size(), e.trials, e.timeout_s, e.max_nodes, e.seed);
  md += fmt::format("- database: {} (experiment {}); host {}; git commit {}\n\n", a.db, e.name, run->engine.host,
                    run->engine.git_commit);
  md += fmt::format("## {} (rows: {}; columns: {}{}{})\n\n", to_string(e.value), fmt::join(e.rows, ", "),
                    fmt::join(e.columns, ", "), e.blocks.empty() ? "" : "; blocks: ", fmt::join(e.blocks, ", "));
  md += to_markdown(summaries, places, e.value);
  md += "\n" + to_markdown(verdicts, places);
  md += "\n## Groups\n\n" + groups_table(e, summaries);
  const fs::path out_dir(a.out_dir);
  const std::string md_path = (out_dir / (e.name + ".md")).string(), csv_path = (out_dir / (e.name + ".csv")).string();
  write_file_atomic(md_path, md);
  std::vector<std::string> extra_header{"value"};
  const std::vector<std::string> verdict_header = verdict_csv_header();
  extra_header.insert(extra_header.end(), verdict_header.begin(), verdict_header.end());
  std::vector<std::vector<std::string>> extra = verdict_csv_fields(verdicts, summaries.size());
  for (std::vector<std::string>& fields : extra) fields.insert(fields.begin(), std::string(to_string(e.value)));
  write_file_atomic(csv_path, to_csv(summaries, places, extra_header, extra));
  write_table_figures(a.out_dir, e.name);
  std::cout << md << std::flush;
  if (!a.quiet)
    fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run->total, run->run_now,
               md_path, csv_path, a.db);
  return run->errors ? 1 : 0;
}

}  // namespace hyfal::cli
