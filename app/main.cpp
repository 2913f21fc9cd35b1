// hyfal — command-line front end: list, run, table, validate, reproduce, instance, merge, plot.
// Every bad input gives one line on stderr and exit code 2, before anything is written.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/experiment.hpp"
#include "app/experiment_file.hpp"
#include "app/merge.hpp"
#include "app/plan.hpp"
#include "app/plot.hpp"
#include "app/reproduce.hpp"
#include "app/runner.hpp"
#include "app/simulate.hpp"
#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/util/rng.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "parallel/cluster.hpp"
#include "parallel/trial_engine.hpp"
#include "results/statistics.hpp"
#include "results/ompl_log.hpp"
#include "results/store.hpp"
#include "results/table_writer.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"
#include "core/model/signal_model.hpp"

#ifndef HYFAL_SOURCE_DIR
#define HYFAL_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;
using namespace hyfal;

namespace {

void write_output(const std::string& path, const std::string& text) {
  if (path.empty() || path == "-") {
    std::cout << text;
    return;
  }
  write_file_atomic(path, text);
}

std::pair<std::string, std::string> split_setting(const std::string& s) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError(fmt::format("--set {}: expected key=value", s));
  return {s.substr(0, eq), s.substr(eq + 1)};
}

// --- list -------------------------------------------------------------------------------------
// One setting as `hyfal list` shows it: --set key=default, its valid values, what it means.
void print_setting(const OptionSpec& o) {
  const std::string range = o.range.empty() ? (o.default_value.is_boolean() ? "true|false" : "any") : o.range;
  fmt::print("      {:<36} {:<18} {}\n", fmt::format("--set {}={}", o.key, o.default_value.dump()), range, o.help);
}

// A suite's signals (for STL requirements) and the requirements it declares, as its default
// instance has them.
void print_signals(const System& system) {
  std::string line;
  for (const auto& s : stl::system_signals(system.info()))
    line += fmt::format("{}{}{}", line.empty() ? "" : ", ", s.name, s.unit.empty() ? "" : " [" + s.unit + "]");
  fmt::print("      signals: {}\n", line);
  if (!system.info().input_aliases.empty())
    fmt::print("      input CSV header (hyfal simulate): {}\n", cli::accepted_input_names(system.info()));
  for (const auto& r : system.info().requirements)
    fmt::print("      requirement {:<6} {}  ({})\n", r.id, r.formula, r.meaning);
}

// Every setting of every suite and method as one Markdown table (the README's parameter table).
std::string settings_markdown() {
  std::string out = "| suite / method | setting | default | valid values | meaning |\n|---|---|---|---|---|\n";
  const auto row = [&](const std::string& owner, const OptionSpec& o) {
    const std::string range = o.range.empty() ? (o.default_value.is_boolean() ? "true, false" : "any") : o.range;
    std::string help = o.help;
    for (std::size_t i = 0; (i = help.find('|', i)) != std::string::npos; i += 2) help.replace(i, 1, "\\|");
    std::string r = range;
    for (std::size_t i = 0; (i = r.find('|', i)) != std::string::npos; i += 2) r.replace(i, 1, "\\|");
    out += fmt::format("| {} | `{}` | `{}` | {} | {} |\n", owner, o.key, o.default_value.dump(), r, help);
  };
  for (const auto& s : all_suites())
    for (const auto& p : s.parameters) row("suite `" + s.name + "`", p);
  for (const auto& m : all_methods())
    for (const auto& o : m.options) row("method `" + m.name + "`", o);
  return out;
}

int cmd_list(bool markdown) {
  if (markdown) {
    std::cout << settings_markdown();
    return 0;
  }
  fmt::print("suites:   (--set key=default  valid values  meaning)\n");
  for (const auto& s : all_suites()) {
    fmt::print("  {:<14} {}\n", s.name, s.description);
    for (const auto& p : s.parameters) print_setting(p);
    print_signals(*s.make(resolve_options(s.parameters, {})));
  }
  fmt::print("methods:\n");
  for (const auto& m : all_methods()) {
    fmt::print("  {:<14} {}\n", m.name, m.description);
    for (const auto& o : m.options) print_setting(o);
  }
  fmt::print("tables:   (hyfal reproduce ID --profile smoke|quick|full|paper; a league: smoke|quick|full|published)\n");
  const auto& tables = builtin_paper_tables();
  if (tables.empty()) fmt::print("  (none)\n");
  for (const auto& t : tables) {
    std::string suites = t.suite;
    if (t.league) {
      suites.clear();
      for (const LeagueRow& row : t.league->rows)
        if (suites.find(row.suite) == std::string::npos) suites += (suites.empty() ? "" : ", ") + row.suite;
    }
    fmt::print("  {:<14} {} [{} {}]\n", t.id, t.title, t.league ? "league of" : "suite", suites);
  }
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
  std::string shard;  // --shard i/K, empty for all trials
  bool plan = false;  // --plan: print the sizing and run nothing
  bool save_trees = false;  // --save-trees: each witness's search tree(s) beside it
};

int cmd_run(const RunArgs& a) {
  check_output_path(a.db, "--db");
  check_output_path(a.witness_dir, "--witness-dir");
  check_experiment_name(a.experiment);
  const SuiteEntry* suite = find_suite(a.suite);
  if (!suite) throw UsageError(fmt::format("unknown suite '{}' (see 'hyfal list')", a.suite));
  const MethodEntry* method = find_method(a.method);
  if (!method) throw UsageError(fmt::format("unknown method '{}' (see 'hyfal list')", a.method));
  const Shard shard = shard_option(a.shard);
  check_directory_creatable(a.witness_dir, "--witness-dir");
  TrialGroupSpec spec;
  spec.experiment = a.experiment;
  spec.suite = suite;
  spec.method = method;
  for (const auto& s : a.sets) spec.settings.push_back(split_setting(s));
  spec.trials = a.trials;
  spec.timeout_s = a.timeout;
  spec.max_nodes = a.max_nodes;
  spec.seed = a.seed;
  const TrialGroup group = resolve_trial_group(spec);

  RunOptions options;
  options.threads = a.threads;
  options.db = a.db;
  options.witness_dir = a.witness_dir;
  options.shard = shard;
  options.plan = a.plan;
  options.progress = !a.quiet && isatty(STDERR_FILENO);
  options.quiet = a.quiet;
  options.save_trees = a.save_trees;
  const auto run = run_groups(fmt::format("{} on {}", method->name, suite->name), {&group}, options);
  if (!run) return 0;  // --plan
  const std::vector<TrialRecord>& rows = run->trials[0];
  const auto groups = summarize_trials(rows);
  std::cout << (a.format == "csv" ? to_csv(groups) : to_markdown(groups));
  if (!a.quiet) {
    std::size_t validated = 0;
    for (const auto& r : rows) validated += r.validated;
    const Cluster* cluster = Cluster::current();
    fmt::print("\n{} trials ({} run now), {} witnesses validated; {}threads {}; database {}; witnesses under {}\n",
               rows.size(), run->run_now, validated, cluster ? fmt::format("{} MPI ranks x ", cluster->size()) : "",
               a.threads > 0 ? a.threads : default_thread_count(), a.db,
               a.witness_dir);
  }
  return run->errors ? 1 : 0;
}

// --- table ------------------------------------------------------------------------------------
int cmd_table(const std::string& db, const std::string& experiment, const std::string& format,
              const std::string& output) {
  if (!fs::exists(db)) throw UsageError(fmt::format("no results database at '{}'", db));
  // ompl-log: one log per (suite, instance); -o DIR (an existing folder, or a path ending in '/')
  // writes each to DIR/<k>-<suite>.log, as OMPL's tools read one experiment per file.
  const bool log_dir = format == "ompl-log" && !output.empty() && (output.back() == '/' || fs::is_directory(output));
  if (log_dir) {
    check_directory_creatable(output, "-o");
  } else if (!output.empty() && output != "-") {
    if (fs::is_directory(output)) throw UsageError(fmt::format("-o '{}' is a directory", output));
    const fs::path parent = fs::path(output).parent_path();
    check_directory_creatable(parent.empty() ? "." : parent.string(), "-o");
  }
  TrialStore store = TrialStore::open_read_only(db);
  const auto rows = store.load(experiment.empty() ? std::nullopt : std::optional<std::string>(experiment));
  if (format == "ompl-log") {
    const auto logs = to_ompl_logs(rows);
    std::string all;
    for (std::size_t k = 0; k < logs.size(); ++k) {
      if (log_dir)
        write_output((fs::path(output) / fmt::format("{}-{}.log", k + 1, logs[k].suite)).string(), logs[k].text);
      else
        all += logs[k].text;
    }
    if (!log_dir) write_output(output, all);
    return 0;
  }
  const auto groups = summarize_trials(rows);
  write_output(output, format == "csv" ? to_csv(groups) : to_markdown(groups));
  return 0;
}

// --- instance export ----------------------------------------------------------------------------
int cmd_instance_export(const std::string& suite_name, const std::vector<std::string>& sets_text) {
  const SuiteEntry* suite = find_suite(suite_name);
  if (!suite) throw UsageError(fmt::format("unknown suite '{}' (see 'hyfal list')", suite_name));
  std::vector<std::pair<std::string, std::string>> sets;
  for (const auto& s : sets_text) sets.push_back(split_setting(s));
  Json instance;
  try {
    instance = canonical_instance(suite->parameters, resolve_options(suite->parameters, sets));
    if (suite->export_instance) {
      std::cout << suite->export_instance(instance).dump() << '\n';
      return 0;
    }
    const auto system = suite->make(instance);  // no suite-specific export: the SystemInfo facts
    const SystemInfo& info = system->info();
    std::cout << Json{{"format", "hyfal-instance/1"}, {"suite", suite->name}, {"instance", instance},
                      {"state_names", info.state_names}, {"input_names", info.input_names},
                      {"initial", {{"mode", info.initial_mode}, {"x", info.initial_state}}},
                      {"other_initial_states", info.other_initial_states},
                      {"sampling_box", {{"lo", info.sampling_box.lo}, {"hi", info.sampling_box.hi}}},
                      {"step_duration", info.step_duration}}
                     .dump()
              << '\n';
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return 0;
}

// --- validate ---------------------------------------------------------------------------------
// Exit 2 (bad input): the file cannot be read, is not JSON, is not a witness (a missing,
// mistyped or out-of-range field), names an unknown suite or instance, or does not fit the system
// (sizes, modes, transitions: ValidationReport::malformed). Exit 1: a well-formed witness that
// does not re-simulate to the unsafe set (INVALID on stdout).
int cmd_validate(const std::string& file) {
  // Names and values quoted from the file may hold control characters (a JSON "\n"): escaped,
  // so that an error stays one line.
  Witness w;
  try {
    w = witness_from_text(read_input_file(file));
  } catch (const WitnessError& e) {
    throw UsageError(one_line(fmt::format("'{}': {}", file, e.what())));
  }
  const SuiteEntry* suite = find_suite(w.suite);
  if (!suite) throw UsageError(one_line(fmt::format("'{}': unknown suite '{}'", file, w.suite)));
  std::vector<std::pair<std::string, std::string>> sets;
  for (const auto& [k, v] : w.instance.items()) sets.emplace_back(k, v.is_string() ? v.get<std::string>() : v.dump());
  std::shared_ptr<const System> system;
  try {
    system = suite->make(resolve_options(suite->parameters, sets));
  } catch (const std::invalid_argument& e) {
    throw UsageError(one_line(fmt::format("'{}': bad instance: {}", file, e.what())));
  }
  ValidationReport r = validate_witness(*system, w);
  if (r.malformed)
    throw UsageError(one_line(fmt::format("'{}': not a witness of this {} instance: {}", file, w.suite, r.reason)));
  // An STL witness records the robustness its validation found; a re-validation finds the same.
  if (r.valid && r.robustness && w.requirement &&
      !(std::abs(*r.robustness - w.requirement->robustness) <= 1e-9 * (1.0 + std::abs(*r.robustness)))) {
    r.valid = false;
    r.reason = fmt::format("the re-simulated robustness {:.9g} differs from the recorded {:.9g}", *r.robustness,
                           w.requirement->robustness);
  }
  fmt::print("{}: {}\n", r.valid ? "VALID" : "INVALID", one_line(r.reason));
  return r.valid ? 0 : 1;
}

}  // namespace

// Number checks with short messages (CLI11's ranges print DBL_MAX in full and let NaN pass).
CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& s) {
        try {
          std::size_t used = 0;
          const double v = std::stod(s, &used);
          if (used == s.size() && std::isfinite(v) && v > 0.0) return std::string();
        } catch (const std::exception&) {
        }
        return "'" + s + "' is not a positive number";
      },
      "POSITIVE");
}
CLI::Validator non_negative_integer() {
  return CLI::Validator(
      [](std::string& s) {
        return !s.empty() && s.size() <= 19 && s.find_first_not_of("0123456789") == std::string::npos
                   ? std::string()
                   : "'" + s + "' is not a non-negative integer";
      },
      "UINT");
}
CLI::Validator integer_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) {
        const bool digits = !s.empty() && s.size() <= 18 && s.find_first_not_of("0123456789") == std::string::npos;
        if (digits) {
          const long long v = std::stoll(s);
          if (v >= lo && v <= hi) return std::string();
        }
        return fmt::format("'{}' is not an integer in [{}, {}]", s, lo, hi);
      },
      fmt::format("INT in [{}, {}]", lo, hi));
}
CLI::Validator shard_text() {
  return CLI::Validator(
      [](std::string& s) {
        return parse_shard(s) ? std::string()
                                   : fmt::format("'{}' is not a shard i/K with 0 <= i < K <= {}", s, kMaxShards);
      },
      "i/K");
}
CLI::Validator positive_integer() {
  return CLI::Validator(
      [](std::string& s) {
        return !s.empty() && s.size() <= 18 && s.find_first_not_of("0123456789") == std::string::npos &&
                       s.find_first_not_of('0') != std::string::npos
                   ? std::string()
                   : "'" + s + "' is not a positive integer";
      },
      "N>0");
}

namespace {
int run_command(int argc, char** argv);
}  // namespace

// Under mpirun every rank starts here: rank 0 runs the command (and coordinates the trials it
// runs), the other ranks serve trials until rank 0 is done; see parallel/cluster.hpp.
int main(int argc, char** argv) {
  std::unique_ptr<Cluster> cluster;
  try {
    cluster = Cluster::join_if_launched(&argc, &argv);
  } catch (const ClusterError& e) {
    if (launcher_rank() == 0) fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return e.exit_code();
  }
  if (cluster && cluster->rank() > 0) {
    const SystemResolver resolve = [](const std::string& suite_name, const std::string& instance) {
      const SuiteEntry* suite = find_suite(suite_name);
      if (!suite) return std::shared_ptr<const System>();
      return suite->make(Json::parse(instance));
    };
    return cluster->serve(resolve, git_commit());
  }
  if (cluster) {
    try {
      cluster->check_ranks(git_commit());
    } catch (const ClusterError& e) {
      fmt::print(stderr, "hyfal: error: {}\n", e.what());
      cluster->finish(e.exit_code());
      return e.exit_code();
    }
  }
  const int rc = run_command(argc, argv);
  if (cluster) cluster->finish(rc);
  return rc;
}

namespace {

// Every command and the values its options are parsed into (CLI11 writes them in place: the
// object stays where it was built).
struct CommandLine {
  CLI::App app{
      "hyfal: parallel benchmark harness for falsification of hybrid systems with RRT-family planners.\n"
      "Searches input sequences that drive a hybrid system into its unsafe set (s <= 0), records every\n"
      "trial in SQLite, writes validated witnesses, and prints summary tables."};
  bool list_markdown = false;
  RunArgs run_args;
  cli::ExperimentArgs experiment_args;
  std::string table_db = "results/hyfal.sqlite", table_experiment, table_format = "md", table_output;
  cli::ReproduceArgs reproduce_args;
  cli::MergeArgs merge_args;
  std::string instance_suite;
  std::vector<std::string> instance_sets;
  cli::PlotArgs plot_args;
  std::string witness_file;
  cli::SimulateArgs simulate_args;
  std::string witness_csv_file, witness_csv_format = "arch-csv", witness_csv_output;
  CLI::App *simulate = nullptr, *witness = nullptr;
  CLI::App *list = nullptr, *run = nullptr, *table = nullptr, *reproduce = nullptr, *merge = nullptr,
           *instance_export = nullptr, *plot = nullptr, *validate = nullptr;
  CLI::Option* run_suite = nullptr;
};

// list [--markdown]
void add_list_command(CommandLine& c) {
  c.list = c.app.add_subcommand("list", "list suites and methods with every --set setting (default, valid values), and tables");
  c.list->add_flag("--markdown", c.list_markdown, "print every setting as one Markdown table (as in the README)");
}

// run: flags or an experiment file
void add_run_command(CommandLine& c) {
  auto* run = c.run = c.app.add_subcommand("run", "run trials of one method on one suite instance; resumes a stored run");
  run->footer(
      "On a cluster: `mpirun -n K hyfal run ...` runs the same trials on K processes: rank 0 hands them out\n"
      "and is the only one to write --db and --witness-dir; every rank runs --threads threads. Results equal\n"
      "those of one process, and a run stopped at one K resumes at any other (README: Running on a cluster).");
  run->add_option("file", c.experiment_args.file,
                  "an experiment file (.toml): suites, methods, trials, caps, seed and table layout (README: "
                  "\"Tables and experiments as TOML files\"); instead of --suite, --method, --set, --trials, "
                  "--timeout, --max-nodes, --seed, --experiment and --format");
  c.run_suite = run->add_option("--suite", c.run_args.suite, "suite name (see 'hyfal list'); required without a file");
  run->add_option("--method", c.run_args.method, "method name")->capture_default_str();
  run->add_option("--set", c.run_args.sets, "instance parameter or method option, key=value (repeatable)");
  run->add_option("--trials", c.run_args.trials, "number of trials (indices 0..N-1), at most 1000000")
      ->check(integer_in(1, kMaxTrials))->capture_default_str();
  run->add_option("--threads", c.run_args.threads, "worker threads, 0 = all cores, at most 1024")
      ->check(integer_in(0, kMaxThreads))->capture_default_str();
  run->add_option("--timeout", c.run_args.timeout, "per-trial wall-clock limit, seconds (any positive number; very large = no limit)")
      ->check(positive_number())->capture_default_str();
  run->add_option("--max-nodes", c.run_args.max_nodes, "per-trial node cap")->check(positive_integer())->capture_default_str();
  run->add_option("--seed", c.run_args.seed, "master seed; trial seeds derive from it, the suite, instance, method and index")
      ->check(non_negative_integer())->capture_default_str();
  run->add_option("--experiment", c.run_args.experiment, "experiment name stored with each trial")->capture_default_str();
  run->add_option("--db", c.run_args.db, "SQLite results database")->capture_default_str();
  run->add_option("--witness-dir", c.run_args.witness_dir, "directory for witness JSON files")->capture_default_str();
  run->add_option("--format", c.run_args.format, "summary table format")->check(CLI::IsMember({"md", "csv"}))->capture_default_str();
  run->add_flag("--quiet", c.run_args.quiet, "print only the table");
  run->add_option("--shard", c.run_args.shard,
                  "run only share i of K (0 <= i < K <= 100000): the trial indices t with t % K == i, into --db "
                  "(one database per shard, e.g. per Slurm array task; combine them with 'hyfal merge')")
      ->check(shard_text());
  run->add_flag("--plan", c.run_args.plan,
                "print the number of trials, the caps and an upper bound of CPU-hours (and what --db still lacks), "
                "run nothing and write nothing");
  run->add_option("--out-dir", c.experiment_args.out_dir, "with an experiment file: where NAME.md and NAME.csv are written")
      ->capture_default_str();
  run->add_flag("--save-trees", c.run_args.save_trees,
                "beside each witness F.json also write F.tree.csv: the trial's search tree(s), per node its parent, "
                "mode and state (at most 50000 edges, subsampled deterministically); results do not change; not "
                "under mpirun");
}

// table
void add_table_command(CommandLine& c) {
  auto* table = c.table = c.app.add_subcommand("table", "summarize a results database: n, falsified rate, mean/median/std/95% CI");
  table->add_option("--db", c.table_db, "SQLite results database")->capture_default_str();
  table->add_option("--experiment", c.table_experiment, "only this experiment");
  table->add_option("--format", c.table_format, "md, csv, or ompl-log (OMPL's benchmark log, one experiment per suite instance)")
      ->check(CLI::IsMember({"md", "csv", "ompl-log"}))
      ->capture_default_str();
  table->add_option("--output,-o", c.table_output, "write to this file instead of stdout (ompl-log: or into this folder, one file per experiment)");
}

// reproduce ID --profile P
void add_reproduce_command(CommandLine& c) {
  auto* reproduce = c.reproduce = c.app.add_subcommand(
      "reproduce", "run a paper table's rows (resuming) and write <out-dir>/ID.md and .csv beside the paper's numbers");
  reproduce->add_option("id", c.reproduce_args.id, "table id (see 'hyfal list') or the path of a table file (.toml)")->required();
  reproduce->footer("Runs on a cluster like `run` does: `mpirun -n K hyfal reproduce ID --profile P` (see `hyfal run --help`).");
  reproduce->add_option("--profile", c.reproduce_args.profile,
                        "smoke (seconds), quick (minutes), full (the committed tables: larger samples, every column, "
                        "per-method caps; hours; not every table has one), paper (the paper's set-up) or, for a "
                        "league table (arch-fals), published (the published tools' settings: runs, budget, control points)")
      ->required()
      ->check(CLI::IsMember({"smoke", "quick", "full", "paper", "published"}));
  reproduce->add_option("--threads", c.reproduce_args.threads, "worker threads, 0 = all cores, at most 1024")
      ->check(integer_in(0, kMaxThreads))->capture_default_str();
  reproduce->add_option("--seed", c.reproduce_args.seed, "master seed; trial seeds derive from it, the suite, instance, method and index")
      ->check(non_negative_integer())
      ->capture_default_str();
  reproduce->add_option("--db", c.reproduce_args.db, "SQLite results database")->capture_default_str();
  reproduce->add_option("--witness-dir", c.reproduce_args.witness_dir, "directory for witness JSON files")->capture_default_str();
  reproduce->add_option("--out-dir", c.reproduce_args.out_dir, "where ID.md and ID.csv are written")->capture_default_str();
  reproduce->add_option("--shard", c.reproduce_args.shard,
                        "run only share i of K (0 <= i < K <= 100000) of the table's trials (position in the full "
                        "trial list % K == i), into --db; the table then covers only that database until the "
                        "shard databases are merged ('hyfal merge')")
      ->check(shard_text());
  reproduce->add_flag("--save-trees", c.reproduce_args.save_trees,
                      "write each witness's search tree beside it (F.tree.csv; hyfal plot draws it under the path); "
                      "not under mpirun");
  reproduce->add_flag("--plan", c.reproduce_args.plan,
                      "print the table's cells, trials, per-trial caps and an upper bound of CPU-hours (and what "
                      "--db still lacks), run nothing and write nothing");
}

// merge OUT INPUTS...
void add_merge_command(CommandLine& c) {
  auto* merge = c.merge = c.app.add_subcommand(
      "merge",
      "merge results databases (e.g. of --shard runs) into OUT: idempotent, refuses conflicting rows, writes all or "
      "nothing");
  merge->add_option("out", c.merge_args.out, "the merged database (created if missing; must not be an input)")->required();
  merge->add_option("inputs", c.merge_args.inputs, "databases to merge in (only read)")->required();
  merge->add_option("--witness-dir", c.merge_args.witness_dir,
                    "copy each merged trial's witness into this folder (as 'run' lays them out) and store the new "
                    "path; without it the stored paths are kept");
}

// instance export
void add_instance_command(CommandLine& c) {
  auto* instance = c.app.add_subcommand("instance", "export a suite instance as JSON for outside tools");
  instance->require_subcommand(1);
  auto* instance_export = c.instance_export = instance->add_subcommand("export", "print the instance (e.g. navigation maze, dynamics, properties) as JSON");
  instance_export->add_option("--suite", c.instance_suite, "suite name")->required();
  instance_export->add_option("--set", c.instance_sets, "instance parameter, key=value (repeatable)");
}

// plot
void add_plot_command(CommandLine& c) {
  auto* plot = c.plot = c.app.add_subcommand(
      "plot", "figures (PNG and SVG, Debian's python3-matplotlib): of the tables 'reproduce' wrote, or of one witness");
  plot->add_option("tables_dir", c.plot_args.tables_dir, "a folder of tables from 'hyfal reproduce' (ID.csv, ID-SERIES.csv)");
  plot->add_option("--witness", c.plot_args.witness,
                   "a witness JSON file: its path (navigation: over the maze; aircraft: the conflict; blimp: the tower), "
                   "with the search tree under it when F.tree.csv (hyfal run --save-trees) is beside F.json");
  plot->add_option("--tree", c.plot_args.tree, "with --witness: the tree file to draw (default: F.tree.csv beside F.json)");
  plot->add_option("--out", c.plot_args.out,
                   "tables: the folder for the figures (default TABLES_DIR); witness: F.png, F.svg beside it "
                   "(default: the witness's path with .png)");
}

// validate FILE
void add_validate_command(CommandLine& c) {
  c.validate = c.app.add_subcommand("validate", "re-simulate a witness JSON file with a tight integrator and check it");
  c.validate->add_option("file", c.witness_file, "witness JSON file")->required();
}

// simulate --suite S [--set k=v]... --input FILE.csv [--trace OUT.csv]
void add_simulate_command(CommandLine& c) {
  auto* s = c.simulate = c.app.add_subcommand(
      "simulate", "drive a suite instance with an input signal (ARCH-COMP CSV: time, then one column per input; "
                  "piecewise constant); print each requirement's robustness (a trace shorter than a requirement's "
                  "horizon: its robustness interval, and 'unknown' where that does not decide), optionally write the trace");
  s->add_option("--suite", c.simulate_args.suite, "suite name")->required();
  s->add_option("--set", c.simulate_args.sets, "instance parameter, key=value (repeatable; requirement=... adds one)");
  s->add_option("--input", c.simulate_args.input,
                "the input CSV (a header row time,<inputs> is optional; an input may go by its alias, e.g. "
                "time,throttle,brake for at: see 'hyfal list'); required unless the suite has no inputs (f16): it "
                "then runs for the longest horizon of its requirements");
  s->add_option("--trace", c.simulate_args.trace, "write the trace (time and every signal) as CSV to this file; - for stdout");
  s->add_option("--interpolation", c.simulate_args.interpolation,
                "zoh: each row's input is held until the next row (the default, the searches' signals); linear: the rows "
                "are control points joined by straight lines (S-TaLiRo's and Breach's default, and the MathWorks AT "
                "trace's), simulated as pieces of the integrator's step at the line's midpoint values")
      ->check(CLI::IsMember({"zoh", "linear"}));
}

// witness FILE --format arch-csv [-o OUT]
void add_witness_command(CommandLine& c) {
  auto* w = c.witness = c.app.add_subcommand("witness", "convert a witness: its input signal as an ARCH-COMP validation CSV");
  w->add_option("file", c.witness_csv_file, "witness JSON file")->required();
  w->add_option("--format", c.witness_csv_format, "output format")->check(CLI::IsMember({"arch-csv"}));
  w->add_option("-o,--output", c.witness_csv_output, "output file (default: stdout)");
}

// An unknown command gets one line naming the commands (CLI11's own message would name the
// word as an unexpected argument). Returns the exit code, or nothing for a known command.
std::optional<int> reject_unknown_command(const CLI::App& app, int argc, char** argv) {
  if (argc <= 1 || argv[1][0] == '-') return std::nullopt;
  const std::string cmd = argv[1];
  for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == cmd) return std::nullopt;
  fmt::print(stderr, "hyfal: error: unknown command '{}' (commands: list, run, table, validate, simulate, witness, reproduce, instance, merge, plot; see 'hyfal --help')\n", cmd);
  return 2;
}

// Parses into c; returns the exit code where there is nothing to run (help, a parse error).
std::optional<int> parse(CommandLine& c, int argc, char** argv) {
  try {
    c.app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return c.app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return c.app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "hyfal: error: {}\n", e.what());
    return 2;
  }
  return std::nullopt;
}

// run with flags, or with an experiment file (whose run the flags must not state again).
int run_flags_or_file(CommandLine& c) {
  const RunArgs& ra = c.run_args;
  cli::ExperimentArgs& xa = c.experiment_args;
  if (xa.file.empty()) {
    if (c.run_suite->count() == 0) throw UsageError("--suite is required (or an experiment file)");
    if (c.run->get_option("--out-dir")->count() > 0) throw UsageError("--out-dir is for an experiment file");
    return cmd_run(ra);
  }
  // The file states what the flags would: giving both would leave one of them unused.
  for (const char* flag : {"--suite", "--method", "--set", "--trials", "--timeout", "--max-nodes", "--seed",
                           "--experiment", "--format"})
    if (c.run->get_option(flag)->count() > 0)
      throw UsageError(fmt::format("{}: the experiment file '{}' states the run; give a file or flags, not both",
                                   flag, xa.file));
  xa.threads = ra.threads;
  xa.db = ra.db;
  xa.witness_dir = ra.witness_dir;
  xa.shard = ra.shard;
  xa.plan = ra.plan;
  xa.quiet = ra.quiet;
  xa.save_trees = ra.save_trees;
  return cli::cmd_run_experiment(xa);
}

// Runs the command that was parsed; returns its exit code.
int dispatch(CommandLine& c) {
  if (*c.list) return cmd_list(c.list_markdown);
  if (*c.run) return run_flags_or_file(c);
  if (*c.table) return cmd_table(c.table_db, c.table_experiment, c.table_format, c.table_output);
  if (*c.validate) return cmd_validate(c.witness_file);
  if (*c.simulate) return cli::cmd_simulate(c.simulate_args);
  if (*c.witness) return cli::cmd_witness_csv(c.witness_csv_file, c.witness_csv_output);
  if (*c.instance_export) return cmd_instance_export(c.instance_suite, c.instance_sets);
  if (*c.reproduce) return cli::cmd_reproduce(c.reproduce_args);
  if (*c.merge) return cli::cmd_merge(c.merge_args);
  if (*c.plot) {
    c.plot_args.out_given = c.plot->get_option("--out")->count() > 0;
    return cli::cmd_plot(c.plot_args);
  }
  return 0;
}

// The exception a command threw (call it in a catch block) as one line on stderr and its exit
// code, classified by core/util/error.hpp: 2 for bad input, 3 for a machine that failed (a rerun
// resumes), 1 for anything else.
int report_failure() {
  try {
    throw;
  } catch (const std::exception& e) {
    const int code = exit_code_of(e);
    fmt::print(stderr, "hyfal: error: {}{}\n", e.what(),
               code == 3 ? " (the run stopped; rerun the same command to resume)" : "");
    return code;
  }
}

int run_command(int argc, char** argv) {
  CommandLine c;
  c.app.require_subcommand(1);
  c.app.set_help_all_flag("--help-all", "help for every command");
  for (const auto add : {add_list_command, add_run_command, add_table_command, add_reproduce_command,
                         add_merge_command, add_instance_command, add_plot_command, add_validate_command,
                         add_simulate_command, add_witness_command})
    add(c);
  if (const auto code = reject_unknown_command(c.app, argc, argv)) return *code;
  if (const auto code = parse(c, argc, argv)) return *code;
  try {
    return dispatch(c);
  } catch (...) {
    return report_failure();
  }
}

}  // namespace
