#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

// RRFT, the Rapidly-exploring Random Forest of Trees of seed 003 (Alg. 3): one RRT per seed
// p in P̄ (a Halton sequence over P), trees terminated on growth or coverage and replaced while
// the seeds' dispersion µ(P̄) is above µ̄, then restarted at seeds not yet covered (issue 27).
// docs/methods.md, "RRFT in detail", gives the conventions, the restart rule and the defaults.
MethodEntry rrft_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(rrft) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> rrft_methods() { return {rrft_method()}; }

}  // namespace hyfal
