// The Planner interface: grow a search (tree, forest, ...) until a state with s <= 0 is found,
// the time or node budget is spent, or the trial is cancelled.
#pragma once
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stop_token>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/trajectory.hpp"
#include "core/trial_record.hpp"

namespace hyfal {

class TrialCpuClock;  // core/trial_cpu.hpp

struct PlannerLimits {
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
};

struct PlannerContext {
  const System& system;
  std::span<const double> parameters;  // p, for methods that do not search P
  std::uint64_t seed = 0;
  PlannerLimits limits;
  std::stop_token stop;  // cooperative cancellation
  // The trial's CPU clock: task bodies a planner runs on other threads go through cpu->task()
  // (core/trial_cpu.hpp) so that cpu_s counts them; null outside the trial engine.
  TrialCpuClock* cpu = nullptr;
};

struct PlannerCounters {
  std::int64_t nodes = 0;
  std::int64_t propagations = 0;
  std::int64_t integration_steps = 0;
};

// A per-trial progress series, e.g. coverage against nodes (stored in the `series` table).
struct NamedSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;
};

struct PlannerOutcome {
  // falsified (a state with s <= 0 was reached; the engine validates the trajectory),
  // not_found (the method gave up), timeout, node_cap.
  TrialStatus status = TrialStatus::not_found;
  PlannerCounters counters;
  std::optional<Trajectory> trajectory;  // set when falsified
  Json metrics = Json::object();         // method-specific scalars (coverage, beta, trees, ...)
  std::vector<NamedSeries> series;
};

class Planner {
 public:
  virtual ~Planner() = default;
  virtual PlannerOutcome solve(const PlannerContext& ctx) = 0;
};

// Why a search loop must stop now, if it must: the budget checks every planner shares.
class SearchBudget {
 public:
  explicit SearchBudget(const PlannerContext& ctx) : ctx_(ctx), deadline_(deadline_after(ctx.limits.timeout_s)) {}
  // nullopt while the search may go on.
  std::optional<TrialStatus> exhausted(std::int64_t nodes) const {
    if (nodes >= ctx_.limits.max_nodes) return TrialStatus::node_cap;
    if (ctx_.stop.stop_requested()) return TrialStatus::timeout;
    if (std::chrono::steady_clock::now() >= deadline_) return TrialStatus::timeout;
    return std::nullopt;
  }
  // The same deadline and cancellation, for a Propagator (a long propagation ends early).
  PropagationInterrupt interrupt() const { return {deadline_, ctx_.stop}; }

 private:
  // now + seconds, saturated: a timeout beyond half of what the clock can still count (about
  // 146 years), or NaN, means no deadline rather than an overflow into the past.
  static std::chrono::steady_clock::time_point deadline_after(double seconds) {
    using Clock = std::chrono::steady_clock;
    const auto now = Clock::now();
    const double room = std::chrono::duration<double>(Clock::time_point::max() - now).count();
    if (!(seconds < 0.5 * room)) return Clock::time_point::max();
    return now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  }

  const PlannerContext& ctx_;
  std::chrono::steady_clock::time_point deadline_;
};

// A declared setting (a method option or a suite's instance parameter): key, default (its JSON
// type is the setting's type), help text and the valid values, declared once beside the default
// (as OMPL's declareParam does with a range string):
//   "[1, 1000]", "(0, 1]", "[0, inf)"  an interval (integers and numbers; inf allowed as a bound)
//   "metric|t2go"                      the allowed strings
//   ""                                 any value of the type (booleans only; a test checks)
// core/options.hpp checks values against it; `hyfal list` prints it.
struct OptionSpec {
  std::string key;
  Json default_value;
  std::string help;
  std::string range = {};
};

struct MethodEntry {
  std::string name;
  std::string description;
  std::vector<OptionSpec> options;
  std::function<std::unique_ptr<Planner>(const Json& options)> make;
  // What the method needs of a system beyond the common interface (e.g. HyDICE a region
  // decomposition): throws std::invalid_argument naming what is missing. Empty: any system.
  // Checked when a run is resolved, before anything is written.
  std::function<void(const System& system, const Json& options)> check_system = {};
};

// The method registry (core/planners/registry.cpp): one line per method.
const std::vector<MethodEntry>& all_methods();
const MethodEntry* find_method(std::string_view name);

}  // namespace hyfal
