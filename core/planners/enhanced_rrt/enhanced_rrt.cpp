// Enhanced RRT, seed 000 Alg. 3-4, with each enhancement a separate option so that variants can
// be compared (Tables I-III):
//   selection = metric | t2go    x_near and u_new by rho, or by the time-to-go (III.2); t2go
//                                picks x_near among the k nearest by rho (the paper's
//                                suggestion), falling back to rho when none is finite.
//   history   = none | tree | knn  history weighting H (III.3) normalized over the whole tree
//                                (the paper's definition, O(N) per iteration) or over the k
//                                nearest; a failed extension (u_new already applied from
//                                x_near, so x_new is already in T) increments n_j and tries the
//                                next best input (Alg. 4).
//   sampling  = uniform | medium | heavy | adaptive   B(x; µ, β) (III.6) around the suite's
//                                goal point with σ(β) (III.7): fixed β = 0.5 (medium), fixed
//                                β = 1 (heavy, σ = σ_min), or β = n_s / n_β updated every N_s
//                                iterations (III.5), starting at β = 1 (Alg. 3); the counts run
//                                over the whole search (beta_counts=run) or restart every N_s
//                                (window): core/search/samplers/biased_sampler.hpp says why run.
// With adaptive sampling, an x_near that fails to grow toward a sample inside S is excluded
// from selection for later samples inside S (Sect. III-C). The secondary stop of Alg. 3 ends
// the search (not_found) when the coverage gained over the last `coverage_window` nodes is
// below `delta_c_min`. With several initial states (SystemInfo::other_initial_states) one tree
// grows from each, in turn (the forest of seed 000 Fig. 12); nodes are counted over the forest.
// With every option at its default this is exactly the baseline RRT (tested).
//
// The expansion step is split in two phases so that it can run in batches (issue 12,
// core/search/parallel_slots.hpp): propose() (lines 1-4 of Alg. 4: x_rand, x_near, every input of Ū
// propagated and scored) only reads the forest; commit() (lines 5-9: the first input not yet
// applied from x_near, n_j, x_new, exclusions, β's record) writes it. The no-progress filter and
// the unsafe test are RrtExtension's (core/planners/rrt/rrt_extension.hpp), shared with rrt.
//
// Batches (`batch` = B > 1). One round = B slots. Slot s of round r is Alg. 3's iteration
// i = (iterations committed before the round) + s: it grows tree i mod (number of trees) (the
// forest's rotation, as at B = 1), draws x_rand from its own stream slot_seed(seed, r, s) with
// the β of the round's start, and selects x_near against the round's start: the k nearest, t2go,
// H's n_j, the exclusions and the tree are all frozen while the slots propagate in parallel (one
// propagator, time-to-go and input grid per slot). Then the slots are committed in slot order,
// each exactly as one sequential iteration: the applied-input bits are the live ones (a slot
// that picked an x_near an earlier slot of its round extended skips the input that slot applied,
// counting n_j++), then n_j, exclusions, the new node, coverage, and AdaptiveBias::record. So
// history and exclusions written by a round are seen by the next round's selections, and β can
// only change between rounds as far as sampling is concerned (β is recomputed every N_s
// records, possibly mid-commit, but the round's samples were already drawn with the old one).
// The first slot in slot order whose node reaches s <= 0 ends the search; the node cap and the
// coverage stop are checked before every commit, so the cap is exact. Every propagation the
// round made is counted. B = 1 is the sequential algorithm with the trial's one stream (pinned).
#include "core/planners/enhanced_rrt/enhanced_rrt.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <unordered_set>

#include <fmt/format.h>

#include "core/planners/rrt/rrt_extension.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/coverage_grid.hpp"
#include "core/search/input_grid.hpp"
#include "core/search/metrics/history_weight.hpp"
#include "core/search/metrics/time_to_go.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/search/samplers/biased_sampler.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

namespace {

enum class Selection { metric, t2go };
enum class History { none, tree, knn };
enum class Sampling { uniform, medium, heavy, adaptive };

// Defaults and ranges are declared once, in enhanced_rrt_method(); parse_options fills every field.
struct EnhancedOptions {
  Selection selection;
  History history;
  Sampling sampling;
  int k;
  double sigma_min, sigma_max;
  int n_s;
  AdaptiveBias::Counts beta_counts;
  int coverage_window;
  double delta_c_min;
  std::int64_t coverage_at;
  int series_every;
  bool record_failed_extensions;
  bool t2go_inputs;
};

template <class E>
E parse_choice(const Json& o, const char* key, std::initializer_list<std::pair<const char*, E>> choices) {
  const std::string v = o.at(key).get<std::string>();
  for (const auto& [name, e] : choices)
    if (v == name) return e;
  std::string names;
  for (const auto& [name, e] : choices) names += (names.empty() ? "" : ", ") + std::string(name);
  throw std::invalid_argument(fmt::format("enhanced-rrt: {}={} is not one of {}", key, v, names));
}

EnhancedOptions parse_options(const Json& o) {
  EnhancedOptions e{};
  e.selection = parse_choice<Selection>(o, "selection", {{"metric", Selection::metric}, {"t2go", Selection::t2go}});
  e.history =
      parse_choice<History>(o, "history", {{"none", History::none}, {"tree", History::tree}, {"knn", History::knn}});
  e.sampling = parse_choice<Sampling>(o, "sampling",
                                      {{"uniform", Sampling::uniform},
                                       {"medium", Sampling::medium},
                                       {"heavy", Sampling::heavy},
                                       {"adaptive", Sampling::adaptive}});
  e.k = o.at("k").get<int>();
  e.sigma_min = o.at("sigma_min").get<double>();
  e.sigma_max = o.at("sigma_max").get<double>();
  e.n_s = o.at("n_s").get<int>();
  e.beta_counts = parse_choice<AdaptiveBias::Counts>(
      o, "beta_counts", {{"run", AdaptiveBias::Counts::run}, {"window", AdaptiveBias::Counts::window}});
  e.coverage_window = o.at("coverage_window").get<int>();
  e.delta_c_min = o.at("delta_c_min").get<double>();
  e.coverage_at = o.at("coverage_at").get<std::int64_t>();
  e.series_every = o.at("series_every").get<int>();
  e.record_failed_extensions = o.at("record_failed_extensions").get<bool>();
  e.t2go_inputs = o.at("t2go_inputs").get<bool>();
  // Single values are checked against their declared ranges (enhanced_rrt_method()); relations here.
  if (!(e.sigma_max >= e.sigma_min)) throw std::invalid_argument("enhanced-rrt: need sigma_min <= sigma_max");
  return e;
}

// The biased samplers (III.6) draw around the suite's goal point µ.
void check_enhanced_system(const System& sys, const EnhancedOptions& o) {
  const SystemInfo& info = sys.info();
  if (o.sampling != Sampling::uniform && info.goal_point.size() != info.dim())
    throw std::invalid_argument(
        fmt::format("sampling={} needs the suite's goal point, which suite '{}' does not declare",
                    o.sampling == Sampling::adaptive ? "adaptive" : "biased", info.suite));
}

// One tree of the forest, with the per-node bookkeeping the enhancements need.
struct Tree {
  Tree(std::size_t n, std::size_t m, const WeightedEuclidean& metric) : nodes(n, m), nn(metric) {}
  NodeStore nodes;
  NearestNeighbors nn;
  std::vector<std::uint64_t> applied;              // Ū indices applied from each node (|Ū| <= 64)
  std::unordered_set<std::uint64_t> applied_wide;  // (node, index) pairs when |Ū| > 64
  std::vector<char> excluded;                      // excluded from selection for samples in S
  std::vector<double> projected;                   // sqrt(w) x of every node, for history = tree
};

// One expansion slot: its scratch (propagator, time-to-go and input grid, which all keep mutable
// buffers, so each slot owns its own) and its proposal, filled by propose() against the frozen
// forest and consumed by commit().
struct Slot {
  Slot(const System& sys, const WeightedEuclidean& metric, std::span<const double> p, int k)
      : prop(sys.make_propagator()),
        t2go(sys, metric, p),
        U(sys),
        x_rand(sys.info().dim()),
        neighbors(static_cast<std::size_t>(k)) {
    const Box& box = sys.info().sampling_box;
    for (std::size_t i = 0; i < box.dim(); ++i) uniform.emplace_back(box.lo[i], box.hi[i]);
    if (sys.info().requirement) stl.emplace(sys);
  }
  std::unique_ptr<Propagator> prop;
  TimeToGo t2go;
  InputGrid U;  // Ū at x_near (admissible inputs of a driver model)
  std::vector<std::uniform_real_distribution<double>> uniform;
  std::vector<double> x_rand;
  // select_near's buffers.
  std::vector<Neighbor> neighbors;
  std::vector<double> cand_dist, t2go_buf, query;
  std::vector<std::uint32_t> cand_fail;
  std::vector<NodeId> cand_id;
  // Per-input outcomes of the extension, and the inputs by increasing score.
  std::vector<double> states, score;
  std::vector<PropagationResult> results;
  std::vector<std::size_t> order;
  PlannerCounters counters;  // this slot's propagations and integration steps
  // STL requirements: the monitor, and each input's samples until commit chooses one.
  std::optional<stl::EdgeMonitor> stl;
  std::vector<std::vector<double>> rows;
  // The proposal.
  std::size_t tree = 0;
  bool in_spec = false;
  NodeId near = kNoNode;
  Mode q = 0;
};

// One enhanced-RRT trial (Alg. 3): rounds of select (propose) and extend (commit), β updated by
// the commits, the coverage stop checked before every commit. EnhancedRrt::solve runs one.
class EnhancedSearch {
 public:
  EnhancedSearch(const EnhancedOptions& o, std::size_t batch, const PlannerContext& ctx)
      : o_(o),
        batch_(batch),
        ctx_(ctx),
        sys_(ctx.system),
        info_(sys_.info()),
        p_(ctx.parameters),
        metric_(info_.metric_weights),
        budget_(ctx),
        rng_(ctx.seed),
        biased_sampler_((check_enhanced_system(sys_, o), info_.sampling_box), info_.goal_point, o.sigma_min,
                        o.sigma_max),
        adaptive_(o.n_s, o.beta_counts) {
    for (std::size_t s = 0; s < batch_; ++s) {
      slots_.push_back(std::make_unique<Slot>(sys_, metric_, p_, o_.k));
      slots_.back()->prop->set_interrupt(budget_.interrupt());  // a propagation past the deadline ends as rejected
    }
    if (info_.coverage.spacing > 0.0) coverage_.emplace(info_.coverage, info_.dim());
  }

  PlannerOutcome run() {
    plant_forest();
    for (std::uint64_t round = 0; !out_.trajectory && !stopped_; ++round) {
      if (auto why = round_start_stop()) {
        out_.status = *why;
        break;
      }
      select_round(round, round_beta());
      extend_round();
    }
    return report();
  }

 private:
  // The forest: one tree per initial state, its root checked against the specification.
  void plant_forest() {
    std::vector<std::vector<double>> starts{info_.initial_state};
    for (const auto& x0 : info_.other_initial_states) starts.push_back(x0);
    for (const auto& x0 : starts) {
      forest_.emplace_back(info_.dim(), info_.input_names.size(), metric_);
      add_node(forest_.back(), kNoNode, info_.initial_mode, info_.initial_mode, x0, {}, 0.0, -1);
    }
    for (auto& t : forest_)
      if (!out_.trajectory && starts_unsafe(sys_, info_.initial_mode, t.nodes.state(0), p_)) finish_falsified(t, 0);
  }

  // `monitor`: the node's STL monitor state; `indexed` false: a settled node (STL), kept out of
  // the nearest-neighbour index since no extension of it can falsify.
  NodeId add_node(Tree& t, NodeId parent, Mode edge_mode, Mode mode, std::span<const double> x,
                  std::span<const double> u, double duration, int transition, std::span<const double> monitor = {},
                  bool indexed = true) {
    const std::size_t n = info_.dim();
    const NodeId id = t.nodes.add(parent, edge_mode, mode, x, u, duration, transition, monitor);
    if (indexed) t.nn.add(id, x);
    t.applied.push_back(0);
    t.excluded.push_back(0);
    if (o_.history == History::tree) {
      const auto& w = metric_.weights();
      for (std::size_t i = 0; i < n; ++i) t.projected.push_back(std::sqrt(w[i]) * x[i]);
    }
    PlannerCounters& c = out_.counters;
    ++c.nodes;
    if (coverage_) {
      coverage_->add(x);
      if (c.nodes % o_.series_every == 0) coverage_series_.points.emplace_back(c.nodes, coverage_->coverage());
      if (c.nodes == o_.coverage_at) out_.metrics["coverage"] = coverage_->coverage();
    }
    return id;
  }

  void finish_falsified(Tree& t, NodeId leaf) {
    out_.status = TrialStatus::falsified;
    out_.trajectory = trajectory_from_tree(sys_, *slots_.front()->prop, t.nodes, leaf, p_);  // slot 0's propagator
  }

  // A node that violates the STL requirement ends the search once the witness validator confirms
  // it (confirmed_falsification, rrt_extension.hpp); a refused one stays a leaf (commit_monitored
  // left it out of the index) and the search goes on. Reachability: the node with s <= 0 ends it.
  void falsified_at(Tree& t, NodeId leaf) {
    if (!info_.requirement) return finish_falsified(t, leaf);
    double rho = 0.0;
    std::optional<Trajectory> confirmed = confirmed_falsification(sys_, *slots_.front()->prop, t.nodes, leaf, p_, &rho);
    if (!confirmed) {
      ++refused_;
      lowest_upper_ = std::min(lowest_upper_, rho);
      return;
    }
    lowest_upper_ = std::min(lowest_upper_, stl::EdgeMonitor::bounds_of(t.nodes, leaf).upper);
    out_.status = TrialStatus::falsified;
    out_.trajectory = std::move(confirmed);
  }

  // Alg. 3's secondary stop: Δc over the trailing N nodes below Δc_min.
  bool coverage_stalled() const {
    return coverage_ && o_.coverage_window > 0 && coverage_->nodes() > static_cast<std::size_t>(o_.coverage_window) &&
           coverage_->growth(o_.coverage_window) * o_.coverage_window < o_.delta_c_min;
  }

  // The checks of a round's start: the budget, then the coverage stop.
  std::optional<TrialStatus> round_start_stop() const {
    if (auto why = budget_.exhausted(out_.counters.nodes)) return why;
    if (coverage_stalled()) return TrialStatus::not_found;
    return std::nullopt;
  }

  // The checks before every later commit of a round: the node cap (exact), the coverage stop.
  std::optional<TrialStatus> commit_stop() const {
    if (out_.counters.nodes >= ctx_.limits.max_nodes) return TrialStatus::node_cap;
    if (coverage_stalled()) return TrialStatus::not_found;
    return std::nullopt;
  }

  // β as of the round's start: the slots of a round sample with it.
  double round_beta() const {
    return o_.sampling == Sampling::adaptive ? adaptive_.beta() : o_.sampling == Sampling::heavy ? 1.0 : 0.5;
  }

  // Line 1-2 of Alg. 4: x_rand ~ B(x; µ, β) (or uniform) from `g`; in_spec: x_rand in S.
  void sample(Rng& g, double beta, Slot& slot) const {
    if (o_.sampling != Sampling::uniform)
      biased_sampler_.sample(g, beta, slot.x_rand);
    else
      for (std::size_t i = 0; i < info_.dim(); ++i) slot.x_rand[i] = slot.uniform[i](g);
    slot.in_spec = o_.sampling == Sampling::adaptive && sys_.spec(info_.initial_mode, slot.x_rand, p_) <= 0.0;
  }

  // Select: every slot of the round samples x_rand and proposes an extension against the forest
  // of the round's start (batch = 1: the trial's one stream; else the slot's own), slot s
  // growing tree (iteration + s) mod (number of trees), the forest's rotation. Every
  // propagation the round made is counted.
  void select_round(std::uint64_t round, double beta) {
    const auto trees = static_cast<std::int64_t>(forest_.size());
    if (batch_ == 1) {
      Slot& slot = *slots_.front();
      slot.counters = {};
      slot.tree = static_cast<std::size_t>(iteration_ % trees);
      sample(rng_, beta, slot);
      propose(forest_[slot.tree], rng_, slot);
    } else {
      parallel_slots(batch_, ctx_.cpu, [&](std::size_t s) {
        Slot& slot = *slots_[s];
        slot.counters = {};
        slot.tree = static_cast<std::size_t>((iteration_ + static_cast<std::int64_t>(s)) % trees);
        Rng g(slot_seed(ctx_.seed, round, s));
        sample(g, beta, slot);
        propose(forest_[slot.tree], g, slot);
      });
    }
    for (const auto& slot : slots_) {
      out_.counters.add_work(slot->counters);
    }
  }

  // Extend: the round's slots committed in slot order, each one Alg. 3 iteration; the first
  // node with s <= 0 ends the search, and so does a stop rule before a later commit.
  void extend_round() {
    for (std::size_t s = 0; s < batch_ && !out_.trajectory; ++s) {
      if (s > 0)
        if (auto why = commit_stop()) {
          out_.status = *why;
          stopped_ = true;
          return;
        }
      ++iteration_;
      Slot& slot = *slots_[s];
      Tree& t = forest_[slot.tree];
      const NodeId leaf = commit(t, slot);
      if (leaf != kNoNode) falsified_at(t, leaf);
    }
  }

  // Per-trial results.
  PlannerOutcome report() {
    PlannerCounters& c = out_.counters;
    if (coverage_) {
      out_.metrics["coverage_final"] = coverage_->coverage();
      coverage_series_.points.emplace_back(c.nodes, coverage_->coverage());
      out_.series.push_back(std::move(coverage_series_));
    }
    if (o_.sampling == Sampling::adaptive) {
      out_.metrics["beta_final"] = adaptive_.beta();
      out_.series.push_back(std::move(beta_series_));
    }
    std::uint32_t max_fail = 0;
    std::int64_t excluded = 0;
    std::vector<double> fails;
    for (const auto& t : forest_)
      for (NodeId i = 0; i < t.nodes.size(); ++i) {
        max_fail = std::max(max_fail, t.nodes.failed_extensions(i));
        excluded += t.excluded[i];
        if (o_.record_failed_extensions) fails.push_back(t.nodes.failed_extensions(i));
      }
    out_.metrics["failed_extensions_max"] = max_fail;
    if (o_.sampling == Sampling::adaptive) out_.metrics["excluded_nodes"] = excluded;
    out_.metrics["trees"] = forest_.size();
    if (info_.requirement) out_.metrics["robustness"] = lowest_upper_;
    if (refused_ > 0) out_.metrics["refused_candidates"] = refused_;
    if (o_.record_failed_extensions) {  // seed 000 Fig. 6: n_j sorted in descending order
      std::sort(fails.begin(), fails.end(), std::greater<>());
      NamedSeries s{"failed_extensions_sorted", {}};
      for (std::size_t i = 0; i < fails.size(); ++i) s.points.emplace_back(static_cast<double>(i), fails[i]);
      out_.series.push_back(std::move(s));
    }
    if (ctx_.trees)  // --save-trees: after the search, a copy of each tree
      for (std::size_t i = 0; i < forest_.size(); ++i) ctx_.trees->add(i, forest_[i].nodes);
    return std::move(out_);
  }
  // Lines 3-4 of Alg. 4 for one slot, reading the tree only (it runs concurrently with the other
  // slots of its round): x_near, then every input of Ū propagated and scored by rho or t2go
  // toward x_rand, the inputs sorted by score (the order lines 5-9 try them in).
  void propose(const Tree& t, Rng& g, Slot& slot) const {
    const System& sys = sys_;
    const WeightedEuclidean& metric = metric_;
    const std::span<const double> p = p_;
    const std::size_t n = metric.dim();
    slot.near = select_near(t, metric, slot);
    if (slot.near == kNoNode) return;
    const Mode q = t.nodes.info(slot.near).mode;
    slot.q = q;
    const auto x_near = t.nodes.state(slot.near);
    slot.U.draw(q, x_near, g);  // Ū, or fresh random inputs under the suite's policy
    const std::size_t nu = slot.U.count();
    slot.states.resize(nu * n);
    slot.score.assign(nu, std::numeric_limits<double>::infinity());
    slot.results.resize(nu);
    if (slot.stl && slot.rows.size() < nu) slot.rows.resize(nu);
    const bool by_t2go = o_.selection == Selection::t2go && o_.t2go_inputs;
    bool any_finite_t2go = false;
    for (std::size_t j = 0; j < nu; ++j) {
      std::span<double> xs(slot.states.data() + j * n, n);
      const double dt = sys.info().step_duration;
      if (slot.stl) {
        slot.results[j] = slot.stl->propagate(t.nodes, slot.near, q, x_near, slot.U.input(j), p, dt, *slot.prop, xs);
        slot.stl->set_aside(slot.rows[j]);
      } else {
        slot.results[j] = slot.prop->propagate(q, x_near, slot.U.input(j), p, dt, xs);
      }
      RrtExtension::count(slot.results[j], slot.counters);
      if (!RrtExtension::makes_progress(slot.results[j])) continue;  // the no-progress filter
      if (by_t2go) {
        slot.score[j] = slot.t2go(slot.results[j].mode, xs, slot.x_rand);
        any_finite_t2go = any_finite_t2go || std::isfinite(slot.score[j]);
      } else {
        slot.score[j] = metric.distance(slot.x_rand, xs);
      }
    }
    if (by_t2go && !any_finite_t2go)  // fall back to rho
      for (std::size_t j = 0; j < nu; ++j)
        if (RrtExtension::makes_progress(slot.results[j]))
          slot.score[j] = metric.distance(slot.x_rand, std::span<const double>(slot.states.data() + j * n, n));
    slot.order.resize(nu);
    std::iota(slot.order.begin(), slot.order.end(), 0);
    std::stable_sort(slot.order.begin(), slot.order.end(),
                     [&](std::size_t a, std::size_t b) { return slot.score[a] < slot.score[b]; });
  }

  // Lines 3-9 of Alg. 4 committed for one slot (in slot order): x_near's selection; the best
  // input not applied from x_near yet (each already-applied one is a failed extension, n_j++,
  // and leaves Ū: the applied bits are the live ones, so two slots of a round that chose the
  // same x_near do not add the same x_new twice); x_new added; exclusions; the β record.
  // Returns the new node when it reached the unsafe set, else kNoNode.
  NodeId commit(Tree& t, Slot& slot) {
    const WeightedEuclidean& metric = metric_;
    const std::size_t n = metric.dim();
    const NodeId near = slot.near;
    if (near == kNoNode) {
      if (o_.sampling == Sampling::adaptive) record_beta(slot.in_spec, false);
      return kNoNode;
    }
    t.nodes.count_selection(near);
    const std::size_t nu = slot.U.count();
    std::size_t chosen = nu;
    for (std::size_t j : slot.order) {
      if (!std::isfinite(slot.score[j])) break;
      if (o_.history != History::none && was_applied(t, near, j, nu)) {
        t.nodes.count_failure(near);
        continue;
      }
      chosen = j;
      break;
    }
    if (chosen == nu) {
      if (o_.history == History::none) t.nodes.count_failure(near);  // no input made progress
      if (slot.in_spec) t.excluded[near] = 1;
      if (o_.sampling == Sampling::adaptive) record_beta(slot.in_spec, false);
      return kNoNode;
    }
    // Without history weighting the tree still adds x_new (Alg. 2), but a repeated input is
    // counted as a failed extension all the same, so Fig. 6 can compare n_j with and without.
    if (o_.history == History::none && was_applied(t, near, chosen, nu)) t.nodes.count_failure(near);
    mark_applied(t, near, chosen, nu);
    const std::span<const double> x_new(slot.states.data() + chosen * n, n);
    const PropagationResult& r = slot.results[chosen];
    const double rho_before = metric.distance(t.nodes.state(near), slot.x_rand);
    if (slot.stl) return commit_monitored(t, slot, near, chosen, x_new, rho_before);
    const NodeId id = add_node(t, near, slot.q, r.mode, x_new, slot.U.input(chosen), r.duration, r.transition);
    const bool successful = metric.distance(x_new, slot.x_rand) < rho_before;
    if (o_.sampling == Sampling::adaptive) {
      if (slot.in_spec && !successful) t.excluded[near] = 1;
      record_beta(slot.in_spec, successful);
    }
    return RrtExtension::reached_unsafe(r) ? id : kNoNode;
  }

  // The end of commit() under an STL requirement: the chosen input's samples extend x_near's
  // monitor state; the node falsifies when its robustness is bounded above by a negative number.
  NodeId commit_monitored(Tree& t, Slot& slot, NodeId near, std::size_t chosen, std::span<const double> x_new,
                          double rho_before) {
    const PropagationResult& r = slot.results[chosen];
    const stl::PrefixBounds& b = slot.stl->finish_with(t.nodes, near, slot.rows[chosen]);
    if (!stl::EdgeMonitor::violated(b))
      lowest_upper_ = std::min(lowest_upper_, b.upper);  // a violation: once confirmed
    const NodeId id = add_node(t, near, slot.q, r.mode, x_new, slot.U.input(chosen), r.duration, r.transition,
                               slot.stl->state(), !stl::EdgeMonitor::settled(b) && !stl::EdgeMonitor::violated(b));
    const bool successful = metric_.distance(x_new, slot.x_rand) < rho_before;
    if (o_.sampling == Sampling::adaptive) {
      if (slot.in_spec && !successful) t.excluded[near] = 1;
      record_beta(slot.in_spec, successful);
    }
    return stl::EdgeMonitor::violated(b) ? id : kNoNode;
  }

  // Update β: one record per commit under adaptive sampling (III.5); β changes every N_s records.
  void record_beta(bool in_spec, bool successful) {
    if (adaptive_.record(in_spec, successful))
      beta_series_.points.emplace_back(static_cast<double>(iteration_), adaptive_.beta());
  }

  static bool was_applied(const Tree& t, NodeId node, std::size_t j, std::size_t nu) {
    if (nu <= 64) return (t.applied[node] >> j) & 1u;
    return t.applied_wide.count(static_cast<std::uint64_t>(node) * nu + j) != 0;
  }
  static void mark_applied(Tree& t, NodeId node, std::size_t j, std::size_t nu) {
    if (nu <= 64)
      t.applied[node] |= std::uint64_t{1} << j;
    else
      t.applied_wide.insert(static_cast<std::uint64_t>(node) * nu + j);
  }

  // Line 3 of Alg. 4: x_near = argmin over the candidates of rho, t2go, or H(., x_rand; rho|t2go).
  // Reads the tree only (n_j, exclusions as of the round's start), with the slot's buffers.
  NodeId select_near(const Tree& t, const WeightedEuclidean& metric, Slot& slot) const {
    const std::span<const double> x_rand = slot.x_rand;
    std::vector<double>& dist = slot.cand_dist;
    std::vector<std::uint32_t>& fail = slot.cand_fail;
    std::vector<NodeId>& ids = slot.cand_id;
    std::vector<Neighbor>& neighbors = slot.neighbors;
    const bool skip_excluded = slot.in_spec;
    auto distance_of = [&](NodeId id, double rho) {
      return o_.selection == Selection::t2go ? slot.t2go(t.nodes.info(id).mode, t.nodes.state(id), x_rand) : rho;
    };
    if (o_.history == History::tree) {  // (III.3) normalized over the whole tree
      const std::size_t N = t.nodes.size(), n = metric.dim();
      dist.clear();
      fail.clear();
      ids.clear();
      const auto& w = metric.weights();
      std::vector<double>& z = slot.query;
      z.resize(n);
      for (std::size_t i = 0; i < n; ++i) z[i] = std::sqrt(w[i]) * x_rand[i];
      for (std::size_t id = 0; id < N; ++id) {
        if (skip_excluded && t.excluded[id]) continue;
        const double* a = t.projected.data() + id * n;
        double s = 0.0;
        for (std::size_t i = 0; i < n; ++i) s += (a[i] - z[i]) * (a[i] - z[i]);
        ids.push_back(static_cast<NodeId>(id));
        dist.push_back(std::sqrt(s));
        fail.push_back(t.nodes.failed_extensions(static_cast<NodeId>(id)));
      }
      if (o_.selection == Selection::t2go) {
        bool any = false;
        slot.t2go_buf.resize(ids.size());
        for (std::size_t i = 0; i < ids.size(); ++i) {
          slot.t2go_buf[i] = slot.t2go(t.nodes.info(ids[i]).mode, t.nodes.state(ids[i]), x_rand);
          any = any || std::isfinite(slot.t2go_buf[i]);
        }
        if (any)
          std::copy(slot.t2go_buf.begin(), slot.t2go_buf.end(), dist.begin());  // else rho decides (III.2 remark)
      }
      const std::size_t best = argmin_history_weight(dist, fail);
      return best == kNoCandidate ? kNoNode : ids[best];
    }
    // Candidates: the nearest by rho (k of them when t2go or history need a set), skipping
    // excluded nodes for samples in S.
    const bool need_set = o_.selection == Selection::t2go || o_.history == History::knn;
    const std::size_t want = need_set ? static_cast<std::size_t>(o_.k) : 1;
    std::size_t ask = want;
    ids.clear();
    dist.clear();
    while (true) {
      neighbors.resize(std::max(ask, neighbors.size()));
      const std::size_t found = t.nn.knn(x_rand, std::span<Neighbor>(neighbors.data(), ask));
      ids.clear();
      dist.clear();
      for (std::size_t i = 0; i < found && ids.size() < want; ++i) {
        if (skip_excluded && t.excluded[neighbors[i].id]) continue;
        ids.push_back(neighbors[i].id);
        dist.push_back(neighbors[i].distance);
      }
      if (ids.size() == want || found < ask) break;
      ask *= 4;  // too many excluded among the nearest: look further
    }
    if (ids.empty()) return kNoNode;
    if (o_.selection == Selection::t2go) {  // dist holds rho; t2go replaces it when any is finite
      bool any = false;
      slot.t2go_buf.resize(ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i) {
        slot.t2go_buf[i] = distance_of(ids[i], dist[i]);
        any = any || std::isfinite(slot.t2go_buf[i]);
      }
      if (any) std::copy(slot.t2go_buf.begin(), slot.t2go_buf.end(), dist.begin());
    }
    if (o_.history == History::knn) {
      fail.resize(ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i) fail[i] = t.nodes.failed_extensions(ids[i]);
      return ids[argmin_history_weight(dist, fail)];
    }
    return ids[static_cast<std::size_t>(std::min_element(dist.begin(), dist.end()) - dist.begin())];
  }

  const EnhancedOptions& o_;
  const std::size_t batch_;
  const PlannerContext& ctx_;
  const System& sys_;
  const SystemInfo& info_;
  const std::span<const double> p_;
  const WeightedEuclidean metric_;
  const SearchBudget budget_;
  Rng rng_;  // batch = 1: the trial's one stream
  const BiasedSampler biased_sampler_;
  AdaptiveBias adaptive_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::optional<CoverageGrid> coverage_;
  NamedSeries coverage_series_{"coverage", {}}, beta_series_{"beta", {}};
  std::deque<Tree> forest_;  // trees never move (their NN index points into their own storage)
  PlannerOutcome out_;
  std::int64_t refused_ = 0;                                       // STL: violating nodes the witness validator refused
  double lowest_upper_ = std::numeric_limits<double>::infinity();  // STL: the lowest upper bound of any node
  std::int64_t iteration_ = 0;                                     // Alg. 3's iteration count (one per slot committed)
  bool stopped_ = false;                                           // a stop rule ended the search between two commits
};

class EnhancedRrt final : public Planner {
 public:
  EnhancedRrt(EnhancedOptions o, std::size_t batch) : o_(o), batch_(batch < 1 ? 1 : batch) {}

  PlannerOutcome solve(const PlannerContext& ctx) override { return EnhancedSearch(o_, batch_, ctx).run(); }

 private:
  EnhancedOptions o_;
  std::size_t batch_;
};

}  // namespace

MethodEntry enhanced_rrt_method() {
  return {
      "enhanced-rrt",
      "enhanced RRT of seed 000 (Alg. 3-4): t2go selection, history weighting, adaptive bias, "
      "coverage stop; every option off = baseline RRT",
      {{"selection", "metric", "x_near and u_new by the metric (metric) or time-to-go (t2go, III.2)", "metric|t2go"},
       {"k", 10, "candidates (nearest by the metric) for t2go and history=knn", "[1, 1000]"},
       {"history", "none", "history weighting H (III.3): none, tree (whole tree) or knn (k nearest)", "none|tree|knn"},
       {"sampling", "uniform", "x_rand: uniform, medium (β=0.5), heavy (β=1) or adaptive (III.5-7)",
        "uniform|medium|heavy|adaptive"},
       {"sigma_min", 0.05, "σ_min of (III.7), as a fraction of the sampling-box width", "(0, 10]"},
       {"sigma_max", 0.5, "σ_max of (III.7), as a fraction of the sampling-box width", "(0, 10]"},
       {"n_s", 50, "N_s: iterations between β updates (III.5)", "[1, 1000000]"},
       {"beta_counts", "run", "n_s, n_β of (III.5) over the whole search (run) or the last N_s iterations (window)",
        "run|window"},
       {"coverage_window", 0, "N of the secondary stop: stop when c gains < delta_c_min over N nodes (0: off)",
        "[0, 100000000]"},
       {"delta_c_min", 1e-4, "Δc_min of the secondary stop", "[0, 1]"},
       {"coverage_at", 5000, "node count at which the metric 'coverage' is recorded", "[1, inf)"},
       {"series_every", 100, "nodes between points of the coverage series", "[1, 100000000]"},
       {"t2go_inputs", true, "with selection=t2go, also pick u_new by t2go (Alg. 4); false: by the metric"},
       {"record_failed_extensions", false, "store the sorted n_j of the final tree (Fig. 6) as a series"},
       batch_option()},
      [](const Json& o) { return std::make_unique<EnhancedRrt>(parse_options(o), o.at("batch").get<std::size_t>()); },
      [](const System& sys, const Json& o) { check_enhanced_system(sys, parse_options(o)); }};
}

}  // namespace hyfal
