// The adapter between hyfal's System and OMPL 1.5's control planning (ompl.hpp lists the
// methods built on it). One set of objects per trial; nothing is shared between trials.
//
// State space (HybridStateSpace): R^n with the mode q and an `admissible` flag carried in every
// state. Distances are hyfal's metric rho(x, y) = sqrt(sum w_i (x_i - y_i)^2) (the suite's
// metric_weights, the metric every hyfal RRT uses); the mode does not enter them (as in hyfal's
// RRTs). The bounds are the suite's sampling box: where OMPL draws states, not a constraint (a
// state outside the box is valid, as in hyfal; satisfiesBounds is always true).
//
// Control space: R^m with the box U_q0 of the initial mode. A control c is applied at (q, x) as
// the affine image of c on the admissible box System::input_bounds(q, x) (InputGrid::map_onto,
// the map hyfal's RRTs apply to Ū): the identity for a suite whose inputs depend neither on the
// mode nor on the state, a driver's interval for navigation, re-mapped at the start of every
// piece, so every piece's u is admissible where it starts.
//
// Propagation (HybridPropagator): OMPL's propagation step is the suite's δt; a control lasts
// [min_steps, max_steps] steps (the methods' options). One step flows with hyfal's Propagator
// (the suite's integrator, guards localized and resets applied through its event locator),
// continuing in the new mode after each urgent transition for the rest of δt (at most
// kMaxJumpsPerStep transitions: a Zeno chain makes the step inadmissible). A step that ends in
// the unsafe set (s <= 0, localized) stops there, and the state is absorbing: further steps
// leave it unchanged, so a multi-step control that passes through the unsafe set still ends
// in it and OMPL's goal test sees it. A step that leaves the invariant, turns non-finite or is
// interrupted (deadline, cancellation) yields an inadmissible state; the validity checker
// rejects those, so OMPL keeps the motion only up to the last admissible step (invariants
// act as obstacles).
//
// Goal (UnsafeGoal): the unsafe set s(q, x) <= 0; distance max(s, 0); its one sample is the
// suite's goal_point (the µ of hyfal's biased sampler, a point with s <= 0) in the initial mode
// (the mode enters no distance; Syclop locates the goal's region from the sample).
//
// Seeding (SeedStream): OMPL seeds every RNG it constructs from one process-wide generator, so
// under concurrent trials the seeds would depend on the order in which threads construct
// objects. Every RNG that drives the search is therefore re-seeded from the trial's seed: the
// planners' rng_, each state and control sampler (the allocators below: seeds in the order in
// which the planner allocates them, a fixed order in a single-threaded solve) and the pivot
// choice of the nearest-neighbour structures (SeededGnat). What stays unseeded: OMPL's Syclop
// draws its start and goal region from private RNGs (Syclop::RegionSet); with one start region
// and one goal region, as every suite with a grid has (navigation: one start state), the draw
// has one outcome.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/StatePropagator.h>
#include <ompl/control/planners/syclop/GridDecomposition.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/datastructures/NearestNeighborsGNATNoThreadSafety.h>

#include "core/model/decomposition.hpp"
#include "core/model/system.hpp"
#include "core/run/planner.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/util/rng.hpp"

namespace hyfal::ompl_adapter {

namespace ob = ompl::base;
namespace oc = ompl::control;

// Seeds for the OMPL objects of one trial: a SplitMix64 stream from the trial's seed, one draw
// per object in the order the objects are made. OMPL's RNG takes 32-bit seeds (never 0).
class SeedStream {
 public:
  explicit SeedStream(std::uint64_t trial_seed) : state_(splitmix64(trial_seed ^ fnv1a("ompl"))) {}
  std::uint32_t next() {
    state_ = splitmix64(state_);
    const auto s = static_cast<std::uint32_t>(state_ >> 32);
    return s == 0 ? 1u : s;
  }

 private:
  std::uint64_t state_;
};

class HybridStateSpace final : public ob::RealVectorStateSpace {
 public:
  class StateType : public ob::RealVectorStateSpace::StateType {
   public:
    Mode mode = 0;
    bool admissible = true;  // false: made by a step that left the invariant, diverged or was interrupted
  };

  explicit HybridStateSpace(const System& system);

  ob::State* allocState() const override;
  void freeState(ob::State* state) const override;
  void copyState(ob::State* destination, const ob::State* source) const override;
  bool equalStates(const ob::State* a, const ob::State* b) const override;
  double distance(const ob::State* a, const ob::State* b) const override;
  double getMaximumExtent() const override;
  bool satisfiesBounds(const ob::State*) const override { return true; }
  void interpolate(const ob::State* from, const ob::State* to, double t, ob::State* state) const override;
  void registerProjections() override;

  const System& system() const { return system_; }
  std::span<double> x(ob::State* s) const { return {s->as<StateType>()->values, dim_}; }
  std::span<const double> x(const ob::State* s) const { return {s->as<StateType>()->values, dim_}; }
  // Sets s to (q, x), admissible.
  void set(ob::State* s, Mode q, std::span<const double> x) const;

 private:
  const System& system_;
  std::size_t dim_;
  WeightedEuclidean metric_;
};

// KPIECE1's projection (HybridStateSpace's default projection), in this order of preference:
//  1. the suite's coverage grid (SystemInfo::coverage: the grid G of c(T), seed 000 eq. II.1):
//     its dimensions (all when it names none) and its spacing δx as the cell size;
//  2. else the region decomposition's 2-D projection with its coverage cell size;
//  3. else the first (up to) two state dimensions, cells 1/20 of the sampling box.
// Bounds: the coverage box, the sampling box's, or OMPL's estimate for 2 (a few seeded samples).
class HybridProjection final : public ob::ProjectionEvaluator {
 public:
  explicit HybridProjection(const HybridStateSpace* space);
  unsigned int getDimension() const override { return static_cast<unsigned int>(dims_.empty() ? 2 : dims_.size()); }
  void defaultCellSizes() override { cellSizes_ = cells_; }
  void project(const ob::State* state, Eigen::Ref<Eigen::VectorXd> projection) const override;

 private:
  const HybridStateSpace* space_;
  const Decomposition* decomposition_ = nullptr;  // set for choice 2 (dims_ empty)
  std::vector<int> dims_;
  std::vector<double> cells_;
};

// What one propagation step did, and the counters OMPL's propagation calls add up to.
enum class StepEnd { completed, unsafe, inadmissible };

class HybridPropagator final : public oc::StatePropagator {
 public:
  // The deepest chain of transitions one step of δt may take before it counts as Zeno.
  static constexpr int kMaxJumpsPerStep = 64;

  HybridPropagator(oc::SpaceInformation* si, const HybridStateSpace& space, std::span<const double> parameters,
                   PropagationInterrupt interrupt);

  void propagate(const ob::State* state, const oc::Control* control, double duration, ob::State* result) const override;
  bool canPropagateBackward() const override { return false; }

  // One step of `duration` from (q, x) under control c, in place. With `record` every piece is
  // added to it (as a tree node after `leaf`, which follows the last one): the witness replay.
  StepEnd step(Mode& q, std::vector<double>& x, std::span<const double> c, double duration, NodeStore* record,
               NodeId& leaf) const;
  // From now on steps are not counted and not interrupted: the witness replay.
  void start_replay() const;
  const PlannerCounters& counters() const { return counters_; }
  Propagator& propagator() const { return *prop_; }

 private:
  // u = c on the admissible box at (q, x) (see the header comment).
  void admissible_input(Mode q, std::span<const double> x, std::span<const double> c) const;

  const System& system_;
  std::span<const double> parameters_;
  ob::RealVectorBounds control_box_;
  bool state_dependent_;
  // Mutable: OMPL's propagate() is const; the workspace is this trial's alone.
  std::unique_ptr<Propagator> prop_;
  mutable std::vector<double> x_, out_, u_, lo_, hi_;
  mutable PlannerCounters counters_;
  mutable bool counting_ = true;  // off during the witness replay
};

class AdmissibleStates final : public ob::StateValidityChecker {
 public:
  explicit AdmissibleStates(const oc::SpaceInformationPtr& si) : ob::StateValidityChecker(si) {}
  bool isValid(const ob::State* state) const override { return state->as<HybridStateSpace::StateType>()->admissible; }
};

class UnsafeGoal final : public ob::GoalSampleableRegion {
 public:
  UnsafeGoal(const oc::SpaceInformationPtr& si, const HybridStateSpace& space, std::span<const double> parameters);
  double distanceGoal(const ob::State* state) const override;
  // s <= 0 (GoalRegion's own test is distanceGoal < threshold, which misses s = 0 exactly).
  bool isSatisfied(const ob::State* state) const override { return distanceGoal(state) <= 0.0; }
  bool isSatisfied(const ob::State* state, double* distance) const override {
    const double d = distanceGoal(state);
    if (distance) *distance = d;
    return d <= 0.0;
  }
  void sampleGoal(ob::State* state) const override;
  unsigned int maxSampleCount() const override;

 private:
  const HybridStateSpace& space_;
  std::span<const double> parameters_;
};

// Syclop's decomposition: the suite's grid (Decomposition::state_grid) as OMPL's GridDecomposition.
class StateGridDecomposition final : public oc::GridDecomposition {
 public:
  explicit StateGridDecomposition(const hyfal::Decomposition::StateGrid& grid);
  void project(const ob::State* s, std::vector<double>& coord) const override;
  void sampleFullState(const ob::StateSamplerPtr& sampler, const std::vector<double>& coord,
                       ob::State* s) const override;

 private:
  std::array<int, 2> dims_;
};

// OMPL's GNAT (the default nearest-neighbour structure of its RRT and SST) with its pivot choice
// seeded, and a count of the elements ever added (SST removes pruned ones; the count is its nodes).
template <class T>
class SeededGnat final : public ompl::NearestNeighborsGNATNoThreadSafety<T> {
  // GNAT picks the first pivot of a split with GreedyKCenters' protected rng_; a pointer to that
  // member, formed in a class derived from GreedyKCenters, reaches it in GNAT's pivotSelector_.
  struct PivotRng : ompl::GreedyKCenters<T> {
    static ompl::RNG& of(ompl::GreedyKCenters<T>& k) { return k.*(&PivotRng::rng_); }
  };

 public:
  explicit SeededGnat(std::uint32_t seed) { PivotRng::of(this->pivotSelector_).setLocalSeed(seed); }
  void add(const T& data) override {
    ++added_;
    ompl::NearestNeighborsGNATNoThreadSafety<T>::add(data);
  }
  void add(const std::vector<T>& data) override {
    added_ += data.size();
    ompl::NearestNeighborsGNATNoThreadSafety<T>::add(data);
  }
  std::size_t added() const { return added_; }

 private:
  std::size_t added_ = 0;
};

// The control space, state space and space information of one trial, seeded from `seeds`
// (state and control samplers draw their seeds from it as OMPL allocates them).
struct Problem {
  std::shared_ptr<HybridStateSpace> space;
  std::shared_ptr<oc::RealVectorControlSpace> controls;
  oc::SpaceInformationPtr si;
  std::shared_ptr<HybridPropagator> propagator;
  std::shared_ptr<SeedStream> seeds;
};
// min_steps/max_steps: a control's duration in propagation steps of δt.
Problem make_problem(const PlannerContext& ctx, const SearchBudget& budget, unsigned min_steps, unsigned max_steps);

}  // namespace hyfal::ompl_adapter
