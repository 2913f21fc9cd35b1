// validate_witness: the independent re-simulation that decides whether a witness falsifies its
// system. The only place that sees both the simulation and the requirements.
#pragma once
#include <cstddef>
#include <optional>
#include <string>

#include "core/model/system.hpp"
#include "core/witness/witness.hpp"

namespace hyfal {

struct ValidationReport {
  bool valid = false;
  // Not even a witness of this system (bad input, not an invalid execution): a vector of the
  // wrong size, a mode that is not one of the system's modes, a transition index the mode does
  // not have. The rest (values outside P or U, a piece longer than δt, states that do not
  // re-simulate, a safe final state) makes a well-formed witness invalid.
  bool malformed = false;
  std::string reason;            // why not, or a one-line summary when valid
  double final_spec = 0.0;       // s at the re-simulated final state
  double max_state_error = 0.0;  // largest |re-simulated - recorded| over all checked states
  // STL: the robustness of the re-simulated trace (the offline monitor, core/requirements/), and
  // how many samples it has. Valid only when < 0.
  std::optional<double> robustness;
  std::size_t samples = 0;
};

// Re-simulates the pieces from the initial state with a tight Dormand-Prince integrator,
// independent of the stored intermediate states. First, before anything uses them, every index
// the witness names (modes, transitions) and every vector size is checked against the system
// (malformed), and every piece's duration against δt (SystemInfo::step_duration: no method
// extends a node for longer, so a witness asks for bounded work); a held signal's input changes
// only at multiples of δt, or, for a witness that declares a linear signal (linear_input), every
// piece holds that line's value (control points on the δt grid of an instance that admits it). Then: modes, inputs
// within U_q, each piece's end state, that no transition became enabled inside a piece (urgency), that each recorded
// transition is enabled at its piece's end and its reset reproduces the next x_start, and that the final state has s <=
// tolerance — or, for a system with an STL requirement, that the trace, sampled at the end of every sub-interval of the
// re-simulation (the suite's integration step) and on both sides of every transition, has a negative robustness. (A
// violation that lies only between two of these samples, such as an unsafe set entered and left
// within one step, is not seen: such a witness is refused, never a false one accepted.)
ValidationReport validate_witness(const System& system, const Witness& w);

}  // namespace hyfal
