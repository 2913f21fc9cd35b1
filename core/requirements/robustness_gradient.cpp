#include "core/requirements/robustness_gradient.hpp"

#include <stdexcept>

namespace hyfal::stl {

RobustnessGradient::RobustnessGradient(const System& system, const Requirement& requirement)
    : simulator_(system), monitor_(requirement) {
  if (!simulator_.has_tangents())
    throw std::invalid_argument(
        "this system has no gradients: they need a model of our own integrated by RK4 (not a black box)");
}

double RobustnessGradient::evaluate(std::span<const InputPiece> pieces, std::span<const ControlWeights> weights,
                                    std::size_t points, std::span<const double> p, std::span<double> gradient,
                                    std::span<double> parameter_gradient) {
  return monitor_.robustness_gradient(simulator_, pieces, weights, points, p, gradient, CriticalPath::attaining,
                                      parameter_gradient);
}

}  // namespace hyfal::stl
