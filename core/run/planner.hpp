// Planner: the interface every method implements: grow a search (tree, forest, ...) until a state with s <= 0 is found,
// the time or node budget is spent, or the trial is cancelled.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <vector>

#include "core/model/system.hpp"
#include "core/run/trial_record.hpp"
#include "core/search/node_store.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

class TrialCpuClock;  // core/util/trial_cpu_clock.hpp

struct PlannerLimits {
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
};

// One search tree as its planner left it: per node its parent, mode and state, in the order
// the nodes were added (a parent comes before its children).
struct RecordedTree {
  std::size_t index = 0;             // the tree's index in its planner's forest (0 for one tree)
  std::vector<std::int64_t> parent;  // -1 at a root
  std::vector<Mode> mode;
  std::vector<double> states;  // dim values per node
};

// The search trees of one trial, for pictures (`hyfal run --save-trees`; the engine writes them
// beside the witness, parallel/trial_engine.hpp). A planner given one (PlannerContext::trees)
// copies its node stores into it at the end of solve, after the witness is read off the tree, so
// recording changes nothing the search does; without one (the default) the planner does nothing
// more than test a null pointer once.
class TreeRecorder {
 public:
  explicit TreeRecorder(std::size_t dim) : dim_(dim) {}
  std::size_t dim() const { return dim_; }
  // Copies the published nodes of `nodes` (every one when no writer is active) as tree `index`.
  void add(std::size_t index, const NodeStore& nodes) {
    RecordedTree t;
    t.index = index;
    const std::size_t count = nodes.size();
    t.parent.reserve(count);
    t.mode.reserve(count);
    t.states.reserve(count * dim_);
    for (NodeId i = 0; i < count; ++i) {
      const NodeInfo& info = nodes.info(i);
      t.parent.push_back(info.parent == kNoNode ? -1 : static_cast<std::int64_t>(info.parent));
      t.mode.push_back(info.mode);
      const auto x = nodes.state(i);
      t.states.insert(t.states.end(), x.begin(), x.end());
    }
    add(std::move(t));
  }
  // A tree built elsewhere (OMPL's PlannerData): parent[i] < i or -1, states.size() == dim * nodes.
  void add(RecordedTree tree) {
    if (tree.states.size() != tree.parent.size() * dim_ || tree.mode.size() != tree.parent.size())
      throw std::logic_error("TreeRecorder: a tree's states, modes and parents differ in length");
    for (std::size_t i = 0; i < tree.parent.size(); ++i)
      if (tree.parent[i] >= static_cast<std::int64_t>(i) || tree.parent[i] < -1)
        throw std::logic_error("TreeRecorder: a node's parent must come before it");
    trees_.push_back(std::move(tree));
  }
  const std::vector<RecordedTree>& trees() const { return trees_; }

 private:
  std::size_t dim_;
  std::vector<RecordedTree> trees_;
};

struct PlannerContext {
  const System& system;
  std::span<const double> parameters;  // p, for methods that do not search P
  std::uint64_t seed = 0;
  PlannerLimits limits;
  std::stop_token stop;  // cooperative cancellation
  // The trial's CPU clock: task bodies a planner runs on other threads go through cpu->task()
  // (core/util/trial_cpu_clock.hpp) so that cpu_s counts them; null outside the trial engine.
  TrialCpuClock* cpu = nullptr;
  // Where the planner copies its search tree(s) at the end of solve (TreeRecorder); null: nowhere.
  TreeRecorder* trees = nullptr;
};

struct PlannerCounters {
  std::int64_t nodes = 0;
  std::int64_t propagations = 0;
  std::int64_t integration_steps = 0;
  double simulated_time = 0.0;  // flow time of every propagation (STL: simulations = this / horizon)
  // Adds o's propagation work (not its nodes: those are counted where they are committed).
  void add_work(const PlannerCounters& o) {
    propagations += o.propagations;
    integration_steps += o.integration_steps;
    simulated_time += o.simulated_time;
  }
};

// The start of a search falsifies at once: reachability, when s(x0) <= 0. (With an STL
// requirement the root's trace has one sample, decided by the first extension's monitor.)
inline bool starts_unsafe(const System& system, Mode q, std::span<const double> x, std::span<const double> p) {
  return !system.info().requirement && system.spec(q, x, p) <= 0.0;
}

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

}  // namespace hyfal
