// Trials in OMPL's benchmark log format (`hyfal table --format ompl-log`), so that OMPL's
// ompl_benchmark_statistics.py loads them into a benchmark database for Planner Arena. Written
// from the trial records alone (no OMPL needed), after the grammar OMPL documents ("The benchmark
// logfile format", doc/markdown/benchmark.md; what ompl::tools::Benchmark::saveResultsToStream
// writes):
//   one experiment per (suite, instance) of the trials, named "<suite>:<instance JSON>";
//   numeric instance parameters as experiment properties "instance_<key> INTEGER|REAL = v";
//   one planner per method (per (method, config) where a method ran with several configs: then
//   named "<method> <config JSON>"), its common properties the method, options and caps;
//   one run per trial, in trial order, with the run properties
//     time REAL (wall_s), cpu time REAL (cpu_s), solved BOOLEAN (status falsified),
//     correct solution BOOLEAN (validated; empty unless solved), graph states INTEGER (nodes),
//     propagations INTEGER, integration steps INTEGER, hyfal status ENUM (the enum
//     hyfal_status: falsified|not_found|timeout|node_cap|budget|error), trial index INTEGER,
//     seed INTEGER.
//   Preamble: "hyfal version V", the earliest started_at, the hosts, the master seed (0 when the
//   trials differ in it), the largest timeout as the time limit, 0 MB memory limit (hyfal sets
//   none), runs per planner when every planner has the same count, the sum of wall_s as the
//   total time.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "core/run/trial_record.hpp"

namespace hyfal {

struct OmplLog {
  std::string suite, instance;  // the experiment's (suite, instance)
  std::string text;             // one complete log file
};

// One log per (suite, instance), ordered by suite, then instance.
std::vector<OmplLog> to_ompl_logs(std::span<const TrialRecord> trials);

}  // namespace hyfal
