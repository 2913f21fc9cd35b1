#include "core/signal_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal {

SignalSimulations::SignalSimulations(const PlannerContext& ctx, std::int64_t budget, double horizon)
    : ctx_(ctx), system_(ctx.system), requirement_(*ctx.system.info().requirement), budget_(ctx),
      max_simulations_(std::min(budget, ctx.limits.max_nodes)) {
  dt_ = system_.info().step_duration;
  pieces_ = static_cast<std::size_t>(std::max(1.0, std::ceil(horizon / dt_ - 1e-9)));
  reserve(1);
}

const Box& SignalSimulations::input_box() const { return system_.inputs(system_.info().initial_mode).box; }

void SignalSimulations::reserve(std::size_t n) {
  while (slots_.size() < n) {
    std::vector<stl::InputPiece> pieces(pieces_, stl::InputPiece{dt_, std::vector<double>(system_.info().input_names.size())});
    slots_.push_back(std::make_unique<SignalSlot>(system_, requirement_, std::move(pieces)));
    slots_.back()->simulator.set_interrupt(budget_.interrupt());  // a simulation past the deadline ends too
  }
}

void SignalSimulations::check_budget() const {
  if (simulations_ >= max_simulations_) throw SearchOver{TrialStatus::node_cap};
  if (const auto why = budget_.exhausted(0)) throw SearchOver{*why};
}

void SignalSimulations::simulate(SignalSlot& slot) const {
  const stl::SimulatedTrace& trace = slot.simulator.run(slot.pieces, ctx_.parameters);
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
    throw std::invalid_argument("the signal searches drive the system with one input box in every mode: " + slot.problem);
  ++simulations_;
  simulated_time_ += slot.end_time;
  double rho = slot.rho;
  if (rho < 0.0) {
    if (confirmed(slot.pieces)) {
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
bool SignalSimulations::confirmed(const std::vector<stl::InputPiece>& pieces) {
  Trajectory t = stl::trajectory_of_inputs(system_, pieces, ctx_.parameters);
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
  out.metrics["control_points"] = pieces_;
  if (refused_ > 0) out.metrics["refused_candidates"] = refused_;
  if (status == TrialStatus::falsified) out.trajectory = std::move(confirmed_);  // the signal confirmed() replayed
  return out;
}

double signal_horizon(const System& system, double horizon_option) {
  return horizon_option > 0.0 ? horizon_option : system.info().requirement->formula.horizon();
}

void check_signal_system(const System& system, double horizon_option) {
  const SystemInfo& info = system.info();
  if (!info.requirement)
    throw std::invalid_argument("the signal searches (optimisers, adaptive) minimise an STL requirement's robustness: "
                                "--set requirement=... (hyfal list shows the suite's)");
  if (info.input_names.empty()) throw std::invalid_argument(fmt::format("suite '{}' has no inputs to search", info.suite));
  if (system.state_dependent_inputs())
    throw std::invalid_argument(fmt::format("suite '{}' admits inputs that depend on the state (its drivers): a control-point "
                                            "signal cannot respect them",
                                            info.suite));
  if (!std::isfinite(signal_horizon(system, horizon_option)))
    throw std::invalid_argument("the requirement has an unbounded horizon: give the signal's length (--set horizon=...)");
}

}  // namespace hyfal
