#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// The unified enhanced RRT of seed 000 (Alg. 3-4), each enhancement selectable on its own.
MethodEntry enhanced_rrt_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(enhanced_rrt) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> enhanced_rrt_methods() { return {enhanced_rrt_method()}; }

}  // namespace hyfal
