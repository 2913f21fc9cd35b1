#include "core/planners/signal_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/model/signal_model.hpp"
#include "core/witness/validator.hpp"
#include "core/witness/witness.hpp"

namespace hyfal {

InputShape input_shape_of(const std::string& text) {
  if (text == "constant") return InputShape::constant;
  if (text == "linear") return InputShape::linear;
  throw std::invalid_argument(fmt::format("input_shape = '{}': expected constant or linear", text));
}

OptionSpec input_shape_option() {
  return {"input_shape", "constant",
          "the signal between control points: constant (held for δt) or linear (control points every δt, the line "
          "between them; ARCH-COMP instance 1 only)",
          "constant|linear", "constant"};  // unkeyed: stored signal-search trials predate it
}

SignalSimulations::SignalSimulations(const PlannerContext& ctx, std::int64_t budget, double horizon, InputShape shape)
    : ctx_(ctx),
      system_(ctx.system),
      requirement_(*ctx.system.info().requirement),
      budget_(ctx),
      max_simulations_(std::min(budget, ctx.limits.max_nodes)),
      budget_option_(budget),
      shape_(shape) {
  dt_ = system_.info().step_duration;
  pieces_ = static_cast<std::size_t>(std::max(1.0, std::ceil(horizon / dt_ - 1e-9)));
  if (shape_ == InputShape::linear)
    fine_per_piece_ =
        static_cast<std::size_t>(std::max(1.0, std::ceil(dt_ / system_.info().integrator.max_step - 1e-9)));
  // How each driving piece depends on the control points (stl::ControlWeights): piece k on point k;
  // a linear signal's pieces of δt on the points at their ends, by the midpoints' weights.
  for (std::size_t k = 0; k < pieces_; ++k)
    for (std::size_t j = 0; j < fine_per_piece_; ++j) {
      const double w =
          shape_ == InputShape::linear ? (static_cast<double>(j) + 0.5) / static_cast<double>(fine_per_piece_) : 0.0;
      weights_.push_back({k, 1.0 - w, w});
    }
  reserve(1);
}

const Box& SignalSimulations::input_box() const { return system_.inputs(system_.info().initial_mode).box; }

void SignalSimulations::reserve(std::size_t n) {
  while (slots_.size() < n) {
    std::vector<stl::InputPiece> pieces(pieces_,
                                        stl::InputPiece{dt_, std::vector<double>(system_.info().input_names.size())});
    slots_.push_back(std::make_unique<SignalSlot>(system_, requirement_, std::move(pieces)));
    slots_.back()->parameters.assign(ctx_.parameters.begin(), ctx_.parameters.end());
    slots_.back()->simulator.set_interrupt(budget_.interrupt());  // a simulation past the deadline ends too
    if (shape_ == InputShape::linear) {
      const std::size_t m = system_.info().input_names.size();
      slots_.back()->start.assign(m, 0.0);
      slots_.back()->fine.assign(pieces_ * fine_per_piece_,
                                 stl::InputPiece{dt_ / static_cast<double>(fine_per_piece_), std::vector<double>(m)});
    }
  }
}

void SignalSimulations::check_budget() const {
  // The method's budget when it is the smaller limit (or both are reached), else the node cap.
  if (simulations_ >= max_simulations_)
    throw SearchOver{simulations_ >= budget_option_ ? TrialStatus::budget : TrialStatus::node_cap};
  if (const auto why = budget_.exhausted(0)) throw SearchOver{*why};
}

// The line's value at the midpoint of each of its n pieces over a piece of δt, as
// stl::linear_signal_pieces computes it (the validator recomputes them so).
const std::vector<stl::InputPiece>& SignalSimulations::driving_pieces(SignalSlot& slot) const {
  if (shape_ == InputShape::constant) return slot.pieces;
  const std::size_t n = fine_per_piece_, m = slot.start.size();
  for (std::size_t k = 0; k < pieces_; ++k) {
    const std::vector<double>& from = k == 0 ? slot.start : slot.pieces[k - 1].u;
    const std::vector<double>& to = slot.pieces[k].u;
    for (std::size_t j = 0; j < n; ++j) {
      const double w = (static_cast<double>(j) + 0.5) / static_cast<double>(n);
      std::vector<double>& u = slot.fine[k * n + j].u;
      for (std::size_t i = 0; i < m; ++i) u[i] = stl::linear_value(from[i], to[i], w);
    }
  }
  return slot.fine;
}

std::size_t SignalSimulations::samples_through(const stl::SimulatedTrace& trace, std::size_t pieces) const {
  if (pieces == 0) return 1;
  const std::size_t fine = pieces * fine_per_piece_;
  return fine <= trace.piece_ends.size() ? trace.piece_ends[fine - 1] : trace.time.size();
}

void SignalSimulations::simulate(SignalSlot& slot) const {
  const stl::SimulatedTrace& trace = slot.simulator.run(driving_pieces(slot), slot.parameters);
  finish(slot, trace);
}

void SignalSimulations::simulate_with_gradient(SignalSlot& slot, std::vector<double>& gradient,
                                               stl::CriticalPath path) const {
  const std::vector<stl::InputPiece>& pieces = driving_pieces(slot);
  // Where P is searched, p's slopes first (the optimisers' order: signal_search.hpp's header).
  const std::size_t np = searches_parameters() ? slot.parameters.size() : 0;
  gradient.resize(np + control_points() * system_.info().input_names.size());
  const std::span<double> all(gradient);
  const double rho = slot.monitor.robustness_gradient(slot.simulator, pieces, weights_, control_points(),
                                                      slot.parameters, all.subspan(np), path, all.first(np));
  finish(slot, slot.simulator.trace());
  if (!slot.interrupted && slot.problem.empty())
    slot.rho = rho;
  else
    std::fill(gradient.begin(), gradient.end(), 0.0);
}

void SignalSimulations::finish(SignalSlot& slot, const stl::SimulatedTrace& trace) const {
  slot.steps = trace.integration_steps;
  slot.interrupted = slot.simulator.interrupted();
  slot.problem = trace.problem;
  slot.end_time = trace.time.empty() ? 0.0 : trace.time.back();
  slot.rho = slot.interrupted || !trace.problem.empty() ? 0.0 : slot.monitor.robustness(trace);
}

double SignalSimulations::account(const SignalSlot& slot) {
  steps_ += slot.steps;
  if (slot.interrupted) throw SearchOver{TrialStatus::timeout};
  if (!slot.problem.empty())
    throw std::invalid_argument("the signal searches drive the system with one input box in every mode: " +
                                slot.problem);
  ++simulations_;
  simulated_time_ += slot.end_time;
  double rho = slot.rho;
  if (rho < 0.0) {
    if (confirmed(slot)) {
      best_ = rho;
      throw SearchOver{TrialStatus::falsified};
    }
    rho = refused_rho_;
  }
  best_ = std::min(best_, rho);
  return rho;
}

// A negative robustness of the search's simulation is a falsification only when the witness
// validator confirms it: one within the integration error of 0 may not be (a Nelder-Mead signal
// at -2e-5 re-simulated to +0.0037 on AT). A refused signal is no falsification: the search goes
// on with the validator's robustness for it (refused_rho_, at least 0), and the refusal is
// counted (metric refused_candidates).
bool SignalSimulations::confirmed(const SignalSlot& slot) {
  const std::vector<stl::InputPiece>& pieces = shape_ == InputShape::linear ? slot.fine : slot.pieces;
  Trajectory t = stl::trajectory_of_inputs(system_, pieces, slot.parameters);
  if (shape_ == InputShape::linear) {
    LinearInput in;
    in.piece = dt_ / static_cast<double>(fine_per_piece_);
    in.times.push_back(0.0);
    in.values.push_back(slot.start);
    for (std::size_t k = 0; k < pieces_; ++k) {
      in.times.push_back(static_cast<double>(k + 1) * dt_);
      in.values.push_back(slot.pieces[k].u);
    }
    t.linear_input = std::move(in);
  }
  const ValidationReport v = validate_witness(system_, make_witness(system_, "", 0, t));
  if (v.valid) {
    confirmed_ = std::move(t);
    return true;
  }
  ++refused_;
  refused_rho_ = v.robustness ? std::max(*v.robustness, 0.0) : 0.0;
  return false;
}

PlannerOutcome SignalSimulations::outcome(TrialStatus status) {
  PlannerOutcome out;
  out.status = status;
  out.counters.nodes = simulations_;
  out.counters.propagations = simulations_;
  out.counters.integration_steps = steps_;
  out.counters.simulated_time = simulated_time_;
  out.metrics["robustness"] = best_;
  out.metrics["control_points"] = pieces_ + (shape_ == InputShape::linear ? 1 : 0);
  if (refused_ > 0) out.metrics["refused_candidates"] = refused_;
  if (status == TrialStatus::falsified) out.trajectory = std::move(confirmed_);  // the signal confirmed() replayed
  return out;
}

double signal_horizon(const System& system, double horizon_option) {
  return horizon_option > 0.0 ? horizon_option : system.info().requirement->formula.horizon();
}

void check_signal_system(const System& system, double horizon_option, InputShape shape, bool parameters) {
  const SystemInfo& info = system.info();
  if (!info.requirement)
    throw std::invalid_argument(
        "the signal searches (optimisers, adaptive) minimise an STL requirement's robustness: "
        "--set requirement=... (hyfal list shows the suite's)");
  if (info.input_names.empty() && !(parameters && info.parameter_box.has_width()))
    throw std::invalid_argument(
        fmt::format("suite '{}' has no inputs to search{}", info.suite,
                    info.parameter_box.has_width() ? " (its parameters P: rrft, the optimisers)" : ""));
  if (system.state_dependent_inputs())
    throw std::invalid_argument(
        fmt::format("suite '{}' admits inputs that depend on the state (its drivers): a control-point "
                    "signal cannot respect them",
                    info.suite));
  if (shape == InputShape::linear && info.held_inputs && !info.interpolated_inputs)
    throw std::invalid_argument(
        fmt::format("input_shape = linear: suite '{}' at this instance admits only inputs held "
                    "constant for δt (ARCH-COMP instance 2); use input_instance=1, or "
                    "input_shape=constant",
                    info.suite));
  if (!std::isfinite(signal_horizon(system, horizon_option)))
    throw std::invalid_argument(
        "the requirement has an unbounded horizon: give the signal's length (--set horizon=...)");
}

}  // namespace hyfal
