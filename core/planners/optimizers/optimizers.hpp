#pragma once
#include "core/planner.hpp"

namespace hyfal {

// The optimisation falsifiers (core/planners/optimizers/optimizers.cpp).
MethodEntry random_search_method();
MethodEntry simulated_annealing_method();
MethodEntry cmaes_method();
MethodEntry nelder_mead_method();

}  // namespace hyfal
