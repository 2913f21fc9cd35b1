// The trial engine: runs (suite instance x method x trial index) jobs on a oneTBB task arena,
// one single-threaded trial per task. Each finished trial is handed to the sink at once (under
// a lock), so the caller can commit it before the next one ends.
#pragma once
#include <functional>
#include <memory>
#include <stop_token>
#include <string>
#include <vector>

#include "core/planner.hpp"
#include "core/trial_record.hpp"

namespace hyfal {

struct TrialJob {
  TrialKey key;
  std::shared_ptr<const System> system;
  const MethodEntry* method = nullptr;
  Json method_options;
  PlannerLimits limits;
  std::int64_t seed = 0;  // from trial_seed(): never from the thread
};

struct EngineOptions {
  int threads = 0;          // 0: all cores
  std::string witness_dir;  // where witnesses of falsifying trials are written
  bool progress = false;    // a progress line on stderr
  std::string host, git_commit;
  std::stop_token cancel;
};

using TrialSink = std::function<void(const TrialRecord&)>;

// Runs one trial on the calling thread. Never throws: failures become status error.
TrialRecord run_trial(const TrialJob& job, const EngineOptions& options);

// Runs all jobs on `options.threads` threads; `sink` is called once per trial, serialized.
void run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink);

// Where the witness of a trial goes: DIR/EXPERIMENT/SUITE/METHOD/<hash of instance+config>-t<index>.json
std::string witness_path(const std::string& dir, const TrialKey& key);

int default_thread_count();
std::string iso8601_now();
std::string host_name();

}  // namespace hyfal
