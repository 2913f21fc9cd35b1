// OMPL 1.5's control planners as hyfal methods (built when CMake finds OMPL: HYFAL_HAVE_OMPL).
//
//   ompl-rrt         ompl::control::RRT
//   ompl-kpiece      ompl::control::KPIECE1 (projection: see hybrid_space.hpp, HybridProjection)
//   ompl-sst         ompl::control::SST (stops at its first solution)
//   ompl-syclop-rrt  ompl::control::SyclopRRT over the suite's grid (Decomposition::state_grid)
//   ompl-syclop-est  ompl::control::SyclopEST over the same grid
//
// Every method runs on any suite through one adapter (hybrid_space.hpp): hyfal's System as an
// OMPL state space (x and the mode), the suite's input box as the control space, and a
// StatePropagator that advances with hyfal's own Propagator (events, guards, resets). A
// solution (controls and durations) is replayed through the same propagator into an ordinary
// witness, which the trial engine validates like every other method's.
#pragma once
#include <vector>

#include "core/run/method_entry.hpp"

namespace hyfal {

MethodEntry ompl_rrt_method();
MethodEntry ompl_kpiece_method();
MethodEntry ompl_sst_method();
MethodEntry ompl_syclop_rrt_method();
MethodEntry ompl_syclop_est_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(ompl) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> ompl_methods() {
  return {ompl_rrt_method(), ompl_kpiece_method(), ompl_sst_method(), ompl_syclop_rrt_method(),
          ompl_syclop_est_method()};
}

}  // namespace hyfal
