// The newcomer's template planner (docs/contributing.md walks through it): a random tree, the
// simplest tree search there is, written against the Planner interface alone so that every step
// a planner owes is in view. It is not registered (no hyfal_planner line): tests/suites/test_toy.cpp
// compiles it and runs it through the trial engine, so the template keeps compiling and working.
//
// The random tree (LaValle 1998, "Rapidly-exploring random trees", Sect. 2, the naive random
// tree RRT is compared against): repeat
//   pick a node of the tree uniformly at random,
//   pick an input of its mode's finite input set Ū_q uniformly at random,
//   propagate for δt (SystemInfo::step_duration), and add the end state as the node's child,
// until a propagation reaches the unsafe set s <= 0 (falsified), or the node cap, the time budget
// or the trial's cancellation stops it. It explores slowly (the tree's old nodes are picked as
// often as its frontier), which is what RRT's Voronoi bias fixes.
//
// Contract (what every planner promises, core/run/planner.hpp):
//  - deterministic given ctx.seed: every random number comes from one stream seeded by it;
//  - it honours SearchBudget (node cap, deadline, cancellation) between propagations, and the
//    propagator's interrupt within one;
//  - a falsified outcome carries the trajectory from the root to the unsafe node, which the trial
//    engine re-checks with the independent validator (core/witness/validator.hpp);
//  - counters: nodes, propagations, integration steps, simulated time.
// Reachability only: a system with an STL requirement is refused when the run is resolved.
#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

MethodEntry toy_random_tree_method();

// This folder's methods, in the order `hyfal list` would show them once registered by the line
// hyfal_planner(toy) in core/planners/CMakeLists.txt.
inline std::vector<MethodEntry> toy_methods() { return {toy_random_tree_method()}; }

}  // namespace hyfal
