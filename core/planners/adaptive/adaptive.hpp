#pragma once
#include <cstddef>
#include <vector>

#include "core/planner.hpp"

namespace hyfal {

// FalStar's probabilistically adaptive tree search (core/planners/adaptive/adaptive.cpp).
MethodEntry adaptive_method();

namespace adaptive {

// The input values of refinement level `level` over `inputs` dimensions, as fractions of each
// input's range: every combination whose costs sum to exactly `level`, where the corners 0 and 1
// cost 0 and a dyadic n / 2^k (n odd) costs k. Level 0 is the 2^inputs corners; level 1 puts one
// dimension at 1/2; level 2 one at 1/4 or 3/4, or two at 1/2; ... (Ernst et al. 2019, Sect. 4;
// FalStar's Combinatorics.splits). Row-major: inputs fractions per combination, in a fixed order.
std::vector<double> level_fractions(std::size_t inputs, int level);

}  // namespace adaptive
}  // namespace hyfal
