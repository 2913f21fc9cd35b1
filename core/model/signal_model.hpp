// The signals of a system and the traces that carry them: what every layer above the model reads
// (the simulators write them, the monitors judge them, a black box returns them).
//
// Signals of every system, in this order (their indices are what Requirement::sources holds):
// the suite's outputs (SystemInfo::outputs, values from M::outputs), the inputs (input_names,
// constant along a tree edge), and `safety` = s(q, x; p), so that reachability of s <= 0 is also
// the requirement `always (safety > 0)`.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal::stl {

// outputs, then inputs, then safety (see above).
std::vector<SignalInfo> system_signals(const SystemInfo& info);

// u held for `duration` seconds.
struct InputPiece {
  double duration = 0.0;
  std::vector<double> u;
};

// How one input piece depends on an input signal's control points c_k (each a vector of the m
// inputs): u = here · c_point + next · c_(point+1), the same weights for every input. A held
// signal's piece k: {k, 1, 0}; a linear one's: the line's weights at the piece's midpoint
// (stl::linear_signal_pieces). With m inputs, control point k's input j is search variable k m + j.
struct ControlWeights {
  std::size_t point = 0;
  double here = 1.0, next = 0.0;
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

// A model known only by its simulations (System::signal_model: a black box, such as a Python
// function, core/model/black_box.hpp): the output signals of an input signal, from time 0. The samples
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

}  // namespace hyfal::stl
