// The trial engine in tests: each job's outcome as one comparable line, at a given thread count,
// so that a test can show a method's results do not depend on the threads.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "parallel/trial_engine.hpp"

namespace hyfal::test_support {

// Runs `jobs` on `threads` threads; one line per job, in the jobs' order: its status, nodes,
// integration steps and metrics. `each` (optional) sees every record as it comes.
inline std::vector<std::string> outcomes_at(const std::vector<TrialJob>& jobs, int threads,
                                            const std::function<void(const TrialRecord&)>& each = {}) {
  EngineOptions options;
  options.threads = threads;
  std::vector<std::string> out(jobs.size());
  run_trials(jobs, options, [&](const TrialRecord& r) {
    for (std::size_t i = 0; i < jobs.size(); ++i)
      if (jobs[i].key == r.key)
        out[i] = std::string(to_string(r.status)) + " " + std::to_string(r.nodes) + " " +
                 std::to_string(r.integration_steps) + " " + r.metrics;
    if (each) each(r);
  });
  return out;
}

}  // namespace hyfal::test_support
