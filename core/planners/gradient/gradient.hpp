// gradient: falsification by descent along the robustness gradient that the model's own tangents
// give (core/requirements/trace_monitor.hpp, core/simulate/tangent_model.hpp), with random restarts:
// zlscheck's recipe (Bennani & Pouzet et al., ARCH-COMP 2020 FALS; ../shared/arch/anchors.md),
// with exact sensitivities through the hybrid dynamics where zlscheck holds every event's time
// fixed.
//
// The signal is a signal search's (core/planners/signal_search.hpp): K control points of δt, held
// or joined by lines (`input_shape`), bounded by the input box; the parameters stay the
// instance's. One run:
//   start   a uniformly random signal (the trial's stream);
//   step    simulate with the gradient g (one simulation, counted as one against the budget, as
//           zlscheck counts it); stop at a falsification the validator confirms; otherwise move
//           every control value with g ≠ 0 against g's sign by η_t times its input's range,
//           clamped to the box, η_t = η / √t at the t-th step since the start (zlscheck's α/√t;
//           its α is so large that a step reaches the box's corner: η = 1, the default);
//   restart from a fresh random signal when a step no longer moves the signal (every moved value is
//           on its bound, or g = 0), or after `patience` steps that did not lower the start's best ρ.
// Why the sign and not g itself: the control points' slopes differ by orders of magnitude across
// the signal (a throttle late in the run barely moves an early speed); with a corner-reaching
// step both reach the same corner, and a smaller η keeps every point moving.
//
// Contract: deterministic given the trial seed; the budget, deadline and cancellation as every
// signal search; the witness is the falsifying signal, validated independently. Needs a system
// with tangents (RK4 models of our own; not a black box): refused in one line otherwise.
#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

MethodEntry gradient_method();

// This folder's methods (hyfal_planner(gradient) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> gradient_methods() { return {gradient_method()}; }

}  // namespace hyfal
