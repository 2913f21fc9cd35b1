#pragma once
#include "core/planner.hpp"

namespace hyfal {

// The unified enhanced RRT of seed 000 (Alg. 3-4), each enhancement selectable on its own.
MethodEntry enhanced_rrt_method();

}  // namespace hyfal
