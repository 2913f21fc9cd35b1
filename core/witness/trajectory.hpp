// Witness trajectories: what a falsifying trial proves, in a form anyone can re-simulate.
//
// A piece is continuous flow in `mode` under constant `u` for `duration`; when `transition`
// is >= 0 the urgent transition with that guard index fires at its end and its reset maps
// x_end to the next piece's x_start (format hyfal-witness/1; see README). A piece's x_start and
// x_end may be empty, not recorded (SystemInfo::sparse_witness_states; left out of the JSON): the
// validator re-simulates such a piece from its own state and compares nothing there.
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/held_input.hpp"

#include "core/model.hpp"
#include "core/tree.hpp"

namespace hyfal {

struct TrajectoryPiece {
  Mode mode = 0;
  std::vector<double> u;
  double duration = 0.0;
  std::vector<double> x_start, x_end;
  int transition = -1;
};

// A signal linear between control points (times[k], values[k]), as a signal search with
// `input_shape = linear` drives the system (core/signal_search.hpp): each interval between
// control points cut into ceil(length / piece) equal pieces, each holding the line's value at its
// midpoint (stl::linear_signal_pieces). A witness that carries it declares its pieces' inputs to
// be those; the validator checks that they are, and that the control points lie on the δt grid
// of an instance that admits such a signal (SystemInfo::interpolated_inputs).
struct LinearInput {
  std::vector<double> times;
  std::vector<std::vector<double>> values;
  double piece = 0.0;
};

struct Trajectory {
  std::vector<double> parameters;
  Mode initial_mode = 0;
  std::vector<double> initial_x;
  std::vector<TrajectoryPiece> pieces;
  Mode final_mode = 0;
  std::vector<double> final_x;
  double final_spec = 0.0;
  std::optional<LinearInput> linear_input;  // JSON "input_signal": {"shape": "linear", ...}
};

// An STL witness's requirement (instance parameter `requirement`): as named and as written, and
// the robustness of the witness's trace as the validator re-simulates and samples it (< 0).
struct WitnessRequirement {
  std::string id;       // "" for a formula given inline
  std::string formula;
  double robustness = 0.0;
};

struct Witness {
  std::string suite;
  Json instance;
  std::string method;
  std::int64_t trial_seed = 0;
  std::vector<std::string> state_names, input_names;
  Trajectory trajectory;
  std::optional<WitnessRequirement> requirement;  // STL witnesses only
};

// The witness of a trajectory of `system`, with the names and instance the system declares.
Witness make_witness(const System& system, std::string method, std::int64_t trial_seed, Trajectory trajectory);

// A witness file that cannot be read: not JSON, or a field missing, mistyped or out of range.
class WitnessError : public InputError {
 public:
  using InputError::InputError;
  const char* name() const noexcept override { return "WitnessError"; }
};

Json to_json(const Witness& w);
// Throws WitnessError naming the first missing or malformed field: a missing member, a wrong
// JSON type, a non-finite number, a vector whose length differs from state_names/input_names, an
// integer (mode, transition, seed) outside its type's range (never wrapped).
Witness witness_from_json(const Json& j);
// witness_from_json of a file's text; a JSON syntax error or a number beyond double's range
// (1e999) is a WitnessError giving where the parser stopped (byte offset, line and column, all
// counted from 1) and the cause. Throws nothing else.
Witness witness_from_text(std::string_view text);

// The trajectory from the root to `leaf`; x_end of each piece is re-flowed with `propagator`
// (the tree stores post-reset states only). Under an STL requirement over held inputs
// (SystemInfo::held_inputs) a tree edge is an input held through transitions: it is re-simulated
// into its flow pieces (append_held_input), which end where the tree's edge ended.
Trajectory trajectory_from_tree(const System& system, Propagator& propagator,
                                const NodeStore& tree, NodeId leaf,
                                std::span<const double> parameters);

// Appends to t the pieces of u held from (q, x) for `duration` (hold_input, core/held_input.hpp):
// one per flow between transitions, x_end before the reset. prop must be in STL mode (a sink
// set), so that the unsafe set does not stop the flow. q and x become the end's; returns the
// held input's end.
HeldInputEnd append_held_input(Trajectory& t, Propagator& prop, Mode& q, std::vector<double>& x,
                               std::vector<double>& next, std::span<const double> u, std::span<const double> p,
                               double duration);

struct ValidationReport {
  bool valid = false;
  // Not even a witness of this system (bad input, not an invalid execution): a vector of the
  // wrong size, a mode that is not one of the system's modes, a transition index the mode does
  // not have. The rest (values outside P or U, a piece longer than δt, states that do not
  // re-simulate, a safe final state) makes a well-formed witness invalid.
  bool malformed = false;
  std::string reason;          // why not, or a one-line summary when valid
  double final_spec = 0.0;     // s at the re-simulated final state
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
// piece holds that line's value (control points on the δt grid of an instance that admits it). Then: modes, inputs within U_q, each
// piece's end state, that no transition became enabled inside a piece (urgency), that each
// recorded transition is enabled at its piece's end and its reset reproduces the next
// x_start, and that the final state has s <= tolerance — or, for a system with an STL requirement,
// that the trace, sampled at the end of every sub-interval of the re-simulation (the suite's
// integration step) and on both sides of every transition, has a negative robustness. (A
// violation that lies only between two of these samples, such as an unsafe set entered and left
// within one step, is not seen: such a witness is refused, never a false one accepted.)
ValidationReport validate_witness(const System& system, const Witness& w);

}  // namespace hyfal
