#include "core/requirements/trace_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace hyfal::stl {

TraceMonitor::TraceMonitor(const Requirement& requirement) : requirement_(requirement), monitor_(requirement.formula) {}

TraceView TraceMonitor::view(const SimulatedTrace& trace, std::size_t samples) {
  const std::size_t n = std::min(samples, trace.time.size());
  values_.clear();
  for (int s : requirement_.sources)
    values_.insert(values_.end(), trace.signals[s].begin(), trace.signals[s].begin() + n);
  return TraceView{std::span<const double>(trace.time).first(n), values_};
}

double TraceMonitor::robustness(const SimulatedTrace& trace) { return monitor_.robustness(view(trace)); }

TraceVerdict judge_prefix(OfflineMonitor& monitor, const TraceView& trace) {
  TraceVerdict v;
  v.horizon = monitor.formula().horizon();
  const double end = trace.time.empty() ? 0.0 : trace.time.back();
  // The pieces' durations are summed: a trace meant to end at the horizon may fall short of it
  // by rounding.
  v.complete = !std::isfinite(v.horizon) || end >= v.horizon - 1e-9 * std::max(1.0, v.horizon);
  if (v.complete) {
    const double rho = monitor.robustness(trace);
    v.bounds = {rho, rho};
  } else {
    v.bounds = monitor.robustness_interval(trace, false);
  }
  return v;
}

TraceVerdict TraceMonitor::judge(const SimulatedTrace& trace) { return judge_prefix(monitor_, view(trace)); }

Interval TraceMonitor::prefix_bounds(const SimulatedTrace& trace, std::size_t samples, bool closed_at_last_time) {
  return monitor_.robustness_interval(view(trace, samples), false, closed_at_last_time);
}

double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace) {
  TraceMonitor monitor(requirement);
  return monitor.robustness(trace);
}

}  // namespace hyfal::stl
