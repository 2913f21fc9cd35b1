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
