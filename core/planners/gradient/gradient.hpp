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
//   step    simulate with the direction g (one simulation, counted as one against the budget, as
//           zlscheck counts it); stop at a falsification the validator confirms; otherwise move
//           every control value with g ≠ 0 against g's sign by η of its input's range (`step_rule`
//           scaled: by η times its share of the largest slope), clamped to the box. η = 1 (the
//           default) reaches the box's corner, as zlscheck's huge α does.
//   schedule  halving (the default): every step starts from the best signal of this start, and a
//           step that does not lower ρ halves η; sqrt (zlscheck's): from the last signal, with
//           η / √t at the t-th step.
//   restart from a fresh random signal when a step no longer moves the signal (every moved value is
//           on its bound, or g = 0), or after `patience` failed steps.
//   direction  blocking (the default): lower every term of a max that stands above 0 together
//           (core/requirements/robustness.hpp, CriticalPath::every_blocking); subgradient: ρ's own.
// Why the sign and not g itself: the control points' slopes differ by orders of magnitude across
// the signal (a throttle late in the run barely moves an early speed); with a corner-reaching
// step both reach the same corner, and a smaller η keeps every point moving. Why halving and
// blocking (10 runs each, budget 1500; docs/measurements.md): on CC4 zlscheck's own recipe (sqrt,
// subgradient) falsified 2 of 10 (flat, nested min/max), halving with the subgradient 10/10 at 120
// simulations, halving with blocking 10/10 at 41.9; on AT6a the subgradient's 2/10 became 10/10 at
// 33.7 once blocking weighed each atom in its threshold's units (3000 rpm against 35 mph); AT1,
// AT2 and SC are unchanged (2.0, 5.5, 2.0); CC5 pays for it (16.9 with sqrt, 26.7 with halving).
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
