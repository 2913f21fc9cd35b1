#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// Baseline RRT, seed 000 Alg. 1-2 / seed 003 Alg. 1-2.
MethodEntry rrt_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(rrt) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> rrt_methods() { return {rrt_method()}; }

}  // namespace hyfal
