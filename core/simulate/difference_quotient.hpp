// The slope of a model's function (a flow, reset, guard or output) at one point, by differences:
// what the tangents (tangent_model.hpp) and the signals' slopes (InputSimulator::signal_tangent)
// read where a model gives no derivative of its own.
#pragma once
#include <algorithm>
#include <cmath>

namespace hyfal {

// A step of 1e-7 relative, made exactly representable against x (x + h − x is h), so that the
// quotient divides by the step really taken. Not ε^(1/3) (6e-6), where a smooth function's central
// difference is most accurate: table-driven models have kinks (AT's torque map and converter
// tables, at every breakpoint), and a stage that lies within h of one gets a slope averaged over
// both sides, as often as h is large. Measured on AT1 and AT6a against central differences of the
// whole simulation (tests/core/requirements/test_robustness_gradient.cpp, 10 signals each): median
// relative error 4.8e-6 and 7.8e-6 at 6e-6; 3.5e-9 and 2.6e-9 at 1e-7; 7.6e-9 and 6.0e-9 at 1e-8,
// where rounding (ε / h) takes over.
inline double difference_step(double x) {
  const double h = 1e-7 * std::max(1.0, std::abs(x));
  volatile double xh = x + h;
  return xh - x;
}

// f' at x from f(x − h), f(x), f(x + h): the central quotient where the function is smooth
// there; where the two one-sided quotients disagree by more than 10 % (a branch of the model, such
// as a saturation, a table's breakpoint or a rounding to a chart's tick, lies within h of x) the
// smaller one, the side without the jump: the slope of the branch x itself is on, as automatic
// differentiation would give it (for a kink, one of its two one-sided slopes). Without it, AT's
// engine resting on its 600 rpm bound (a saturated integrator: the pull toward the bound on one
// side, the torque balance on the other) got a slope of 1e5 /s and tangents of 1e152.
inline double difference_quotient(double below, double at, double above, double h) {
  const double right = (above - at) / h, left = (at - below) / h;
  if (std::abs(right - left) <= 0.1 * (std::abs(right) + std::abs(left))) return (above - below) / (2.0 * h);
  return std::abs(right) < std::abs(left) ? right : left;
}

}  // namespace hyfal
