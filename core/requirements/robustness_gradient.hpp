// RobustnessGradient: ρ of an input signal and its gradient with respect to the signal's control
// points (and, when asked, the system's parameters), through the model's own dynamics.
//
// ρ is the exact robustness of the simulation (stl::InputSimulator's trace, bit for bit). Its
// gradient is a subgradient: the monitor's critical samples (OfflineMonitor::critical_samples),
// each the derivative of one signal at one sample, which the tangents of the simulation give
// (InputSimulator::signal_tangent, core/simulate/tangent_model.hpp). One call is one simulation
// (with its tangents), as zlscheck counts it (../shared/arch/anchors.md).
#pragma once
#include <span>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/model/system.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/simulate/input_simulator.hpp"

namespace hyfal::stl {

class RobustnessGradient {
 public:
  // Throws std::invalid_argument when the system has no tangents (a black box, an integrator
  // other than RK4).
  RobustnessGradient(const System& system, const Requirement& requirement);
  // Simulates `pieces` (weights[k]: how piece k's input depends on the `points` control points,
  // ControlWeights) at parameters p; returns ρ and writes ∂ρ/∂c into gradient (points × m values,
  // point k's input j at k m + j). A trace that ends early (an invariant, a rejected step) is
  // judged as it ends, as the signal searches judge theirs.
  // parameter_gradient (when not empty, p.size() values): ∂ρ/∂p as well (F16's attitude).
  double evaluate(std::span<const InputPiece> pieces, std::span<const ControlWeights> weights, std::size_t points,
                  std::span<const double> p, std::span<double> gradient, std::span<double> parameter_gradient = {});
  // The last evaluation's trace and simulator (its deadline: set_interrupt).
  const SimulatedTrace& trace() const { return simulator_.trace(); }
  InputSimulator& simulator() { return simulator_; }

 private:
  InputSimulator simulator_;
  TraceMonitor monitor_;
};

}  // namespace hyfal::stl
