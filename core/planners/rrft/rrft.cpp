// RRFT — Rapidly-exploring Random Forest of Trees (seed 003, Sect. 4-5, Alg. 3): one RRT per seed
// p_i of P̄ (a Halton sequence over the parameter box P), each extended by the step of
// core/planners/rrt/rrt_extension.hpp with p_i as its parameters, trees ended on growth or
// coverage and replaced while the seeds' dispersion µ(P̄) is above µ̄, then restarted at seeds not
// yet covered (issue 27).
//
// Invariants: results are identical at any thread count (the trees advance in rounds, everything
// that couples them happens at the round barrier in seed order, and every stream derives from the
// trial seed, the seed index and the restart count); the forest never holds more than max_nodes
// nodes (per-round node quotas); batch = 1 is Alg. 3's round of K sequential extensions.
//
// The conventions (coverage D(T) = seed 003's c(T), the scaled growth n_g·g), the run-ahead rounds,
// the batches, stalls, restarts, planting and the defaults with their reasons are written out in
// docs/methods.md, "RRFT in detail".
#include "core/planners/rrft/rrft.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include "core/planners/rrt/rrt_extension.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/coverage_grid.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/search/samplers/halton.hpp"
#include "core/util/rng.hpp"
#include "core/util/trial_cpu_clock.hpp"

namespace hyfal {

namespace {

// Defaults and ranges are declared once, in rrft_method(); `o` is resolved against them.
struct RrftOptions {
  int n_t;
  int K;
  double g_min;
  double c_min;
  double mu_min;
  int window;
  int max_seeds;
  bool shift;
  int series_every;
  std::size_t batch;
  std::int64_t budget = 0;  // simulation-equivalents (simulated time / the requirement's horizon); 0: no cap
};

RrftOptions parse_options(const Json& o) {
  RrftOptions r{};
  r.n_t = o.at("n_t").get<int>();
  r.K = o.at("K").get<int>();
  r.g_min = o.at("g_min").get<double>();
  r.c_min = o.at("c_min").get<double>();
  r.mu_min = o.at("mu_min").get<double>();
  r.window = o.at("window").get<int>();
  r.max_seeds = o.at("max_seeds").get<int>();
  r.shift = o.at("shift").get<bool>();
  r.series_every = o.at("series_every").get<int>();
  r.batch = o.at("batch").get<std::size_t>();
  r.budget = o.at("budget").get<std::int64_t>();
  return r;
}

enum class TreeEnd { active, growth, coverage, stalled };

// The point record_point() adds to a tree's coverage/growth series for its current size.
struct SeriesPoint {
  double n = 0.0;           // the tree's nodes
  double uncovered = 1.0;   // D(T)
  bool has_growth = false;  // more than `window` nodes: n_g·g(T) is defined
  double growth = 0.0;      // n_g·g(T)
};

// What the barrier of a round needs from one tree, taken by the tree itself when it finishes the
// round: with run-ahead (batch = 1) a tree may already be rounds further when its barrier comes.
struct RoundEnd {
  std::int64_t round = 0;
  PlannerCounters counters;
  std::size_t coverage_points = 0, growth_points = 0;  // series lengths
  SeriesPoint point;
  bool found = false;                  // the tree reached s <= 0 (it stops)
  TreeEnd decision = TreeEnd::active;  // its termination test (it stops unless active)
};

// One expansion slot of a batched round (batch > 1): its own step scratch and propagator, and
// the proposal it made against its tree's frozen state. Not tied to a tree: slot k of a round
// serves (active tree k / B, slot k % B).
struct RrftSlot {
  RrftSlot(const System& sys, const WeightedEuclidean& metric)
      : step(sys, metric), prop(sys.make_propagator()), x_rand(sys.info().dim()) {}
  RrtExtension step;
  std::unique_ptr<Propagator> prop;
  std::vector<double> x_rand;
  PlannerCounters counters;
  bool proposed = false;     // false: no proposal (no quota left, or the time was up)
  bool interrupted = false;  // the deadline passed mid-proposal: not a failed extension
};

// One tree of the forest, T_{p_i}. Touched by one task at a time (its round), else by the
// coordinating thread at the barriers.
struct ForestTree {
  ForestTree(const System& sys, const WeightedEuclidean& metric, std::size_t index_, std::size_t seed_,
             std::vector<double> p_, std::uint64_t stream_seed_)
      : index(index_),
        seed(seed_),
        p(std::move(p_)),
        nodes(sys.info().dim(), sys.info().input_names.size()),
        nn(std::in_place, metric),
        prop(sys.make_propagator()),
        step(sys, metric),
        stream_seed(stream_seed_),
        rng(stream_seed),
        grid(std::in_place, sys.info().coverage, sys.info().dim()),
        coverage_series{fmt::format("coverage/tree{}", index_), {}},
        growth_series{fmt::format("growth/tree{}", index_), {}} {
    const SystemInfo& info = sys.info();
    for (std::size_t i = 0; i < info.dim(); ++i) uniform.emplace_back(info.sampling_box.lo[i], info.sampling_box.hi[i]);
    x_rand.resize(info.dim());
  }

  std::size_t index;  // in planting order, restarts included: series tree<index>, nodes_per_tree
  std::size_t seed;   // its seed's index in P̄ (= index for a planted tree)
  std::vector<double> p;
  NodeStore nodes;
  std::optional<NearestNeighbors> nn;  // released when the tree ends
  std::unique_ptr<Propagator> prop;
  RrtExtension step;
  std::uint64_t stream_seed;  // seeds rng (batch = 1) and the slots' streams (batch > 1)
  Rng rng;
  std::optional<CoverageGrid> grid;  // released when the tree ends
  std::vector<std::uniform_real_distribution<double>> uniform;
  std::vector<double> x_rand;
  PlannerCounters counters;
  std::int64_t failed_streak = 0;  // consecutive extension attempts that added nothing
  NodeId leaf = kNoNode;           // a node with s <= 0, once found
  TreeEnd end = TreeEnd::active;
  NamedSeries coverage_series, growth_series;
  // Scheduling (see "Run-ahead" in the header).
  std::deque<RoundEnd> finished;  // rounds finished and not yet passed by their barrier
  RoundEnd at_barrier;            // as of the last barrier passed (counters of the tree there)
  std::int64_t last_round = 0;    // the last round this tree finished
  std::int64_t next_quota = 0;    // node quota of round (barrier + 1), in seed order
  bool running = false;           // a task is growing its next round
  bool stopped = false;           // found or terminated by its own round end: no more rounds
};

// g(T) and D(T) (seed 003 eq. 3) are measured on the suite's coverage grid.
void check_rrft_system(const System& sys, const Json& options) {
  if (!(sys.info().coverage.spacing > 0.0))
    throw std::invalid_argument(
        fmt::format("suite '{}' defines no coverage grid, which RRFT needs for c(T), g(T)", sys.info().suite));
  if (options.contains("budget") && options.at("budget").get<std::int64_t>() > 0) {
    const auto& requirement = sys.info().requirement;
    if (!requirement || !(std::isfinite(requirement->formula.horizon()) && requirement->formula.horizon() > 0.0))
      throw std::invalid_argument(
          "budget > 0 needs an STL requirement of finite, positive horizon (simulations are "
          "simulated time / the horizon): --set requirement=...");
  }
}

// One RRFT trial: the forest, its rounds and barriers. Rrft::solve builds one and runs it.
class ForestSearch {
 public:
  ForestSearch(const RrftOptions& o, const PlannerContext& ctx)
      : o_(o),
        ctx_(ctx),
        sys_(ctx.system),
        info_(sys_.info()),
        metric_(info_.metric_weights),
        budget_(ctx),
        time_cap_(o.budget > 0 ? static_cast<double>(o.budget) * info_.requirement->formula.horizon()
                               : std::numeric_limits<double>::infinity()),
        searched_(info_.parameter_box.has_width()),
        halton_(info_.parameter_box, halton_shift(o, ctx)),
        max_active_(searched_ ? static_cast<std::size_t>(o.n_t) : 1),
        max_seeds_(searched_ ? static_cast<std::size_t>(o.max_seeds) : 1),
        mu_(searched_ ? 1.0 : 0.0),
        n_g_(static_cast<double>(CoverageGrid(info_.coverage, info_.dim()).points())) {}

  PlannerOutcome run() {
    const std::size_t initial = std::min(max_active_, max_seeds_);
    for (std::size_t i = 0; i < initial; ++i) plant();
    done_ = end_checks();
    if (!done_) plan_next_round();
    if (!done_ && o_.batch > 1)
      run_batched_rounds();
    else if (!done_)
      run_ahead_rounds();
    return report();
  }

 private:
  // The Cranley–Patterson shift of the Halton sequence (`shift`), from the trial seed.
  static std::vector<double> halton_shift(const RrftOptions& o, const PlannerContext& ctx) {
    const Box& P = ctx.system.info().parameter_box;
    std::vector<double> shift;
    if (o.shift && P.dim() > 0) {
      Rng srng(splitmix64(ctx.seed ^ 0x48616c746f6e5368ULL));
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (std::size_t k = 0; k < P.dim(); ++k) shift.push_back(unit(srng));
    }
    return shift;
  }

  // The forest's counters as of the last barrier.
  void recount() {
    total_ = {};
    for (const auto& t : trees_) {
      total_.nodes += t->at_barrier.counters.nodes;
      total_.add_work(t->at_barrier.counters);
    }
  }

  SeriesPoint point_of(const ForestTree& t) const {
    SeriesPoint pt;
    pt.n = static_cast<double>(t.nodes.size());
    pt.uncovered = t.grid->uncovered();
    pt.has_growth = t.grid->nodes() > static_cast<std::size_t>(o_.window);
    if (pt.has_growth) pt.growth = n_g_ * t.grid->growth(static_cast<std::size_t>(o_.window));
    return pt;
  }

  static void record_point(ForestTree& t, const SeriesPoint& pt) {
    if (!t.coverage_series.points.empty() && t.coverage_series.points.back().first == pt.n) return;
    t.coverage_series.points.emplace_back(pt.n, pt.uncovered);
    if (pt.has_growth) t.growth_series.points.emplace_back(pt.n, pt.growth);
  }

  // The tree's own termination test: stalled, not growing, fully grown (or active).
  TreeEnd termination_test(const ForestTree& t, const SeriesPoint& pt) const {
    if (t.failed_streak >= o_.window) return TreeEnd::stalled;
    if (pt.has_growth && pt.growth <= o_.g_min) return TreeEnd::growth;
    if (pt.uncovered <= o_.c_min) return TreeEnd::coverage;
    return TreeEnd::active;
  }

  // The end of a tree's round, by the tree itself: its counters, series lengths, found, and its
  // termination test, all functions of its own state.
  void end_round(ForestTree& t, std::int64_t round) const {
    RoundEnd e;
    e.round = round;
    e.counters = t.counters;
    e.coverage_points = t.coverage_series.points.size();
    e.growth_points = t.growth_series.points.size();
    e.point = point_of(t);
    e.found = t.leaf != kNoNode;
    if (!e.found) e.decision = termination_test(t, e.point);
    t.stopped = e.found || e.decision != TreeEnd::active;
    t.last_round = round;
    t.finished.push_back(e);
  }

  // Alg. 3's planting: a new tree at the next seed of P̄ (the suite's parameters when P is not
  // searched), with the seed's own stream.
  void plant() {
    std::vector<double> p =
        searched_ ? halton_.next() : std::vector<double>(ctx_.parameters.begin(), ctx_.parameters.end());
    seeds_.push_back(std::move(p));
    const std::size_t seed = seeds_.size() - 1;
    add_tree(seed, stream_seed(0x52524654'00000000ULL + seed));  // "RRFT"
    mu_ = searched_ ? dispersion(seeds_, info_.parameter_box) : 0.0;
    dispersion_series_.points.emplace_back(static_cast<double>(total_.nodes), mu_);
  }

  // A restart (see "Restarts" in the header): a new tree at seed s of P̄, from the initial state,
  // with a fresh stream of the trial seed and the restart count (never of a thread).
  void restart(std::size_t s) {
    ++restarts_;
    add_tree(s, stream_seed(0x52455354'00000000ULL + static_cast<std::uint64_t>(restarts_)));  // "REST"
  }

  std::uint64_t stream_seed(std::uint64_t salt) const { return splitmix64(splitmix64(ctx_.seed) ^ splitmix64(salt)); }

  // A new active tree at seed s, rooted at (x0, q0); its first round is the one after this barrier.
  void add_tree(std::size_t s, std::uint64_t stream) {
    auto t = std::make_unique<ForestTree>(sys_, metric_, trees_.size(), s, seeds_[s], stream);
    t->prop->set_interrupt(budget_.interrupt());  // a propagation past the deadline ends as rejected
    const NodeId root = t->nodes.add(kNoNode, info_.initial_mode, info_.initial_mode, info_.initial_state, {}, 0.0, -1);
    t->nn->add(root, info_.initial_state);
    t->grid->add(info_.initial_state);
    t->counters.nodes = 1;
    if (starts_unsafe(sys_, info_.initial_mode, info_.initial_state, t->p)) t->leaf = root;
    t->at_barrier.counters = t->counters;
    t->at_barrier.found = t->leaf != kNoNode;
    t->stopped = t->at_barrier.found;
    t->last_round = rounds_;
    active_.push_back(t.get());
    trees_.push_back(std::move(t));
    recount();
  }

  // Alg. 3 plants another seed: P̄ is not dispersed enough and fewer than max_seeds are planted.
  bool may_plant() const { return searched_ && seeds_.size() < max_seeds_ && mu_ > o_.mu_min; }

  // The seed a restart goes to: of the seeds whose trees all concluded, none of them fully
  // grown, the one whose trees hold the fewest nodes so far (ties: the lowest index), so that
  // restarts spread over the seeds whose reachable sets are least explored. None when every
  // idle seed was covered by a fully grown tree (with no tree growing: the search is complete).
  std::optional<std::size_t> restart_seed() const {
    std::vector<std::int64_t> nodes(seeds_.size(), 0);
    std::vector<bool> excluded(seeds_.size(), false);  // covered, or a tree still grows there
    for (const auto& t : trees_) {
      nodes[t->seed] += t->at_barrier.counters.nodes;
      if (t->end != TreeEnd::growth) excluded[t->seed] = true;  // coverage, active or parked
    }
    std::optional<std::size_t> best;
    for (std::size_t s = 0; s < seeds_.size(); ++s)
      if (!excluded[s] && (!best || nodes[s] < nodes[*best])) best = s;
    return best;
  }

  // The end checks, in seed order: found? (lowest seed index wins), no tree left, the budget.
  bool end_checks() {
    for (ForestTree* t : active_)
      if (t->at_barrier.found) {
        winner_ = t;
        out_.status = TrialStatus::falsified;
        return true;
      }
    if (active_.empty()) {  // the search is complete, or the node cap stopped a planting or restart
      const bool complete = !may_plant() && !restart_seed();
      out_.status = complete ? TrialStatus::not_found : TrialStatus::node_cap;
      return true;
    }
    if (auto why = budget_.exhausted(total_.nodes)) {
      out_.status = *why;
      return true;
    }
    if (total_.simulated_time >= time_cap_) {  // the simulation budget, checked at the barrier
      out_.status = TrialStatus::budget;
      return true;
    }
    return false;
  }

  // Node quotas of the next round in seed order, and how far trees may run ahead of it.
  void plan_next_round() {
    std::int64_t left = ctx_.limits.max_nodes - total_.nodes;
    const std::int64_t per_round = static_cast<std::int64_t>(max_active_) * (o_.K + 1);  // nodes and roots
    ahead_ = 0;
    while (ahead_ < kRunAhead && left >= (ahead_ + 2) * per_round) ++ahead_;
    for (ForestTree* t : active_) {
      t->next_quota = std::min<std::int64_t>(o_.K, std::max<std::int64_t>(left, 0));
      left -= t->next_quota;
    }
  }

  // The trees whose round ended in a termination leave the active set (seed order).
  void terminate_ended_trees() {
    std::vector<ForestTree*> still;
    for (ForestTree* t : active_) {
      t->end = t->at_barrier.decision;
      if (t->end == TreeEnd::active) {
        still.push_back(t);
        continue;
      }
      ++terminated_[static_cast<int>(t->end)];
      record_point(*t, point_of(*t));    // a terminated tree stopped at this round
      if (t->end == TreeEnd::stalled) {  // not concluded: it keeps its nodes and waits for a slot
        parked_.push_back(t);
        continue;
      }
      if (ctx_.trees) ctx_.trees->add(t->index, t->nodes);  // --save-trees: before its nodes are freed
      release(*t);
    }
    active_.swap(still);
  }

  // The free slots, in this order: a new seed while P̄ is not dispersed enough (Alg. 3), else
  // the stalled tree that has waited longest resumes, else a restart at the least explored seed
  // not yet covered (see "Stalls" and "Restarts" in the header).
  void refill_slots() {
    while (active_.size() < max_active_) {
      const bool room = total_.nodes < ctx_.limits.max_nodes;
      std::optional<std::size_t> s;
      if (may_plant() && room) {
        plant();
      } else if (!parked_.empty()) {
        resume(parked_.front());
        parked_.pop_front();
      } else if (room && (s = restart_seed())) {
        restart(*s);
      } else {
        break;
      }
    }
  }

  // A stalled tree grows again from where it stopped, with its own stream, in seed order among
  // the active trees; its next round is the one after this barrier.
  void resume(ForestTree* t) {
    t->end = TreeEnd::active;
    t->at_barrier.decision = TreeEnd::active;
    t->failed_streak = 0;
    t->stopped = false;
    t->last_round = rounds_;
    auto at = std::find_if(active_.begin(), active_.end(), [&](const ForestTree* a) { return a->index > t->index; });
    active_.insert(at, t);
  }

  // The barrier of round `rounds_` (every active tree finished it): found? then terminations
  // (seed order), plantings, the end checks. Returns true when the search ends.
  bool barrier() {
    ++rounds_;
    for (ForestTree* t : active_) {
      t->at_barrier = t->finished.front();
      t->finished.pop_front();
    }
    recount();
    bool found = false;
    for (ForestTree* t : active_) found = found || t->at_barrier.found;
    if (!found) {  // terminations, unless a tree found the unsafe set this round
      terminate_ended_trees();
      refill_slots();
    }
    if (end_checks()) return true;
    plan_next_round();
    return false;
  }

  // batch > 1: lockstep rounds of B slots per tree.
  void run_batched_rounds() {
    std::vector<std::int64_t> quota;
    std::vector<std::unique_ptr<RrftSlot>> slots;  // the rounds' slot scratch, reused
    while (!done_) {
      quota.clear();
      for (ForestTree* t : active_) quota.push_back(t->next_quota);
      grow_batched(active_, quota, static_cast<std::uint64_t>(rounds_ + 1), slots);
      for (ForestTree* t : active_) end_round(*t, rounds_ + 1);
      done_ = barrier();
    }
  }

  // batch = 1: run-ahead rounds of K extensions. A task grows one round of one tree; when it
  // ends, the same task starts that tree's next round if the tree goes on and the look-ahead
  // allows, and passes every barrier whose round all active trees have finished.
  void run_ahead_rounds() {
    tbb::task_group tasks;
    tbb::this_task_arena::isolate([&] {  // while it waits, this thread runs only this trial's rounds
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (ForestTree* t : active_) start_round(tasks, t);
      }
      tasks.wait();
    });
    std::lock_guard<std::mutex> lock(mutex_);  // happens-before from the last task
  }

  // Starts tree t's next round as a task, unless it is parked by the look-ahead. Under mutex_.
  void start_round(tbb::task_group& tasks, ForestTree* t) {
    if (done_ || t->running || t->stopped) return;
    const std::int64_t round = t->last_round + 1;
    if (round > rounds_ + 1 + ahead_) return;  // parked until the next barrier
    const std::int64_t q = round == rounds_ + 1 ? t->next_quota : o_.K;
    t->running = true;
    tasks.run([this, &tasks, t, round, q] {
      auto body = [&] {
        { std::lock_guard<std::mutex> sync(mutex_); }  // happens-before from the spawner
        grow(*t, q);
        std::lock_guard<std::mutex> lock(mutex_);
        end_round(*t, round);
        t->running = false;
        start_round(tasks, t);
        pass_barriers(tasks);
      };
      if (ctx_.cpu)
        ctx_.cpu->task(body);  // cpu_s counts the threads that helped
      else
        body();
    });
  }

  // Passes every barrier whose round all active trees have finished. Under mutex_.
  void pass_barriers(tbb::task_group& tasks) {
    while (!done_) {
      for (ForestTree* t : active_)
        if (t->finished.empty()) return;
      done_ = barrier();
      if (!done_)
        for (ForestTree* t : active_) start_round(tasks, t);  // parked by the look-ahead, or planted
    }
  }

  // Per-trial results, as of the last barrier: a tree that ran ahead of it drops the series
  // points of its later rounds (their counters are not counted either).
  PlannerOutcome report() {
    if (winner_) {
      Trajectory traj = trajectory_from_tree(sys_, *winner_->prop, winner_->nodes, winner_->leaf, winner_->p);
      traj.parameters = winner_->p;
      out_.trajectory = std::move(traj);
    }
    recount();
    out_.counters = total_;
    Json per_tree = Json::array();
    for (auto& t : trees_) {
      per_tree.push_back(t->at_barrier.counters.nodes);
      if (t->grid) {
        if (t->last_round > rounds_) {
          t->coverage_series.points.resize(t->at_barrier.coverage_points);
          t->growth_series.points.resize(t->at_barrier.growth_points);
          record_point(*t, t->at_barrier.point);
        } else {
          record_point(*t, point_of(*t));
        }
      }
      out_.series.push_back(std::move(t->coverage_series));
      out_.series.push_back(std::move(t->growth_series));
    }
    out_.series.push_back(std::move(dispersion_series_));
    out_.metrics["seeds_planted"] = seeds_.size();
    out_.metrics["trees"] = trees_.size();  // planted and restarted
    out_.metrics["restarts"] = restarts_;
    out_.metrics["nodes_per_tree"] = per_tree;
    out_.metrics["winning_seed"] = winner_ ? static_cast<std::int64_t>(winner_->seed) : std::int64_t{-1};
    out_.metrics["winning_parameter"] = winner_ ? Json(winner_->p) : Json(nullptr);
    // Each coordinate also as a scalar (p0, p1, ...), so tables can average it over trials.
    if (winner_)
      for (std::size_t i = 0; i < winner_->p.size(); ++i) out_.metrics["winning_p" + std::to_string(i)] = winner_->p[i];
    out_.metrics["dispersion_final"] = mu_;
    out_.metrics["terminated_growth"] = terminated_[static_cast<int>(TreeEnd::growth)];
    out_.metrics["terminated_coverage"] = terminated_[static_cast<int>(TreeEnd::coverage)];
    out_.metrics["terminated_stalled"] = terminated_[static_cast<int>(TreeEnd::stalled)];
    out_.metrics["rounds"] = rounds_;
    if (ctx_.trees)  // --save-trees: the trees not released at a termination (recorded there)
      for (const auto& t : trees_)
        if (t->end == TreeEnd::active || t->end == TreeEnd::stalled) ctx_.trees->add(t->index, t->nodes);
    return std::move(out_);
  }

  // Up to K extension attempts of one tree (the RRT step of rrt_extension.hpp), at most `quota`
  // nodes added; stops early when the tree reaches s <= 0 or the time is up.
  void grow(ForestTree& t, std::int64_t quota) const {
    const std::size_t n = info_.dim();
    std::int64_t added = 0;
    for (int a = 0; a < o_.K && added < quota && t.leaf == kNoNode; ++a) {
      if (budget_.exhausted(0)) return;  // time or cancellation (the node cap is the quota's)
      for (std::size_t i = 0; i < n; ++i) t.x_rand[i] = t.uniform[i](t.rng);
      const RrtExtensionResult r = t.step.extend(t.nodes, *t.nn, *t.prop, t.x_rand, t.p, t.rng, t.counters);
      if (!r.added()) {
        if (t.prop->interrupted()) return;  // the deadline passed mid-extension: not a stall
        ++t.failed_streak;
        continue;
      }
      ++added;
      after_add(t, r);
    }
  }

  // One batched round (batch = B > 1): every active tree's B slots proposed in one parallel_slots
  // call against the frozen trees, then each tree's slots committed in slot order, at most
  // `quota` nodes per tree, stopping at the tree's first node with s <= 0.
  void grow_batched(const std::vector<ForestTree*>& active, const std::vector<std::int64_t>& quota, std::uint64_t round,
                    std::vector<std::unique_ptr<RrftSlot>>& slots) const {
    const std::size_t B = o_.batch, n = info_.dim();
    const std::size_t count = active.size() * B;
    while (slots.size() < count) {
      slots.push_back(std::make_unique<RrftSlot>(sys_, metric_));
      slots.back()->prop->set_interrupt(budget_.interrupt());  // a propagation past the deadline ends as rejected
    }
    parallel_slots(count, ctx_.cpu, [&](std::size_t k) {
      const std::size_t i = k / B, s = k % B;
      const ForestTree& t = *active[i];
      RrftSlot& slot = *slots[k];
      slot.counters = {};
      slot.proposed = false;
      slot.interrupted = false;
      if (quota[i] <= 0 || t.leaf != kNoNode) return;  // nothing this tree may add
      if (budget_.exhausted(0)) return;                // time or cancellation
      Rng g(slot_seed(t.stream_seed, round, s));
      for (std::size_t d = 0; d < n; ++d) {
        auto axis = t.uniform[d];  // a copy: distributions are not const-callable
        slot.x_rand[d] = axis(g);
      }
      slot.step.propose(t.nodes, t.nn->nearest(slot.x_rand).id, *slot.prop, slot.x_rand, t.p, g, slot.counters);
      slot.interrupted = slot.prop->interrupted();
      slot.proposed = true;
    });
    for (std::size_t i = 0; i < active.size(); ++i) commit_slots(*active[i], quota[i], &slots[i * B]);
  }

  // Tree t's B slots of a batched round committed in slot order (trees in seed order).
  void commit_slots(ForestTree& t, std::int64_t quota, const std::unique_ptr<RrftSlot>* slots) const {
    const std::size_t B = o_.batch;
    for (std::size_t s = 0; s < B; ++s) {  // every propagation of the round was made
      t.counters.add_work(slots[s]->counters);
    }
    std::int64_t added = 0;
    for (std::size_t s = 0; s < B && added < quota && t.leaf == kNoNode; ++s) {
      RrftSlot& slot = *slots[s];
      if (!slot.proposed) continue;
      const RrtExtensionResult r = slot.step.commit(t.nodes, *t.nn, t.counters);
      if (!r.added()) {
        if (slot.interrupted) break;  // the deadline passed mid-extension: not a stall
        ++t.failed_streak;
        continue;
      }
      ++added;
      after_add(t, r);
    }
  }

  // A new node of tree t: coverage, the failed streak, the series, the found check.
  void after_add(ForestTree& t, const RrtExtensionResult& r) const {
    t.grid->add(t.nodes.state(r.node));
    t.failed_streak = 0;
    if (t.nodes.size() % static_cast<std::size_t>(o_.series_every) == 0) {
      t.coverage_series.points.emplace_back(static_cast<double>(t.nodes.size()), t.grid->uncovered());
      if (t.grid->nodes() > static_cast<std::size_t>(o_.window))
        t.growth_series.points.emplace_back(
            static_cast<double>(t.nodes.size()),
            static_cast<double>(t.grid->points()) * t.grid->growth(static_cast<std::size_t>(o_.window)));
    }
    if (!r.reached_unsafe) return;
    // An STL violation counts once the witness validator confirms it (rrt_extension.hpp); a
    // refused node stays a leaf and the tree grows on. (Not counted in a metric: a tree may run
    // rounds ahead of the barrier that the report drops, so a count would depend on scheduling.)
    if (sys_.info().requirement && !confirmed_falsification(sys_, *t.prop, t.nodes, r.node, t.p, nullptr)) return;
    t.leaf = r.node;
  }

  // A terminated tree never wins: free its search structures, keep its counters and series.
  static void release(ForestTree& t) {
    t.grid.reset();
    t.nn.reset();
    t.prop.reset();
    t.nodes.clear();
  }

  // Rounds a tree may run ahead of the next barrier (batch = 1): enough to keep every core busy
  // while one tree's round is slow, few enough that little work is done past the round where
  // the search ends (it is thrown away).
  static constexpr std::int64_t kRunAhead = 4;

  const RrftOptions& o_;
  const PlannerContext& ctx_;
  const System& sys_;
  const SystemInfo& info_;
  const WeightedEuclidean metric_;
  const SearchBudget budget_;
  const double time_cap_;  // simulated time the budget allows (infinite: no budget)
  const bool searched_;
  HaltonSequence halton_;
  const std::size_t max_active_, max_seeds_;
  double mu_;         // µ(P̄)
  const double n_g_;  // grid points of the coverage grid
  PlannerOutcome out_;
  std::vector<std::vector<double>> seeds_;  // P̄
  std::vector<std::unique_ptr<ForestTree>> trees_;
  std::vector<ForestTree*> active_;  // in seed order
  std::deque<ForestTree*> parked_;   // stalled trees waiting for a free slot, the longest waiting first
  NamedSeries dispersion_series_{"dispersion", {}};
  PlannerCounters total_;    // over the forest, as of the last barrier
  std::int64_t rounds_ = 0;  // barriers passed (a tree planted at barrier b grows from round b + 1)
  std::int64_t ahead_ = 0;   // run-ahead: rounds past (barrier + 1) a tree may start
  ForestTree* winner_ = nullptr;
  std::int64_t terminated_[4] = {0, 0, 0, 0};
  std::int64_t restarts_ = 0;
  bool done_ = false;
  std::mutex mutex_;  // run-ahead: the tasks' hand-offs (visible to ThreadSanitizer)
};

class Rrft final : public Planner {
 public:
  explicit Rrft(RrftOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_rrft_system(ctx.system, Json::object());
    return ForestSearch(o_, ctx).run();
  }

 private:
  RrftOptions o_;
};
}  // namespace

MethodEntry rrft_method() {
  return {"rrft",
          "RRFT of seed 003 (Alg. 3): a forest of RRTs, one per Halton seed p in P, grown in parallel; "
          "a tree ends on growth/coverage and is replaced by a new seed while the seeds' dispersion is above mu_min, "
          "else by a restart at a seed whose trees all stopped growing (not_found only when every seed is covered)",
          {{"n_t", 4, "initial trees = maximum active trees (1 when P is 0-dimensional)", "[1, 1024]"},
           {"K", 10,
            "extension attempts per active tree per round at batch = 1 (K = 1: the interleaving of Alg. 3; batch B > "
            "1: B slots per tree per round)",
            "[1, 100000]"},
           {"g_min", 0.01, "ḡ: a tree is not growing when n_g·g(T) <= g_min (coverage gained per node, in grid points)",
            "[0, 1e9]"},
           {"c_min", 0.05, "c̄: a tree is fully grown when D(T) (seed 003 eq. 3, falls to 0) <= c_min", "[0, 1]"},
           {"mu_min", 0.1, "µ̄: plant new seeds while µ(P̄) (eq. 2, normalized by P's diameter) > mu_min", "[0, 1]"},
           {"window", 200, "nodes of the finite difference g(T); also failed attempts before a tree is stalled",
            "[1, 10000000]"},
           {"max_seeds", 64, "at most this many seeds (trees) per trial", "[1, 4096]"},
           {"shift", false, "shift the Halton sequence by a per-trial random vector (Cranley-Patterson)"},
           {"series_every", 50, "tree nodes between points of the coverage/growth series", "[1, 100000000]"},
           batch_option(),
           {"budget", 0,
            "STL requirements: simulation-equivalents per run (simulated time / the requirement's horizon), checked "
            "at each round's barrier, then the run stops as budget; 0 = no cap (ARCH-COMP: 1500)",
            "[0, 100000000]", 0}},
          [](const Json& o) { return std::make_unique<Rrft>(parse_options(o)); },
          check_rrft_system,
          false,
          /*searches_parameters=*/true};
}

}  // namespace hyfal
