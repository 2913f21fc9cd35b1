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
                                         CriticalPath path, std::span<double> parameter_gradient) {
  const std::size_t vars = points * (pieces.empty() ? 0 : pieces[0].u.size());
  if (gradient.size() != vars)
    throw std::invalid_argument(
        fmt::format("robustness_gradient: room for {} values, {} expected", gradient.size(), vars));
  if (!parameter_gradient.empty() && parameter_gradient.size() != p.size())
    throw std::invalid_argument(fmt::format("robustness_gradient: room for {} parameter slopes, {} parameters",
                                            parameter_gradient.size(), p.size()));
  const bool parameters = !parameter_gradient.empty();
  std::fill(gradient.begin(), gradient.end(), 0.0);
  std::fill(parameter_gradient.begin(), parameter_gradient.end(), 0.0);
  critical_.clear();
  keep_.clear();
  double rho = std::numeric_limits<double>::quiet_NaN();
  // One simulation with its tangents, which keeps every sample's (the trace is run()'s, bit for
  // bit), unless the last trace had so many samples that recording them costs more than a plain
  // run that finds the critical samples first. Measured with bench_gradient (issue 55): NN's
  // 24,000 samples of 155 numbers are 30 MB a simulation (121× a plain run kept, 23× in two
  // runs); CC5's 5,000 of 167 cost 3× a plain run in copies alone; AT1's 2,000 of 34 are cheap.
  constexpr std::size_t kRecordAtMost = std::size_t{1} << 18;  // numbers (2 MB)
  const bool two_runs = last_samples_ * simulator.tangent_sample_size(parameters) > kRecordAtMost;
  const SimulatedTrace& first =
      two_runs ? simulator.run(pieces, p) : simulator.run_with_tangents(pieces, weights, points, p, {}, parameters);
  // A run the deadline cut short, or one that did not fit the system, stays as it is: no gradient.
  if (simulator.interrupted() || !first.problem.empty())
    return first.time.empty() ? rho : monitor_.robustness(view(first));
  const std::size_t samples = first.time.size();
  last_samples_ = samples;
  if (samples == 0) return rho;
  rho = monitor_.robustness_at_every_sample(view(first));
  monitor_.critical_samples(critical_, path);
  // One term per signal and sample (a spread path reaches a sample many times): each term costs
  // the signal's slopes at its sample.
  std::sort(critical_.begin(), critical_.end(), [](const SampleWeight& a, const SampleWeight& b) {
    return a.sample != b.sample ? a.sample < b.sample : a.signal < b.signal;
  });
  if (two_runs) {
    for (const SampleWeight& c : critical_) keep_.push_back(c.sample);
    keep_.erase(std::unique(keep_.begin(), keep_.end()), keep_.end());  // critical_ is sorted by sample
    const SimulatedTrace& trace = simulator.run_with_tangents(pieces, weights, points, p, keep_, parameters);
    if (simulator.interrupted() || trace.time.size() != samples) return rho;
  }
  terms_.clear();
  for (const SampleWeight& c : critical_) {
    const auto signal = static_cast<std::size_t>(requirement_.sources[c.signal]);
    if (!terms_.empty() && terms_.back().sample == c.sample && terms_.back().signal == signal)
      terms_.back().weight += c.weight;
    else
      terms_.push_back({signal, c.sample, c.weight});
  }
  simulator.add_signal_tangents(terms_, gradient, parameter_gradient);
  return rho;
}

double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace) {
  TraceMonitor monitor(requirement);
  return monitor.robustness(trace);
}

}  // namespace hyfal::stl
