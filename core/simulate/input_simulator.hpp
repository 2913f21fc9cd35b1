// Simulating a system under a given input signal, sampled as the searches sample (STL mode of the
// propagator: every integration step, both sides of every transition, entries into s <= 0):
// what `hyfal simulate` writes, and how a test or a user checks a model or replays someone
// else's counterexample (an ARCH-COMP input CSV).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/model.hpp"
#include "core/trajectory.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness.hpp"

namespace hyfal::stl {

// u held for `duration` seconds.
struct InputPiece {
  double duration = 0.0;
  std::vector<double> u;
};

// Every signal of the system (system_signals order) at every sample.
struct SimulatedTrace {
  std::vector<double> time;
  std::vector<std::vector<double>> signals;  // [signal][sample]
  // How the simulation ended: completed (every piece flowed), invariant (the system's invariant,
  // e.g. its horizon, ended it early: the trace stops there), rejected (a non-finite state, or
  // more than 10^4 transitions at one instant).
  PropagationEnd end = PropagationEnd::completed;
  // Set when the input signal does not fit the system (the end is then rejected): an input outside
  // the current mode's input box U_q (a suite whose U_q differs between modes, like the
  // thermostat's, cannot be driven by one signal).
  std::string problem;
  std::int64_t integration_steps = 0;  // over every propagation, the interrupted one included
  std::int64_t transitions = 0;        // discrete transitions taken (mode switches, shifts)
  // piece_ends[k]: the samples recorded by the end of input piece k (its last sample's index + 1),
  // for every piece that flowed to its end; the samples after it belong to the next piece (a
  // shift its new input causes at once included). The prefix of the first k + 1 pieces.
  std::vector<std::size_t> piece_ends;
  std::size_t samples() const { return time.size(); }
};

// The signal through control points (times[k], values[k]), linear between consecutive ones (S-TaLiRo's
// and Breach's default interpolation; the Simulink trace's inputs), as pieces of constant input:
// each interval cut into ceil(length / step) equal pieces holding the line's value at their
// midpoints (the integral of the input over each piece is exact; a model affine in u sees the
// exact input mean over every integration step when step is its integrator's). Times increase;
// values.size() == times.size(). The signal ends at the last control point.
// The line from a to b at weight w in [0, 1], kept between a and b (a rounding of the line must
// not step outside an input box whose bound is a or b).
inline double linear_value(double a, double b, double w) {
  const double v = (1.0 - w) * a + w * b;
  return a <= b ? (v < a ? a : v > b ? b : v) : (v < b ? b : v > a ? a : v);
}

std::vector<InputPiece> linear_signal_pieces(std::span<const double> times, std::span<const std::vector<double>> values,
                                             double step);

// A model known only by its simulations (System::signal_model: a black box, such as a Python
// function, core/black_box.hpp): the output signals of an input signal, from time 0. The samples
// it returns are its own (any times, increasing); the simulators below add the inputs held at
// each sample and the safety signal. A prefix of its trace (the adaptive search's pruning) is
// sound only for a causal model: outputs up to t that depend on the inputs up to t only.
class SignalModel {
 public:
  virtual ~SignalModel() = default;
  // The outputs (SystemInfo::outputs order) at `time`, for `pieces` (each u held for its duration)
  // with parameters p; `time` and each of `outputs` are overwritten, `time` reaching the pieces'
  // end (InputSimulator refuses a shorter trace with std::runtime_error: a model that stops early
  // breaks its contract). Throws std::runtime_error with the model's own message when it fails or
  // returns something malformed.
  virtual void simulate(std::span<const InputPiece> pieces, std::span<const double> p, std::vector<double>& time,
                        std::vector<std::vector<double>>& outputs) const = 0;
};

// An input signal given at samples, as `hyfal simulate` reads it from a CSV and the Python module
// from arrays: values[k] (one per input) at times[k]; held from times[k] to times[k + 1] (zoh), or,
// with linear_step > 0, the line through the samples cut into pieces of at most linear_step
// (linear_signal_pieces). What either accepts: at least two samples, times from 0 and increasing,
// each value inside `box` up to 1e-9 (then clamped into it). The first sample that breaks it, in
// sample order and, within a sample, time first, then the inputs in order.
struct SampledSignalProblem {
  enum class Kind { too_few, first_time, not_increasing, outside } kind;
  std::size_t sample = 0, input = 0;  // input: for `outside`
  double value = 0.0;                 // the time (first_time, not_increasing) or the value (outside)
};
std::optional<SampledSignalProblem> sampled_signal_problem(std::span<const double> times,
                                                          std::span<const std::vector<double>> values, const Box& box);
// The pieces of a signal sampled_signal_problem accepts (values clamped into `box`).
std::vector<InputPiece> sampled_signal_pieces(std::span<const double> times, std::vector<std::vector<double>> values,
                                              const Box& box, double linear_step);
// The pieces a linear signal is cut into for `info`'s system: its integrator's (largest) step.
double linear_piece_step(const SystemInfo& info);
// The input `name` names: an input's name or an alias the suite declares (SystemInfo::input_aliases,
// e.g. ARCH-COMP's `throttle`), case-insensitively; info.input_names.size() when none.
std::size_t input_named(const SystemInfo& info, std::string_view name);

// Simulates `system` from its initial state with parameters p under `pieces` (each u of the
// system's input dimension). Throws std::invalid_argument on a piece of the wrong size or a
// negative or non-finite duration.
SimulatedTrace simulate_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p);

// The same, for many simulations of one system (an optimiser's): the propagator and the trace's
// buffers are kept between runs, so a run allocates nothing once the longest trace has been seen.
class InputSimulator {
 public:
  explicit InputSimulator(const System& system);
  ~InputSimulator();
  // The trace of `pieces`, valid until the next run.
  const SimulatedTrace& run(std::span<const InputPiece> pieces, std::span<const double> p);
  // The last run's trace (empty before the first).
  const SimulatedTrace& trace() const;
  // A trial's deadline and cancellation, which also end a simulation in flight (its end is then
  // rejected and interrupted() true, for this run and every later one).
  void set_interrupt(PropagationInterrupt interrupt);
  bool interrupted() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What a trace says of a requirement. A trace that reaches the requirement's horizon gives
// ρ(φ, 0) itself (bounds.lower == bounds.upper); so does any trace for a requirement without a
// horizon (an unbounded operator): it is judged as it ends, as the searches judge theirs. A
// shorter trace is a prefix: its bounds hold ρ(φ, 0) of every extension (robustness.hpp), and
// may decide the verdict all the same.
struct TraceVerdict {
  Interval bounds;
  double horizon = 0.0;   // the requirement's (+inf: unbounded)
  bool complete = true;   // the trace reaches the horizon
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

// The execution under `pieces` as a witness's trajectory (core/trajectory.hpp): one piece per
// flow between transitions (an input piece cut at each transition), each piece's end state before
// its reset, as the validator re-simulates them; it ends where simulate_inputs ends.
Trajectory trajectory_of_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p);

// The robustness of a simulated trace for a requirement of the same system (its sources index
// the trace's signals).
double trace_robustness(const Requirement& requirement, const SimulatedTrace& trace);

}  // namespace hyfal::stl
