// TraceMonitor: the robustness of a simulated trace for a requirement, and the verdict of a trace
// that may end before the requirement's horizon (judge_prefix: what `hyfal simulate` prints, and
// the rule the witness validator applies).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness.hpp"
#include "core/simulate/input_simulator.hpp"

namespace hyfal::stl {

// What a trace says of a requirement. A trace that reaches the requirement's horizon gives
// ρ(φ, 0) itself (bounds.lower == bounds.upper); so does any trace for a requirement without a
// horizon (an unbounded operator): it is judged as it ends, as the searches judge theirs. A
// shorter trace is a prefix: its bounds hold ρ(φ, 0) of every extension (robustness.hpp), and
// may decide the verdict all the same.
struct TraceVerdict {
  Interval bounds;
  double horizon = 0.0;  // the requirement's (+inf: unbounded)
  bool complete = true;  // the trace reaches the horizon
  bool falsified() const { return bounds.upper < 0.0; }
  bool satisfied() const { return bounds.lower >= 0.0; }
  bool decided() const { return falsified() || satisfied(); }
};

// The verdict of `trace` (at least one sample) for the monitor's formula: complete when it
// reaches the formula's horizon (up to 1e-9 relative: durations summed by rounding), judged as
// TraceVerdict says.
TraceVerdict judge_prefix(OfflineMonitor& monitor, const TraceView& trace);

// The robustness of traces of one system for one requirement, with its buffers kept.
class TraceMonitor {
 public:
  explicit TraceMonitor(const Requirement& requirement);
  // ρ(φ, 0) of the trace as it ends (whatever the horizon).
  double robustness(const SimulatedTrace& trace);
  TraceVerdict judge(const SimulatedTrace& trace);
  // The robustness interval of the trace's first `samples` samples as a prefix (every
  // extension's ρ(φ, 0) lies in it: robustness.hpp), e.g. up to a piece_ends entry;
  // closed_at_last_time: of the extensions that add no further sample at the prefix's last time.
  Interval prefix_bounds(const SimulatedTrace& trace, std::size_t samples, bool closed_at_last_time = false);
  // ρ(φ, 0) of the simulation of `pieces` (as it ends) and its gradient with respect to the signal's
  // control points (InputSimulator::run_with_tangents's arguments; points × m values into
  // `gradient`): a subgradient, the monitor's critical samples (OfflineMonitor::critical_samples)
  // times their tangents (InputSimulator::add_signal_tangents). One run of `simulator` with its
  // tangents (the same trace as a plain run, bit for bit, which stays in the simulator), or for a
  // long trace a plain run first and then one that keeps only the critical samples' tangents. NaN
  // and a zero gradient for a trace without samples.
  // path = every_blocking: a descent direction for falsification instead (CriticalPath).
  // parameter_gradient (when not empty, p.size() values): ∂ρ/∂p as well.
  double robustness_gradient(InputSimulator& simulator, std::span<const InputPiece> pieces,
                             std::span<const ControlWeights> weights, std::size_t points, std::span<const double> p,
                             std::span<double> gradient, CriticalPath path = CriticalPath::attaining,
                             std::span<double> parameter_gradient = {});

 private:
  // The requirement's signals of the trace's first `samples` samples (all: SIZE_MAX), as the
  // monitor reads them (in values_).
  TraceView view(const SimulatedTrace& trace, std::size_t samples = SIZE_MAX);
  const Requirement& requirement_;
  OfflineMonitor monitor_;
  std::vector<double> values_;
  std::vector<SampleWeight> critical_;
  std::vector<std::size_t> keep_;
  std::vector<InputSimulator::SignalTerm> terms_;
  std::size_t last_samples_ = 0;  // the last robustness_gradient's trace
};

// The robustness of a simulated trace for a requirement of the same system (its sources index
// the trace's signals).
double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace);

}  // namespace hyfal::stl
