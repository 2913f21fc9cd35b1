#pragma once
#include "core/planner.hpp"

namespace hyfal {

// Baseline RRT, seed 000 Alg. 1-2 / seed 003 Alg. 1-2.
MethodEntry rrt_method();

}  // namespace hyfal
