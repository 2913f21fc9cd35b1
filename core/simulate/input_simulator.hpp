// InputSimulator: simulating a system under a given input signal, sampled as the searches sample (STL mode of the
// propagator: every integration step, both sides of every transition, entries into s <= 0):
// what `hyfal simulate` writes, and how a test or a user checks a model or replays someone
// else's counterexample (an ARCH-COMP input CSV).
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/model/system.hpp"
#include "core/simulate/input_signal.hpp"

namespace hyfal::stl {

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
  // The same simulation, with what the derivatives of its samples with respect to the signal's
  // control points need: weights[k] says how piece k's input depends on them (ControlWeights),
  // `points` control points of m inputs, so points × m search variables (point k's input j is
  // variable k m + j). The trace is run()'s, bit for bit. Throws std::logic_error when the system
  // has no tangents (has_tangents()), std::invalid_argument as run() does and for one weight per
  // piece missing or a point past `points`. keep: the samples add_signal_tangents will be asked
  // for, in increasing order (empty: every one); only theirs are recorded.
  //
  // How (core/simulate/tangent_model.hpp propagates the tangents): within each input piece, the
  // tangents of the directions [the piece's input (m) | p (with parameters) | the state at the
  // piece's start (n; not in the first piece, whose start is fixed)], restarted at every piece
  // (S = [0 | 0 | I], T = 0); at each piece's end, S is kept (that piece's input, parameter and
  // transition matrices). A sample's derivative with respect to the control points is then the
  // chain of these matrices back to the first piece, which add_signal_tangents runs once for all
  // its terms, backwards (an adjoint over the pieces). So the cost is that of n + m tangents,
  // whatever the number of control points (SC: 5 directions for 175 points).
  // parameters: also the derivatives with respect to p (add_signal_tangents' parameters_out).
  const SimulatedTrace& run_with_tangents(std::span<const InputPiece> pieces, std::span<const ControlWeights> weights,
                                          std::size_t points, std::span<const double> p,
                                          std::span<const std::size_t> keep = {}, bool parameters = false);
  // Whether the system propagates tangents (an RK4 model; not a black box).
  bool has_tangents() const;
  // The search variables of the last run_with_tangents.
  std::size_t variables() const;
  // The numbers run_with_tangents records at a kept sample (n (1 + D) + D, D = m + n, + the
  // parameters' count with parameters).
  std::size_t tangent_sample_size(bool parameters = false) const;
  // One term of a derivative: `weight` × signal `signal` (system_signals order) at sample `sample`.
  struct SignalTerm {
    std::size_t signal = 0;
    std::size_t sample = 0;
    double weight = 0.0;
  };
  // After run_with_tangents: adds Σ weight × ∂(signal at sample)/∂c_v to out[v] for every search
  // variable v (out: variables() values). Each is a sample's total derivative: a sample whose time
  // moves with the inputs (after a state event, until its input piece ends) moves along the flow
  // (tangent_model.hpp), as a finite difference of the simulation sees it. Output and safety slopes
  // are central differences of M::outputs and M::spec at the sample. Throws std::invalid_argument
  // for a signal or sample out of range or a wrong size of out, std::logic_error for a sample
  // run_with_tangents did not keep. parameters_out (when not empty; after a run with parameters):
  // the same sums' derivatives with respect to each parameter, added to.
  void add_signal_tangents(std::span<const SignalTerm> terms, std::span<double> out,
                           std::span<double> parameters_out = {});
  // The derivative of one signal at one sample (out: variables() values, overwritten).
  void signal_tangent(std::size_t signal, std::size_t sample, std::span<double> out);
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

}  // namespace hyfal::stl
