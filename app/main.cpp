// hyfal — command-line front end: list, run, table, validate.
// Every bad input gives one line on stderr and exit code 2, before anything is written.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/options.hpp"
#include "core/rng.hpp"
#include "core/trajectory.hpp"
#include "parallel/trial_engine.hpp"
#include "results/statistics.hpp"
#include "results/store.hpp"
#include "results/table_writer.hpp"
#include "suites/registry.hpp"

#ifndef HYFAL_SOURCE_DIR
#define HYFAL_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;
using namespace hyfal;

namespace {

// A bad input: reported as one line, exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string git_commit() {
  std::string out;
  if (FILE* p = popen("git -C '" HYFAL_SOURCE_DIR "' rev-parse --short=12 HEAD 2>/dev/null", "r")) {
    char buf[64];
    while (fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(fmt::format("cannot read '{}'", path));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_output(const std::string& path, const std::string& text) {
  if (path.empty() || path == "-") {
    std::cout << text;
    return;
  }
  const fs::path p(path), tmp = path + ".tmp";
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out || !(out << text) || !out.flush()) throw UsageError(fmt::format("cannot write '{}'", path));
  }
  fs::rename(tmp, p);
}

std::pair<std::string, std::string> split_setting(const std::string& s) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError(fmt::format("--set {}: expected key=value", s));
  return {s.substr(0, eq), s.substr(eq + 1)};
}

// --- list -------------------------------------------------------------------------------------
int cmd_list() {
  fmt::print("suites:\n");
  for (const auto& s : all_suites()) {
    fmt::print("  {:<14} {}\n", s.name, s.description);
    for (const auto& p : s.parameters)
      fmt::print("      --set {}={:<10} {}\n", p.key, p.default_value.dump(), p.help);
  }
  fmt::print("methods:\n");
  for (const auto& m : all_methods()) {
    fmt::print("  {:<14} {}\n", m.name, m.description);
    for (const auto& o : m.options)
      fmt::print("      --set {}={:<10} {}\n", o.key, o.default_value.dump(), o.help);
  }
  fmt::print("tables:\n  (none yet: paper tables come with the algorithm issues)\n");
  return 0;
}

// --- run --------------------------------------------------------------------------------------
struct RunArgs {
  std::string suite, method = "rrt", experiment = "default";
  std::vector<std::string> sets;
  int trials = 10, threads = 0;
  double timeout = 60.0;
  std::int64_t max_nodes = 1'000'000;
  std::uint64_t seed = 1;
  std::string db = "results/hyfal.sqlite", witness_dir = "results/witnesses", format = "md";
  bool quiet = false;
};

int cmd_run(const RunArgs& a) {
  const SuiteEntry* suite = find_suite(a.suite);
  if (!suite) throw UsageError(fmt::format("unknown suite '{}' (see 'hyfal list')", a.suite));
  const MethodEntry* method = find_method(a.method);
  if (!method) throw UsageError(fmt::format("unknown method '{}' (see 'hyfal list')", a.method));
  std::vector<std::pair<std::string, std::string>> instance_sets, method_sets;
  for (const auto& s : a.sets) {
    auto kv = split_setting(s);
    if (has_option(suite->parameters, kv.first))
      instance_sets.push_back(std::move(kv));
    else if (has_option(method->options, kv.first))
      method_sets.push_back(std::move(kv));
    else
      throw UsageError(fmt::format("--set {}: suite '{}' and method '{}' have no setting '{}' (see 'hyfal list')",
                                   s, suite->name, method->name, kv.first));
  }
  const Json instance = resolve_options(suite->parameters, instance_sets);
  const Json options = resolve_options(method->options, method_sets);
  std::shared_ptr<const System> system;
  try {
    system = suite->make(instance);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const Json config = {{"master_seed", a.seed}, {"max_nodes", a.max_nodes}, {"timeout_s", a.timeout},
                       {"options", options}};

  TrialStore store = TrialStore::open(a.db);
  TrialKey base{a.experiment, suite->name, instance.dump(), method->name, config.dump(), 0};
  const auto stored = store.stored_trial_indices(base);
  std::vector<TrialJob> jobs;
  for (int i = 0; i < a.trials; ++i) {
    if (stored.count(i)) continue;
    TrialJob job;
    job.key = base;
    job.key.trial_index = i;
    job.system = system;
    job.method = method;
    job.method_options = options;
    job.limits = {a.timeout, a.max_nodes};
    job.seed = trial_seed(a.seed, base.suite, base.instance, base.method, i);
    jobs.push_back(std::move(job));
  }
  if (!a.quiet && jobs.size() < static_cast<std::size_t>(a.trials))
    fmt::print(stderr, "[hyfal] resuming: {} of {} trials already stored in {}\n", a.trials - jobs.size(),
               a.trials, a.db);

  EngineOptions eo;
  eo.threads = a.threads;
  eo.witness_dir = a.witness_dir;
  eo.progress = !a.quiet && isatty(STDERR_FILENO);
  eo.host = host_name();
  eo.git_commit = git_commit();
  std::size_t errors = 0;
  run_trials(jobs, eo, [&](const TrialRecord& r) {
    store.insert(r);
    if (r.status == TrialStatus::error) {
      ++errors;
      fmt::print(stderr, "[hyfal] trial {} error: {}\n", r.key.trial_index, r.error);
    }
  });

  std::vector<TrialRecord> rows;
  for (auto& r : store.load(a.experiment))
    if (r.key.suite == base.suite && r.key.instance == base.instance && r.key.method == base.method &&
        r.key.config == base.config && r.key.trial_index < a.trials)
      rows.push_back(std::move(r));
  const auto groups = summarize_trials(rows);
  std::cout << (a.format == "csv" ? to_csv(groups) : to_markdown(groups));
  if (!a.quiet) {
    std::size_t validated = 0;
    for (const auto& r : rows) validated += r.validated;
    fmt::print("\n{} trials ({} run now), {} witnesses validated; threads {}; database {}; witnesses under {}\n",
               rows.size(), jobs.size(), validated, a.threads > 0 ? a.threads : default_thread_count(), a.db,
               a.witness_dir);
  }
  return errors ? 1 : 0;
}

// --- table ------------------------------------------------------------------------------------
int cmd_table(const std::string& db, const std::string& experiment, const std::string& format,
              const std::string& output) {
  if (!fs::exists(db)) throw UsageError(fmt::format("no results database at '{}'", db));
  TrialStore store = TrialStore::open(db);
  const auto rows = store.load(experiment.empty() ? std::nullopt : std::optional<std::string>(experiment));
  const auto groups = summarize_trials(rows);
  write_output(output, format == "csv" ? to_csv(groups) : to_markdown(groups));
  return 0;
}

// --- validate ---------------------------------------------------------------------------------
int cmd_validate(const std::string& file) {
  Json j;
  try {
    j = Json::parse(read_file(file));
  } catch (const Json::parse_error& e) {
    throw UsageError(fmt::format("'{}' is not valid JSON: {}", file, e.what()));
  }
  Witness w;
  try {
    w = witness_from_json(j);
  } catch (const WitnessError& e) {
    throw UsageError(fmt::format("'{}': {}", file, e.what()));
  }
  const SuiteEntry* suite = find_suite(w.suite);
  if (!suite) throw UsageError(fmt::format("'{}': unknown suite '{}'", file, w.suite));
  std::vector<std::pair<std::string, std::string>> sets;
  for (const auto& [k, v] : w.instance.items()) sets.emplace_back(k, v.is_string() ? v.get<std::string>() : v.dump());
  std::shared_ptr<const System> system;
  try {
    system = suite->make(resolve_options(suite->parameters, sets));
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("'{}': bad instance: {}", file, e.what()));
  }
  const ValidationReport r = validate_witness(*system, w);
  fmt::print("{}: {}\n", r.valid ? "VALID" : "INVALID", r.reason);
  return r.valid ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hyfal: parallel benchmark harness for falsification of hybrid systems with RRT-family planners.\n"
      "Searches input sequences that drive a hybrid system into its unsafe set (s <= 0), records every\n"
      "trial in SQLite, writes validated witnesses, and prints summary tables."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "help for every command");

  auto* list = app.add_subcommand("list", "list suites (with their --set parameters), methods and tables");

  RunArgs ra;
  auto* run = app.add_subcommand("run", "run trials of one method on one suite instance; resumes a stored run");
  run->add_option("--suite", ra.suite, "suite name (see 'hyfal list')")->required();
  run->add_option("--method", ra.method, "method name")->capture_default_str();
  run->add_option("--set", ra.sets, "instance parameter or method option, key=value (repeatable)");
  run->add_option("--trials", ra.trials, "number of trials (indices 0..N-1)")->check(CLI::PositiveNumber)->capture_default_str();
  run->add_option("--threads", ra.threads, "worker threads, 0 = all cores")->check(CLI::NonNegativeNumber)->capture_default_str();
  run->add_option("--timeout", ra.timeout, "per-trial wall-clock limit, seconds")->check(CLI::PositiveNumber)->capture_default_str();
  run->add_option("--max-nodes", ra.max_nodes, "per-trial node cap")->check(CLI::PositiveNumber)->capture_default_str();
  run->add_option("--seed", ra.seed, "master seed; trial seeds derive from it, the suite, instance, method and index")->capture_default_str();
  run->add_option("--experiment", ra.experiment, "experiment name stored with each trial")->capture_default_str();
  run->add_option("--db", ra.db, "SQLite results database")->capture_default_str();
  run->add_option("--witness-dir", ra.witness_dir, "directory for witness JSON files")->capture_default_str();
  run->add_option("--format", ra.format, "summary table format")->check(CLI::IsMember({"md", "csv"}))->capture_default_str();
  run->add_flag("--quiet", ra.quiet, "print only the table");

  std::string tdb = "results/hyfal.sqlite", texp, tformat = "md", tout;
  auto* table = app.add_subcommand("table", "summarize a results database: n, falsified rate, mean/median/std/95% CI");
  table->add_option("--db", tdb, "SQLite results database")->capture_default_str();
  table->add_option("--experiment", texp, "only this experiment");
  table->add_option("--format", tformat, "md or csv")->check(CLI::IsMember({"md", "csv"}))->capture_default_str();
  table->add_option("--output,-o", tout, "write to this file instead of stdout");

  std::string vfile;
  auto* validate = app.add_subcommand("validate", "re-simulate a witness JSON file with a tight integrator and check it");
  validate->add_option("file", vfile, "witness JSON file")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 2;
  }
  try {
    if (*list) return cmd_list();
    if (*run) return cmd_run(ra);
    if (*table) return cmd_table(tdb, texp, tformat, tout);
    if (*validate) return cmd_validate(vfile);
  } catch (const UsageError& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 2;
  } catch (const OptionError& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 2;
  } catch (const StoreError& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
