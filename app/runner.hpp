// The one pipeline of `run`, `reproduce` and experiment files: resolve (settings -> trial
// groups, everything checked before anything is written), plan (--plan), run (trials the store
// lacks, on this process or an MPI job's ranks), store, and hand the stored trials to a report.
#pragma once
#include <unistd.h>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/shard.hpp"
#include "core/util/error.hpp"
#include "core/run/paper_table.hpp"
#include "core/run/suite_entry.hpp"
#include "parallel/trial_engine.hpp"
#include "results/store.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {

// A bad input: reported as one line on stderr, exit code 2, before anything is written.
struct UsageError : InputError {
  using InputError::InputError;
  const char* name() const noexcept override { return "UsageError"; }
};

// A method that cannot drive the suite at all (check_method_for_system): a usage error for
// `hyfal run`, a cell that does not apply ("n/a") in a league.
struct MethodNotApplicable : UsageError {
  using UsageError::UsageError;
  const char* name() const noexcept override { return "MethodNotApplicable"; }
};

// The short commit of the source tree hyfal was built from, or "unknown".
std::string git_commit();

// Throws UsageError "<what> '<dir>': ..." unless dir is a directory or could be created (its
// deepest existing ancestor is a writable directory). Creates nothing.
void check_directory_creatable(const std::string& dir, const std::string& what);

// Applies `layer` on top of `base`: a key already in base takes the layer's value (paper tables
// stack profile, block, column and row settings this way); a user's own --set list instead must
// name each key once (resolve_options refuses a repeated key).
void overlay_settings(Settings& base, const Settings& layer);

// Limits of the run options, documented in `hyfal run --help` and the README.
constexpr long long kMaxTrials = 1'000'000;   // trial indices per group
constexpr long long kMaxThreads = 1024;       // oneTBB arena size (0 = all cores)
constexpr std::size_t kMaxExperimentName = 200;

// Throws UsageError unless path is a usable path for an output (non-empty, no NUL).
void check_output_path(const std::string& path, const std::string& what);

// Experiment names become folders under --witness-dir: letters, digits, '.', '_', '-', '+', and
// '/' between non-empty parts that are not '.' or '..'. Throws UsageError naming the problem.
void check_experiment_name(const std::string& name);

// One group of trials: a suite instance, a method with its options, limits and a master seed.
struct TrialGroupSpec {
  std::string experiment = "default";
  const SuiteEntry* suite = nullptr;
  const MethodEntry* method = nullptr;
  Settings settings;  // each key routed to the suite's parameters first, then the method's options
  int trials = 10;
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
  std::uint64_t seed = 1;
  int priority = 0;  // TrialJob::priority of its trials: a sweep's later (larger) columns first
};

// A spec resolved: the instance and options in canonical JSON, the system built, the trial key.
struct TrialGroup {
  TrialGroupSpec spec;
  Json instance, options, config;
  std::shared_ptr<const System> system;
  TrialKey base;  // trial_index 0

  // Whether a stored trial belongs to this group (same key but the index, index < trials).
  bool contains(const TrialRecord& record) const;
};

// Routes and resolves the settings and builds the system; writes nothing. Throws UsageError for
// a setting neither the suite nor the method has, or an instance the suite rejects, and
// OptionError for a value of the wrong type.
TrialGroup resolve_trial_group(const TrialGroupSpec& spec);

// The jobs of the group's trial indices 0..trials-1 not in `stored`, with their seeds. With a
// shard, only the indices i whose position first_position + i in the full job list the shard
// keeps (a table's groups follow one another in one list; see distinct_groups).
std::vector<TrialJob> prepare_jobs(const TrialGroup& group, const std::set<std::int64_t>& stored,
                                   const Shard& shard = {}, std::int64_t first_position = 0);

// The groups in this order without those that resolve to the same trials as an earlier one
// (same suite, instance, method and config): a table's rows may share trials.
std::vector<const TrialGroup*> distinct_groups(const std::vector<const TrialGroup*>& groups);

// Parses --shard (empty: the whole job list); throws UsageError naming --shard for a bad value.
Shard shard_option(const std::string& text);

// Engine options both commands use (host, git commit, progress on a terminal).
EngineOptions make_engine_options(int threads, const std::string& witness_dir, bool progress);

// What run_jobs did.
struct JobsRun {
  std::size_t run_now = 0;  // trials this process ran and stored
  std::size_t errors = 0;   // jobs stored with status error at the end (by this or another process)
};

// Runs `jobs` into `store` so that several processes started on the same jobs and database
// cooperate (both `run` and `reproduce` run their trials through it). Each job is claimed in
// the database right before it starts; one that another live process has claimed, or stored,
// is skipped. Afterwards, jobs that are neither stored nor claimed by a live process (their
// owner died: kill -9, a lost host) are run here, and jobs that other processes still run are
// waited for (polling every 0.2 s, with a note on a terminal), until every job is stored. Prints
// one line per trial that ended in error here. Throws what the engine throws (EnvironmentError,
// StoreError), after stopping the trials in flight and releasing this process's claims.
JobsRun run_jobs(const std::vector<TrialJob>& jobs, TrialStore& store, const EngineOptions& engine);

// Where and how the trials of a command run.
struct RunOptions {
  int threads = 0;
  std::string db, witness_dir;
  Shard shard;
  bool plan = false;      // --plan: print the sizing, run nothing, write nothing
  bool progress = false;  // a progress line on stderr (on a terminal)
  bool quiet = false;     // no "resuming" note
  bool save_trees = false;  // --save-trees: each witness's search tree(s) beside it (EngineOptions)
};

// RunOptions from a command's parsed arguments (ExperimentArgs, ReproduceArgs): the options they
// share, under the same names; `quiet` where the command has it (it also turns off the progress
// line). Shard strings must have been checked (shard_option).
template <class Args>
RunOptions run_options_of(const Args& a) {
  RunOptions o;
  o.threads = a.threads;
  o.db = a.db;
  o.witness_dir = a.witness_dir;
  o.shard = shard_option(a.shard);
  o.plan = a.plan;
  o.save_trees = a.save_trees;
  if constexpr (requires { a.quiet; }) o.quiet = a.quiet;
  o.progress = !o.quiet && isatty(STDERR_FILENO) != 0;
  return o;
}

// What run_groups ran and stored.
struct GroupsRun {
  TrialStore store;
  EngineOptions engine;
  std::size_t total = 0;          // trials of the distinct groups in the shard
  std::size_t stored_before = 0;  // of them already stored (resumed)
  std::size_t run_now = 0;        // run and stored by this process
  std::size_t errors = 0;         // stored with status error
  std::vector<std::vector<TrialRecord>> trials;  // per group (as given): its stored trials
};

// The pipeline after resolve (resolve_trial_group, every input checked): plan, or run and store,
// then the stored trials of each group for the caller's report. With options.plan it prints the
// plan of `what` and returns nothing. Otherwise it opens options.db, runs the trials of the
// distinct groups (distinct_groups, in this order; a group's trial 0 at the position after the
// previous group's trials in the job list that --shard divides) that the store does not hold,
// through run_jobs, noting on stderr how many were already stored (unless quiet), and loads
// each group's stored trials. options.save_trees under mpirun is refused (UsageError) before the
// database opens: the workers' results do not carry trees.
std::optional<GroupsRun> run_groups(const std::string& what, const std::vector<const TrialGroup*>& groups,
                                    const RunOptions& options);

// Control characters escaped (\xNN), so that a message quoting a file's text stays one line.
std::string one_line(std::string_view text);

// The text of an input file; throws UsageError naming the file if it cannot be read.
std::string read_input_file(const std::string& path);

}  // namespace hyfal
