// Trajectory: an execution of a system as pieces of flow and transitions, what a falsifying trial
// proves (a witness carries one, core/witness/witness.hpp), in a form anyone can re-simulate.
//
// A piece is continuous flow in `mode` under constant `u` for `duration`; when `transition`
// is >= 0 the urgent transition with that guard index fires at its end and its reset maps
// x_end to the next piece's x_start (format hyfal-witness/1; see README). A piece's x_start and
// x_end may be empty, not recorded (SystemInfo::sparse_witness_states; left out of the JSON): the
// validator re-simulates such a piece from its own state and compares nothing there.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/model/system.hpp"
#include "core/search/node_store.hpp"
#include "core/simulate/held_input.hpp"

namespace hyfal {

struct TrajectoryPiece {
  Mode mode = 0;
  std::vector<double> u;
  double duration = 0.0;
  std::vector<double> x_start, x_end;
  int transition = -1;
};

// A signal linear between control points (times[k], values[k]), as a signal search with
// `input_shape = linear` drives the system (core/planners/signal_search.hpp): each interval between
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

// The trajectory from the root to `leaf`; x_end of each piece is re-flowed with `propagator`
// (the tree stores post-reset states only). Under an STL requirement over held inputs
// (SystemInfo::held_inputs) a tree edge is an input held through transitions: it is re-simulated
// into its flow pieces (append_held_input), which end where the tree's edge ended.
Trajectory trajectory_from_tree(const System& system, Propagator& propagator, const NodeStore& tree, NodeId leaf,
                                std::span<const double> parameters);

// Appends to t the pieces of u held from (q, x) for `duration` (hold_input, core/simulate/held_input.hpp):
// one per flow between transitions, x_end before the reset. prop must be in STL mode (a sink
// set), so that the unsafe set does not stop the flow. q and x become the end's; returns the
// held input's end.
HeldInputEnd append_held_input(Trajectory& t, Propagator& prop, Mode& q, std::vector<double>& x,
                               std::vector<double>& next, std::span<const double> u, std::span<const double> p,
                               double duration);

namespace stl {

// The execution under `pieces` as a witness's trajectory: one piece per
// flow between transitions (an input piece cut at each transition), each piece's end state before
// its reset, as the validator re-simulates them; it ends where simulate_inputs ends.
Trajectory trajectory_of_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p);

}  // namespace stl

}  // namespace hyfal
