// TraceMonitor: the robustness of a simulated trace for a requirement, and the verdict of a trace
// that may end before the requirement's horizon (judge_prefix: what `hyfal simulate` prints, and
// the rule the witness validator applies).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness.hpp"

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

 private:
  // The requirement's signals of the trace's first `samples` samples (all: SIZE_MAX), as the
  // monitor reads them (in values_).
  TraceView view(const SimulatedTrace& trace, std::size_t samples = SIZE_MAX);
  const Requirement& requirement_;
  OfflineMonitor monitor_;
  std::vector<double> values_;
};

// The robustness of a simulated trace for a requirement of the same system (its sources index
// the trace's signals).
double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace);

}  // namespace hyfal::stl
