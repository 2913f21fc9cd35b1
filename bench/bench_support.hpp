// Helpers shared by the hyfal microbenchmarks.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/options.hpp"
#include "suites/registry.hpp"

namespace hyfal::bench {

// A thermostat instance: the defaults, with `overrides` as `key=value` settings would give them.
inline std::shared_ptr<const System> thermostat(
    const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  const SuiteEntry* suite = find_suite("thermostat");
  if (suite == nullptr) throw std::runtime_error("the thermostat suite is not registered");
  return suite->make(resolve_options(suite->parameters, overrides));
}

// Adds a counter of CPU seconds per one of `count` items (per integration step, per node):
// Google Benchmark divides a rate counter by the CPU time and kInvert takes the reciprocal.
// The console prints it with an SI prefix, e.g. "52.2ns".
inline void report_time_per(benchmark::State& state, const char* name, double count) {
  state.counters[name] =
      benchmark::Counter(count, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace hyfal::bench
