#include "core/planners/ompl/hybrid_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

#include <ompl/util/Console.h>

#include "core/search/input_grid.hpp"

namespace hyfal::ompl_adapter {

namespace {

// OMPL's state sampler over the sampling box, with its own seed.
class SeededStateSampler final : public ob::RealVectorStateSampler {
 public:
  SeededStateSampler(const ob::StateSpace* space, std::uint32_t seed) : ob::RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

// OMPL's uniform control sampler over the control box, with its own seed.
class SeededControlSampler final : public oc::RealVectorControlUniformSampler {
 public:
  SeededControlSampler(const oc::ControlSpace* space, std::uint32_t seed) : oc::RealVectorControlUniformSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

ob::RealVectorBounds bounds_of(const Box& box) {
  ob::RealVectorBounds b(static_cast<unsigned int>(box.dim()));
  b.low = box.lo;
  b.high = box.hi;
  return b;
}

}  // namespace

// --- state space -------------------------------------------------------------------------------

HybridStateSpace::HybridStateSpace(const System& system)
    : ob::RealVectorStateSpace(static_cast<unsigned int>(system.info().dim())),
      system_(system),
      dim_(system.info().dim()),
      metric_(system.info().metric_weights) {
  setName("hyfal-" + system.info().suite);
  setBounds(bounds_of(system.info().sampling_box));
}

ob::State* HybridStateSpace::allocState() const {
  auto* s = new StateType();
  s->values = new double[dim_]();
  s->mode = system_.info().initial_mode;
  return s;
}

void HybridStateSpace::freeState(ob::State* state) const {
  auto* s = static_cast<StateType*>(state);
  delete[] s->values;
  delete s;
}

void HybridStateSpace::copyState(ob::State* destination, const ob::State* source) const {
  auto* d = destination->as<StateType>();
  const auto* s = source->as<StateType>();
  std::copy(s->values, s->values + dim_, d->values);
  d->mode = s->mode;
  d->admissible = s->admissible;
}

bool HybridStateSpace::equalStates(const ob::State* a, const ob::State* b) const {
  const auto* sa = a->as<StateType>();
  const auto* sb = b->as<StateType>();
  return sa->mode == sb->mode && sa->admissible == sb->admissible &&
         std::equal(sa->values, sa->values + dim_, sb->values);
}

double HybridStateSpace::distance(const ob::State* a, const ob::State* b) const { return metric_.distance(x(a), x(b)); }

double HybridStateSpace::getMaximumExtent() const {
  const Box& box = system_.info().sampling_box;
  return metric_.distance(box.lo, box.hi);
}

void HybridStateSpace::interpolate(const ob::State* from, const ob::State* to, double t, ob::State* state) const {
  const auto* f = from->as<StateType>();
  const auto* g = to->as<StateType>();
  auto* s = state->as<StateType>();
  for (std::size_t i = 0; i < dim_; ++i) s->values[i] = f->values[i] + t * (g->values[i] - f->values[i]);
  s->mode = t < 1.0 ? f->mode : g->mode;
  s->admissible = f->admissible && g->admissible;
}

void HybridStateSpace::registerProjections() { registerDefaultProjection(std::make_shared<HybridProjection>(this)); }

void HybridStateSpace::set(ob::State* s, Mode q, std::span<const double> x) const {
  auto* st = s->as<StateType>();
  std::copy(x.begin(), x.end(), st->values);
  st->mode = q;
  st->admissible = true;
}

// --- projection --------------------------------------------------------------------------------

HybridProjection::HybridProjection(const HybridStateSpace* space) : ob::ProjectionEvaluator(space), space_(space) {
  const SystemInfo& info = space->system().info();
  const CoverageSpec& cov = info.coverage;
  if (cov.spacing > 0.0) {  // 1. the coverage grid
    dims_ = cov.dims;
    if (dims_.empty())
      for (std::size_t i = 0; i < info.dim(); ++i) dims_.push_back(static_cast<int>(i));
    cells_.assign(dims_.size(), cov.spacing);
    if (cov.box.dim() == dims_.size()) setBounds(bounds_of(cov.box));
  } else if ((decomposition_ = space->system().decomposition())) {  // 2. the decomposition's projection
    cells_.assign(2, decomposition_->cell_size());
  } else {  // 3. the first two dimensions
    const Box& box = info.sampling_box;
    for (std::size_t i = 0; i < std::min<std::size_t>(2, info.dim()); ++i) {
      dims_.push_back(static_cast<int>(i));
      const double cell = (box.hi[i] - box.lo[i]) / 20.0;
      cells_.push_back(cell > 0.0 ? cell : 1.0);
    }
    ob::RealVectorBounds b(static_cast<unsigned int>(dims_.size()));
    for (std::size_t k = 0; k < dims_.size(); ++k) {
      b.low[k] = box.lo[dims_[k]];
      b.high[k] = box.hi[dims_[k]];
    }
    setBounds(b);
  }
}

void HybridProjection::project(const ob::State* state, Eigen::Ref<Eigen::VectorXd> projection) const {
  const auto x = space_->x(state);
  if (dims_.empty()) {
    double out[2];
    decomposition_->project(state->as<HybridStateSpace::StateType>()->mode, x, std::span<double, 2>(out, 2));
    projection[0] = out[0];
    projection[1] = out[1];
    return;
  }
  for (std::size_t k = 0; k < dims_.size(); ++k) projection[static_cast<Eigen::Index>(k)] = x[dims_[k]];
}

// --- propagation -------------------------------------------------------------------------------

HybridPropagator::HybridPropagator(oc::SpaceInformation* si, const HybridStateSpace& space,
                                   std::span<const double> parameters, PropagationInterrupt interrupt)
    : oc::StatePropagator(si),
      system_(space.system()),
      parameters_(parameters),
      control_box_(bounds_of(space.system().inputs(space.system().info().initial_mode).box)),
      state_dependent_(space.system().state_dependent_inputs()),
      prop_(space.system().make_propagator()) {
  prop_->set_interrupt(std::move(interrupt));
  const std::size_t n = system_.info().dim(), m = control_box_.low.size();
  x_.resize(n);
  out_.resize(n);
  u_.resize(m);
  lo_.resize(m);
  hi_.resize(m);
}

void HybridPropagator::admissible_input(Mode q, std::span<const double> x, std::span<const double> c) const {
  const Box& box = system_.inputs(q).box;
  const std::size_t m = u_.size();
  bool identity = !state_dependent_;
  for (std::size_t i = 0; i < m && identity; ++i)
    identity = box.lo[i] == control_box_.low[i] && box.hi[i] == control_box_.high[i];
  if (identity) {
    std::copy(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(m), u_.begin());
    return;
  }
  system_.input_bounds(q, x, lo_, hi_);
  for (std::size_t i = 0; i < m; ++i)
    u_[i] = InputGrid::map_onto(c[i], control_box_.low[i], control_box_.high[i], lo_[i], hi_[i]);
}

StepEnd HybridPropagator::step(Mode& q, std::vector<double>& x, std::span<const double> c, double duration,
                               NodeStore* record, NodeId& leaf) const {
  if (system_.spec(q, x, parameters_) <= 0.0) return StepEnd::unsafe;  // absorbing
  const double t_eps = 1e-12 * std::max(1.0, std::abs(duration));
  double left = duration;
  for (int jumps = 0;; ++jumps) {
    if (jumps > kMaxJumpsPerStep) return StepEnd::inadmissible;  // a Zeno chain
    admissible_input(q, x, c);
    const PropagationResult r = prop_->propagate(q, x, u_, parameters_, left, out_);
    if (counting_) {
      ++counters_.propagations;
      counters_.integration_steps += r.steps;
    }
    if (r.end == PropagationEnd::rejected || r.end == PropagationEnd::invariant) return StepEnd::inadmissible;
    if (record) leaf = record->add(leaf, q, r.mode, out_, u_, r.duration, r.transition);
    x.swap(out_);
    q = r.mode;
    if (r.end == PropagationEnd::unsafe || r.spec <= 0.0) return StepEnd::unsafe;
    if (r.end == PropagationEnd::completed) return StepEnd::completed;
    left -= r.duration;  // jumped: the rest of the step in the new mode
    if (left <= t_eps) return StepEnd::completed;
  }
}

void HybridPropagator::propagate(const ob::State* state, const oc::Control* control, double duration,
                                 ob::State* result) const {
  const auto* from = state->as<HybridStateSpace::StateType>();
  auto* to = result->as<HybridStateSpace::StateType>();  // may be `state`
  const auto* c = control->as<oc::RealVectorControlSpace::ControlType>();
  Mode q = from->mode;
  std::copy(from->values, from->values + x_.size(), x_.begin());
  NodeId unused = kNoNode;
  const StepEnd end = from->admissible
                          ? step(q, x_, std::span<const double>(c->values, u_.size()), duration, nullptr, unused)
                          : StepEnd::inadmissible;
  std::copy(x_.begin(), x_.end(), to->values);
  to->mode = q;
  to->admissible = end != StepEnd::inadmissible;
}

void HybridPropagator::start_replay() const {
  counting_ = false;
  prop_->set_interrupt({});  // the replay re-does work already done: no deadline
}

// --- goal and decomposition ----------------------------------------------------------------------

UnsafeGoal::UnsafeGoal(const oc::SpaceInformationPtr& si, const HybridStateSpace& space,
                       std::span<const double> parameters)
    : ob::GoalSampleableRegion(si), space_(space), parameters_(parameters) {}

double UnsafeGoal::distanceGoal(const ob::State* state) const {
  const auto* s = state->as<HybridStateSpace::StateType>();
  if (!s->admissible) return std::numeric_limits<double>::infinity();
  return std::max(0.0, space_.system().spec(s->mode, space_.x(state), parameters_));
}

void UnsafeGoal::sampleGoal(ob::State* state) const {
  const SystemInfo& info = space_.system().info();
  space_.set(state, info.initial_mode, info.goal_point);
}

unsigned int UnsafeGoal::maxSampleCount() const {
  const SystemInfo& info = space_.system().info();
  return info.goal_point.size() == info.dim() ? 1u : 0u;
}

namespace {
ob::RealVectorBounds grid_bounds(const hyfal::Decomposition::StateGrid& g) {
  ob::RealVectorBounds b(2);
  b.low = {g.lo[0], g.lo[1]};
  b.high = {g.hi[0], g.hi[1]};
  return b;
}
}  // namespace

StateGridDecomposition::StateGridDecomposition(const hyfal::Decomposition::StateGrid& grid)
    : oc::GridDecomposition(grid.cells_per_side, 2, grid_bounds(grid)), dims_(grid.dims) {}

void StateGridDecomposition::project(const ob::State* s, std::vector<double>& coord) const {
  const double* x = s->as<HybridStateSpace::StateType>()->values;
  coord.resize(2);
  // OMPL clamps a coordinate on the upper bound, not one below the lower bound.
  for (int k = 0; k < 2; ++k) coord[k] = std::clamp(x[dims_[k]], bounds_.low[k], bounds_.high[k]);
}

void StateGridDecomposition::sampleFullState(const ob::StateSamplerPtr& sampler, const std::vector<double>& coord,
                                             ob::State* s) const {
  sampler->sampleUniform(s);
  double* x = s->as<HybridStateSpace::StateType>()->values;
  for (int k = 0; k < 2; ++k) x[dims_[k]] = coord[k];
}

// --- one trial's problem -----------------------------------------------------------------------

Problem make_problem(const PlannerContext& ctx, const SearchBudget& budget, unsigned min_steps, unsigned max_steps) {
  // OMPL logs planner progress to stderr from every trial: hyfal reports outcomes itself.
  static std::once_flag quiet;
  std::call_once(quiet, [] { ompl::msg::setLogLevel(ompl::msg::LOG_NONE); });

  const System& system = ctx.system;
  const SystemInfo& info = system.info();
  Problem p;
  p.seeds = std::make_shared<SeedStream>(ctx.seed);
  std::shared_ptr<SeedStream> seeds = p.seeds;
  p.space = std::make_shared<HybridStateSpace>(system);
  p.space->setStateSamplerAllocator(
      [seeds](const ob::StateSpace* s) { return std::make_shared<SeededStateSampler>(s, seeds->next()); });
  const Box& box = system.inputs(info.initial_mode).box;
  p.controls = std::make_shared<oc::RealVectorControlSpace>(p.space, static_cast<unsigned int>(box.dim()));
  p.controls->setBounds(bounds_of(box));
  p.controls->setControlSamplerAllocator(
      [seeds](const oc::ControlSpace* c) { return std::make_shared<SeededControlSampler>(c, seeds->next()); });
  p.si = std::make_shared<oc::SpaceInformation>(p.space, p.controls);
  p.si->setStateValidityChecker(std::make_shared<AdmissibleStates>(p.si));
  p.propagator = std::make_shared<HybridPropagator>(p.si.get(), *p.space, ctx.parameters, budget.interrupt());
  p.si->setStatePropagator(p.propagator);
  p.si->setPropagationStepSize(info.step_duration);
  p.si->setMinMaxControlDuration(min_steps, max_steps);
  p.si->setup();
  return p;
}

}  // namespace hyfal::ompl_adapter
