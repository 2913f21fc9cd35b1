#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// RRT[D*] (Dang & Nahhal's star-discrepancy-guided RRT; a baseline of seed 002): the baseline
// RRT whose x_rand favours the under-covered cells of the sampling box (core/search/samplers/star_discrepancy.hpp).
MethodEntry rrt_dstar_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(rrt_dstar) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> rrt_dstar_methods() { return {rrt_dstar_method()}; }

}  // namespace hyfal
