#include "core/requirements/trace_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

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

double TraceMonitor::robustness_gradient(InputSimulator& simulator, std::span<const InputPiece> pieces,
                                         std::span<const ControlWeights> weights, std::size_t points,
                                         std::span<const double> p, std::span<double> gradient,
                                         CriticalPath path) {
  const std::size_t vars = points * (pieces.empty() ? 0 : pieces[0].u.size());
  if (gradient.size() != vars)
    throw std::invalid_argument(
        fmt::format("robustness_gradient: room for {} values, {} expected", gradient.size(), vars));
  std::fill(gradient.begin(), gradient.end(), 0.0);
  critical_.clear();
  keep_.clear();
  double rho = std::numeric_limits<double>::quiet_NaN();
  const SimulatedTrace& plain = simulator.run(pieces, p);
  // A run the deadline cut short, or one that did not fit the system, stays as it is: no gradient.
  if (simulator.interrupted() || !plain.problem.empty())
    return plain.time.empty() ? rho : monitor_.robustness(view(plain));
  const std::size_t samples = plain.time.size();
  if (!plain.time.empty()) {
    rho = monitor_.robustness_at_every_sample(view(plain));
    monitor_.critical_samples(critical_, path);
    // One term per signal and sample (a spread path reaches a sample many times).
    std::sort(critical_.begin(), critical_.end(), [](const SampleWeight& a, const SampleWeight& b) {
      return a.sample != b.sample ? a.sample < b.sample : a.signal < b.signal;
    });
    std::size_t merged = 0;
    for (const SampleWeight& c : critical_) {
      if (merged > 0 && critical_[merged - 1].sample == c.sample && critical_[merged - 1].signal == c.signal)
        critical_[merged - 1].weight += c.weight;
      else
        critical_[merged++] = c;
    }
    critical_.resize(merged);
    for (const SampleWeight& c : critical_) keep_.push_back(c.sample);
    std::sort(keep_.begin(), keep_.end());
    keep_.erase(std::unique(keep_.begin(), keep_.end()), keep_.end());
  }
  const SimulatedTrace& trace = simulator.run_with_tangents(pieces, weights, points, p, keep_);  // the same trace
  if (simulator.interrupted() || trace.time.size() != samples) return rho;
  tangent_.resize(vars);
  for (const SampleWeight& c : critical_) {
    simulator.signal_tangent(static_cast<std::size_t>(requirement_.sources[c.signal]), c.sample, tangent_);
    for (std::size_t v = 0; v < vars; ++v) gradient[v] += c.weight * tangent_[v];
  }
  return rho;
}

double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace) {
  TraceMonitor monitor(requirement);
  return monitor.robustness(trace);
}

}  // namespace hyfal::stl
