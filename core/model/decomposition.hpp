// The discrete abstraction of seed 002 Sect. 3.2 (HyDICE): a decomposition of each mode's
// continuous state space into regions D_i(q), and the search graph over them.
//
// Implicit, so that it scales to 10^6 modes: nothing is enumerated; a planner asks for the
// region of a state, a region's volume, neighbours, and whether it is unsafe, and stores data
// only for the regions it reaches.
//  - Region ids are 64-bit and unique over all modes (a suite packs (mode, cell) into them).
//  - neighbors(r, out): the out-edges of v_r in G_D — regions adjacent to r inside its mode and
//    the regions REGIONTRANS says a discrete transition may reach from r. False positives are
//    allowed (a spurious edge only costs a useless lead), false negatives are not (Sect. 3.2.2).
//  - is_unsafe(r): D_r ∩ F ≠ ∅ (r has an edge to v_unsafe); false positives allowed as well.
//  - project(q, x, out): proj_q(x) ∈ R^2, the projection on which the regions and the fine
//    coverage grid (spacing cell_size()) are defined.
//  - volume(r): vol(D_r), the area of r's projection.
//  - centre(r), hops_to_unsafe(r): optional, for steering the propagation toward the next
//    region of a lead and for the A* heuristic of the lead search.
//  - dense_size(), dense_index(r): optional dense indexing. Where the ids are (or map onto) a
//    dense range, a planner keeps its per-region data in flat arrays indexed by dense_index(r)
//    instead of hash tables keyed by r (HyDICE's lead search touches millions of regions per
//    second; a hash probe per touch was ~23 % of a navigation 1024² run, issue 12 item 5).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal {

using RegionId = std::uint64_t;

class Decomposition {
 public:
  virtual ~Decomposition() = default;
  virtual RegionId region_of(Mode q, std::span<const double> x) const = 0;
  virtual double volume(RegionId r) const = 0;
  // Replaces the contents of `out` with the out-neighbours of r in G_D.
  virtual void neighbors(RegionId r, std::vector<RegionId>& out) const = 0;
  virtual bool is_unsafe(RegionId r) const = 0;
  virtual void project(Mode q, std::span<const double> x, std::span<double, 2> out) const = 0;
  // Side of the cells of the fine uniform coverage grid on the projection (Sect. 3.2.3).
  virtual double cell_size() const = 0;
  // A point of r's projection to steer toward (its centre, say); NaN when the suite has none.
  virtual std::array<double, 2> centre(RegionId) const {
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  }
  // A lower bound on the number of G_D edges from r to an unsafe region (0 = none known; inf =
  // no path): the A* heuristic of the lead search. Must not overestimate the hop count, and is
  // a whole number (the lead search ranks regions by it in its queue key). (What a
  // hop costs is the planner's choice: HyDICE prices it at the cost of an edge on unreached
  // ground, which can exceed an edge's cost inside its tree: a weighted A*, see hydice.cpp.)
  virtual double hops_to_unsafe(RegionId) const { return 0.0; }
  // 0: no dense indexing. Otherwise every region r has dense_index(r) < dense_size(), and
  // distinct regions have distinct indices.
  virtual std::uint64_t dense_size() const { return 0; }
  virtual std::uint64_t dense_index(RegionId r) const { return r; }
  // A regular grid over two state dimensions that every region lies in one cell of, for planners
  // that need a grid decomposition of the state space (OMPL's Syclop, core/planners/ompl); nullopt
  // when the regions form no such grid.
  struct StateGrid {
    std::array<int, 2> dims;  // the state dimensions the grid spans
    int cells_per_side;
    std::array<double, 2> lo, hi;  // the grid's extent along dims[0] and dims[1]
  };
  virtual std::optional<StateGrid> state_grid() const { return std::nullopt; }
};

}  // namespace hyfal
