// The trial engine: runs (suite instance x method x trial index) jobs on a oneTBB task arena,
// one single-threaded trial per task. Each finished trial is handed to the sink at once (under
// a lock), so the caller can commit it before the next one ends.
#pragma once
#include <functional>
#include <memory>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <vector>

#include "core/util/files.hpp"  // EnvironmentError
#include "core/run/planner.hpp"
#include "core/run/method_entry.hpp"
#include "core/run/trial_record.hpp"

namespace hyfal {

struct TrialJob {
  TrialKey key;
  std::shared_ptr<const System> system;
  const MethodEntry* method = nullptr;
  Json method_options;
  PlannerLimits limits;
  std::int64_t seed = 0;  // from trial_seed(): never from the thread
  // Larger first: a distributed run hands out jobs of higher priority first (a table knows its
  // expensive cells), so long trials do not start last and leave ranks idle at the end.
  int priority = 0;
};

struct EngineOptions {
  int threads = 0;          // 0: all cores
  std::string witness_dir;  // where witnesses of falsifying trials are written
  bool progress = false;    // a progress line on stderr
  std::string host, git_commit;
  std::stop_token cancel;
  // --save-trees: a falsifying trial's search tree(s) go beside its witness (tree_path), as
  // tree_file_text writes them. Off, the planners record nothing (PlannerContext::trees null).
  bool save_trees = false;
};

using TrialSink = std::function<void(const TrialRecord&)>;
// Called right before a job starts (serialized with the sink and with other claims): false
// skips the job (e.g. another process runs it).
using TrialClaim = std::function<bool(const TrialJob&)>;

// What one trial produced before anything is written: its record and, for a falsifying trial,
// the text of its witness file (validated: record.validated says how it re-simulated).
struct TrialResult {
  TrialRecord record;
  std::string witness_text;  // empty when the trial has no witness
  std::string tree_text;     // with EngineOptions::save_trees and a witness: its tree file
};

// Runs one trial on the calling thread (and the arena's threads that help it) and writes
// nothing: failures of the trial become status error. A worker rank of a distributed run sends
// the result to rank 0, which keeps the witness and stores the record.
TrialResult compute_trial(const TrialJob& job, const EngineOptions& options);

// Writes the witness text (if any) to witness_path(witness_dir, key) atomically and records the
// path, and the tree text (if any) to tree_path of it first; nothing without a witness or a
// folder. Throws EnvironmentError if it cannot be written (no temporary file is left).
void keep_witness(TrialResult& result, const std::string& witness_dir);

// compute_trial, then keep_witness(options.witness_dir): the record as it is stored.
TrialRecord run_trial(const TrialJob& job, const EngineOptions& options);

// Runs all jobs on `options.threads` threads; `claim` (if set) is asked before each job starts,
// `sink` is called once per trial run, serialized. If a trial throws (EnvironmentError), or the
// sink or the claim throws, no further job starts, the trials in flight are asked to stop (the
// engine's own stop source, also stopped by options.cancel), their results are dropped (they
// rerun on resume), and the first exception is rethrown once every thread has returned.
void run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
                const TrialClaim& claim = {});

// Where the witness of a trial goes: DIR/EXPERIMENT/SUITE/METHOD/<hash of instance+config>-t<index>.json
std::string witness_path(const std::string& dir, const TrialKey& key);

// The tree file beside a witness (--save-trees): F.json -> F.tree.csv.
std::string tree_path(const std::string& witness_path);

// A tree file (format hyfal-tree/1, CSV): '#' comment lines saying what it holds, then a header
// row `tree,node,parent,mode,<state names>` and one row per node: the tree's index in the
// method's forest (trees in index order), the node's row within its tree, its parent's row (-1
// at a root; a parent's row is below its child's), its mode and its state (9 significant
// digits). More than max_edges edges (nodes that are not roots), or more than max_values state
// values, are subsampled deterministically: the roots and the nodes whose subtree holds at least
// s nodes, for the smallest s within both limits (each tree's trunk and branches without their
// last twigs: every kept edge is an edge of the tree, and the tree keeps its reach); a comment
// line says so and gives s.
inline constexpr std::size_t kTreeFileMaxEdges = 50'000;
inline constexpr std::size_t kTreeFileMaxValues = 2'000'000;
std::string tree_file_text(const TreeRecorder& trees, const SystemInfo& info, std::size_t max_edges = kTreeFileMaxEdges,
                           std::size_t max_values = kTreeFileMaxValues);

int default_thread_count();
std::string iso8601_now();
std::string host_name();

}  // namespace hyfal
