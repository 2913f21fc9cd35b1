// The simulations of a search over input signals (the optimisation falsifiers and FalStar's
// adaptive search, core/planners/optimizers/ and core/planners/adaptive/): each one drives the
// system from its initial state with a piecewise-constant signal of K pieces of δt (the suite's
// SystemInfo::step_duration, so that a signal search and a tree search draw from the same input
// space), K = ceil(horizon / δt), over the requirement's horizon unless the option `horizon` says
// otherwise. Each simulation is sampled as the tree searches sample (stl::InputSimulator) and
// judged by its requirement's robustness; it counts against the run's budget of simulations; a
// negative robustness counts as a falsification only once the witness validator (an independent,
// tight re-simulation) confirms it, and a refused candidate (the search's robustness just below
// 0, the validator's just above) lets the search go on. One place, so that every signal search
// counts and confirms alike.
//
// The signal's shape (option `input_shape`): constant (each piece holds its value: ARCH-COMP's
// instance 2, FalStar's signals) or linear (S-TaLiRo's and Breach's default interpolation,
// admitted by ARCH-COMP's instance 1: SystemInfo::interpolated_inputs). A linear signal has K + 1
// control points on the δt grid, the line between them driving the system as pieces of the
// suite's integration step (its max_step), each holding the line's value at its midpoint
// (stl::linear_signal_pieces: a model affine in u sees the exact mean over every step); its
// witness carries the control points (Trajectory::linear_input), which the validator checks the
// pieces against.
//
// The system's time-invariant parameters P (SystemInfo::parameter_box), where P has width, are
// searched too, as RRFT searches them: each slot carries its own p, which the search writes beside
// the signal (the optimisers: the first dimensions of the decision vector), and the witness
// carries it (the validator checks p ∈ P). A system with no inputs (F16: the initial attitude is
// P) is searched over P alone, with one piece of δt per simulation and no input in it. Elsewhere
// (P a point) p is the instance's, as before.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/simulate/input_signal.hpp"
#include "core/simulate/input_simulator.hpp"

namespace hyfal {

enum class InputShape { constant, linear };

// Parses an `input_shape` option ("constant" | "linear"); throws std::invalid_argument naming it.
InputShape input_shape_of(const std::string& text);
// The option every signal search takes.
OptionSpec input_shape_option();

// Thrown out of a search step to end the search (every optimiser library lets it through).
struct SearchOver {
  TrialStatus status;
};

// One simulation's scratch: its simulator (propagator and trace buffers), monitor and signal. A
// search that simulates B signals at once has B (core/search/parallel_slots.hpp).
struct SignalSlot {
  SignalSlot(const System& system, const stl::Requirement& requirement, std::vector<stl::InputPiece> pieces)
      : simulator(system), monitor(requirement), pieces(std::move(pieces)) {}
  stl::InputSimulator simulator;
  stl::TraceMonitor monitor;
  // The signal: K pieces of δt, whose u the search writes. Shape constant: each piece's value;
  // linear: the control value at the piece's end, `start` the one at time 0 (the system is then
  // driven by `fine`, the line's pieces).
  std::vector<stl::InputPiece> pieces;
  std::vector<double> start;
  std::vector<stl::InputPiece> fine;
  // The parameters p this simulation runs at: the instance's unless the search writes them.
  std::vector<double> parameters;
  // The last simulation (its trace stays in `simulator` until the next): its robustness, work,
  // end time, and whether it was cut short.
  double rho = 0.0;
  std::int64_t steps = 0;
  double end_time = 0.0;
  bool interrupted = false;
  std::string problem;
};

class SignalSimulations {
 public:
  SignalSimulations(const PlannerContext& ctx, std::int64_t budget, double horizon,
                    InputShape shape = InputShape::constant);

  InputShape shape() const { return shape_; }
  std::size_t pieces() const { return pieces_; }  // K
  double piece_duration() const { return dt_; }   // δt
  const Box& input_box() const;                   // U of the initial mode: every piece's bounds
  // Whether the search writes each slot's parameters (P has width), and P.
  bool searches_parameters() const { return parameter_box().has_width(); }
  const Box& parameter_box() const { return system_.info().parameter_box; }
  // Slots 0..n-1 exist after this (slot 0 always does).
  void reserve(std::size_t n);
  SignalSlot& slot(std::size_t i) { return *slots_[i]; }
  // Throws SearchOver when no further simulation may run: the budget is spent (budget; node_cap
  // when the run's node cap is the smaller limit), or
  // the deadline passed or the trial was cancelled (timeout).
  void check_budget() const;
  // Simulations the budget still allows.
  std::int64_t remaining() const { return max_simulations_ - simulations_; }
  std::int64_t simulations() const { return simulations_; }
  // Simulates the slot's signal into `slot` (touches nothing else: slots may run in parallel).
  void simulate(SignalSlot& slot) const;
  // The same simulation with the gradient of its robustness (core/requirements/trace_monitor.hpp)
  // with respect to the signal's control points, into `gradient` in the order the slot holds them
  // (constant: piece by piece; linear: `start`, then the end of each piece), input by input, after
  // the slopes in p where P is searched (searches_parameters: F16's attitude). One
  // simulation, counted by account() as any other. Throws std::logic_error for a system without
  // tangents (InputSimulator::has_tangents).
  void simulate_with_gradient(SignalSlot& slot, std::vector<double>& gradient,
                              stl::CriticalPath path = stl::CriticalPath::attaining) const;
  // The signal's control points: K, or K + 1 for a linear signal.
  std::size_t control_points() const { return pieces_ + (shape_ == InputShape::linear ? 1 : 0); }
  // The samples of `trace` (a slot's last simulation) up to the end of its first `pieces` pieces
  // of δt: the prefix they fix (all of a trace that ended before; 1 for none).
  std::size_t samples_through(const stl::SimulatedTrace& trace, std::size_t pieces) const;
  // Counts the simulation just run in `slot` and returns the search's value for it: its
  // robustness, or, for a candidate the validator refused, the validator's robustness (at least
  // 0). Throws SearchOver{falsified} at a confirmed falsification, SearchOver{timeout} for a
  // simulation the deadline cut short, std::invalid_argument for a signal the system refuses.
  double account(const SignalSlot& slot);
  // The outcome once the search is over: counters, metrics (robustness, control_points,
  // refused_candidates), the confirmed witness's trajectory.
  PlannerOutcome outcome(TrialStatus status);

 private:
  bool confirmed(const SignalSlot& slot);
  // The pieces that drive the system: slot.pieces, or (linear) slot.fine filled from them.
  const std::vector<stl::InputPiece>& driving_pieces(SignalSlot& slot) const;
  // The slot's fields from its simulation's trace (the robustness included).
  void finish(SignalSlot& slot, const stl::SimulatedTrace& trace) const;

  const PlannerContext& ctx_;
  const System& system_;
  const stl::Requirement& requirement_;
  SearchBudget budget_;
  std::vector<std::unique_ptr<SignalSlot>> slots_;
  std::int64_t max_simulations_;
  std::int64_t budget_option_;  // the method's budget (max_simulations_ is it or the node cap)
  double dt_ = 1.0;
  std::size_t pieces_ = 1;
  InputShape shape_ = InputShape::constant;
  std::size_t fine_per_piece_ = 1;  // linear: pieces of the line per piece of δt
  std::vector<stl::ControlWeights> weights_;  // the driving pieces' (simulate_with_gradient)
  std::int64_t simulations_ = 0, steps_ = 0, refused_ = 0;
  double refused_rho_ = 0.0;
  std::optional<Trajectory> confirmed_;  // the falsifying signal's trajectory, once confirmed
  double simulated_time_ = 0.0;
  double best_ = std::numeric_limits<double>::infinity();
};

// What a signal search needs of a system (a method's check_system, and its solve()): an STL
// requirement, inputs or parameters to search (`parameters`: the method searches P), a box that does not depend on the
// state, a finite signal length. Throws std::invalid_argument naming what is missing. A linear shape needs an instance
// that admits it (a held signal's instance 2 does not).
void check_signal_system(const System& system, double horizon_option, InputShape shape = InputShape::constant,
                         bool parameters = true);
// The signal's length: the option's, or the requirement's horizon (0: unset).
double signal_horizon(const System& system, double horizon_option);

}  // namespace hyfal
