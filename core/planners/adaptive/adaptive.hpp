#pragma once
#include <cstddef>
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// FalStar's probabilistically adaptive tree search (core/planners/adaptive/adaptive.cpp).
MethodEntry adaptive_method();
// The tree-optimiser hybrid: the same tree, each new best pass polished by a short Nelder-Mead.
MethodEntry adaptive_local_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(adaptive) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> adaptive_methods() { return {adaptive_method(), adaptive_local_method()}; }

namespace adaptive {

// The input values of refinement level `level` over `inputs` dimensions, as fractions of each
// input's range (core/search/input_levels.hpp; FalStar's Combinatorics.splits): every combination whose
// costs sum to exactly `level`. Row-major, in a fixed order.
std::vector<double> level_fractions(std::size_t inputs, int level);

}  // namespace adaptive
}  // namespace hyfal
