// Helpers shared by the hyfal microbenchmarks.
#pragma once
#include <cstdint>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "suites/registry.hpp"

namespace hyfal::bench {

// `count` points uniform in [0, 1]^dim, row-major. A fixed seed: every run sees the same cloud.
inline std::vector<double> uniform_cloud(std::size_t count, std::size_t dim, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> points(count * dim);
  for (double& v : points) v = unit(rng);
  return points;
}

// An instance of the registered suite `name`: its defaults, with `overrides` as `key=value`
// settings would give them.
inline std::shared_ptr<const System> suite_instance(
    const std::string& name, const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  const SuiteEntry* suite = find_suite(name);
  if (suite == nullptr) throw std::runtime_error("the " + name + " suite is not registered");
  return suite->make(resolve_options(suite->parameters, overrides));
}

// A thermostat instance: the defaults, with `overrides` as `key=value` settings would give them.
inline std::shared_ptr<const System> thermostat(
    const std::vector<std::pair<std::string, std::string>>& overrides = {}) {
  return suite_instance("thermostat", overrides);
}

// Adds a counter of CPU seconds per one of `count` items (per integration step, per node):
// Google Benchmark divides a rate counter by the CPU time and kInvert takes the reciprocal.
// The console prints it with an SI prefix, e.g. "52.2ns".
inline void report_time_per(benchmark::State& state, const char* name, double count) {
  state.counters[name] =
      benchmark::Counter(count, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// What an optimiser pays per simulation of a suite's instance: its input signal through
// stl::InputSimulator (every signal sampled at every integration step and at both sides of every
// jump) and the robustness of the requirement `requirement_id`. Items are simulations.
inline void simulate_with_robustness(benchmark::State& state, const System& sys, const std::string& requirement_id,
                                     const std::vector<stl::InputPiece>& pieces) {
  const stl::Requirement req = stl::resolve_requirement(sys.info(), requirement_id);
  stl::InputSimulator simulator(sys);
  stl::TraceMonitor monitor(req);
  double rho = 0.0;
  for (auto _ : state) {
    rho = monitor.robustness(simulator.run(pieces, sys.info().parameters));
    benchmark::DoNotOptimize(rho);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["samples"] = static_cast<double>(simulator.trace().samples());
  state.counters["robustness"] = rho;
}

}  // namespace hyfal::bench
