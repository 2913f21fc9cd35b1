#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// The optimisation falsifiers (core/planners/optimizers/optimizers.cpp).
MethodEntry random_search_method();
MethodEntry simulated_annealing_method();
MethodEntry cmaes_method();
MethodEntry nelder_mead_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(optimizers) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> optimizers_methods() {
  return {random_search_method(), simulated_annealing_method(), cmaes_method(), nelder_mead_method()};
}

}  // namespace hyfal
