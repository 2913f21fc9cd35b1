// FalStar's probabilistically adaptive tree search ("adaptive"): Ernst, Sedwards, Zhang & Hasuo,
// "Fast falsification of hybrid systems using probabilistically adaptive input", QEST 2019, and
// its journal version (ACM TOMACS 2021); written from the paper and from what FalStar's public
// Adaptive.scala does (../shared/arch/anchors.md summarises both), so that hyfal can show it as a
// peer beside FalStar's own published numbers.
//
// The tree. A node is an input prefix ending at piece boundary t (the root: t = 0). An action is
// one input value held for one segment; level l's actions hold the values of
// adaptive::level_fractions(m, l) for horizon / cp_l (option `cp`, FalStar's "control points",
// default 2 2 3 3 3 4: level 0 the corners for half the horizon, ...). Every node offers every
// level. One pass descends from the root, at each node:
//  - choose_level: level l with weight 2^-l times the share of its actions still alive (untried,
//    or tried and kept);
//  - choose_move in that level: explore (weight `exploration`): an untried action at random;
//    uniform (weight `uniform`): a random kept child; prefix (`prefix`): the kept child with the
//    lowest prefix-robustness upper bound; suffix (`suffix`): the kept child whose subtree has the
//    lowest robustness of a whole simulation (ties: uniformly). Explore needs an untried action,
//    the three exploit moves a kept child; a fresh node therefore explores.
// until an action reaches the horizon (a leaf: tried, never kept). The signal is then simulated
// once (play_out) and the pass backs up (back_up): every node on the path takes the
// simulation's robustness into its subtree's best; each child created on this pass gets the
// robustness interval of the trace up to its time (the prefix monitor's bounds, robustness.hpp),
// and is kept if its lower bound is < 0, else pruned (no extension of it can falsify). The search
// stops at the first falsification the validator confirms, or after `budget` passes.
//
// Choices where the paper leaves a detail open, and why:
//  - Segments are FalStar's: level l's lasts horizon / cp_l, a node's time is the sum of the
//    segments above it, and an action whose segment reaches the horizon is a leaf (the
//    simulation ends at the horizon). The signal itself lies on the suite's δt grid: an input
//    change at node time t takes effect at the first multiple of δt at or after t. That is what
//    FalStar does with δt = 1 s: it resamples its input signal at 1 s before simulating
//    (WithStatistics.sim in Falsification.scala: `us sample (1, T)`), so its change at 7.5 s
//    reaches the model at 8 s; the arch-fals published profile runs this method at δt = 1 s for
//    that reason. Where δt divides every horizon / cp_l the segments are exact. The validator
//    accepts a held signal that changes only at multiples of δt (core/witness/trajectory.cpp).
//  - A node's prefix is judged as FalStar judges it: complete up to its time, so a window that
//    ends exactly there is decided (Robustness.bounds: an always or eventually is known once the
//    trace reaches its interval's end, `xs.T < to` being the open case). Our monitor's prefix
//    interval by default leaves it open, since a sample at that very time (the other side of a
//    jump) could still follow; here the interval is of extensions that add samples only later
//    (robustness_interval's closed_at_last_time). With the open interval, a child at 10 s was
//    never pruned by always[0,10] and ATc4/ATc5 took twice FalStar's simulations (measured).
//  - The budget counts passes, as FalStar's loop does; a pass that reaches a node none of whose
//    actions is alive ends without a simulation (FalStar's Result.empty). Simulations (the
//    counters, the league's count) are the passes that simulated. When the root itself has no
//    live action left, the search has tried everything it may: not_found.
//  - Inputs are piecewise constant, or, with `input_shape = linear` (ours, for
//    ARCH-COMP instance 1), linear between the segments' ends: an action's value is the signal's
//    at its segment's end (the first segment holds its value from 0), so that the signal up to a
//    node's time is fixed by the path to it and the prefix bound prunes as soundly as before.
//  - The robustness a child is ranked by (prefix move) is its prefix interval's upper bound, and a
//    subtree's (suffix move) the lowest whole-simulation robustness through it, both as FalStar
//    sets them; a refused candidate counts with the validator's robustness (signal_search.hpp).
//  - The system's parameters P (SystemInfo::parameter_box) are not searched: every simulation
//    runs at the instance's p (FalStar's `constant` inputs, fixed after their first choice, would
//    be their counterpart; not built). A system with no inputs is refused.
//  - Random draws: one mt19937_64 stream from the trial seed, in a fixed order: the same result
//    at any thread count.
//
// The tree-optimiser hybrid ("adaptive-local", ours; issue 40) is this search plus one step,
// polish(): where `local_after` passes in a row have not lowered the best robustness, a short
// Nelder-Mead (NLopt, at most `local_budget` simulations of the same budget) moves the best
// signal's values, continuous within the box, its segments fixed. The tree chooses the signal's
// shape (where the input changes, roughly to what); the local search reaches the bands between
// the dyadic values. Why this design and not the others tried (docs/measurements.md): a local
// search after every new best spent the budget early where the tree alone is quick (ATc1 13.2
// simulations against 7.5); one over the last segments only lost ATc5 (109 against 62); EMSOFT
// 2018's two layers (UCB over input cells, an optimiser in each playout) pay a whole local search
// for every playout, where this one pays only where the tree stalls. A local search that finds
// nothing doubles the wait before the next, so a row the tree falsifies alone loses little.
#include "core/planners/adaptive/adaptive.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <nlopt.hpp>

#include "core/model/signal_model.hpp"
#include "core/planners/signal_search.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/input_levels.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

namespace adaptive {

std::vector<double> level_fractions(std::size_t inputs, int level) { return dyadic_level_fractions(inputs, level); }

}  // namespace adaptive

namespace {

constexpr std::uint32_t kLeaf = std::numeric_limits<std::uint32_t>::max();

struct AdaptiveOptions {
  std::int64_t budget;
  double horizon;
  std::vector<int> cp;
  double explore, uniform, prefix, suffix;
  // adaptive-local: simulations per local search (0: FalStar's search alone) and its first step
  // as a fraction of each input's range.
  std::int64_t local_budget = 0;
  double local_step = 0.125;
  std::int64_t local_after = 20;   // passes without a new best before a local search
  std::size_t local_segments = 0;  // trailing segments the local search moves (0: all)
  InputShape shape = InputShape::constant;
};

// "2 2 3 3 3 4" -> {2, 2, 3, 3, 3, 4}; throws std::invalid_argument naming what is wrong.
std::vector<int> parse_cp(const std::string& text) {
  std::istringstream in(text);
  std::vector<int> cp;
  std::string word;
  while (in >> word) {
    std::size_t used = 0;
    int v = 0;
    try {
      v = std::stoi(word, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != word.size() || v < 1 || v > 1000)
      throw std::invalid_argument(
          fmt::format("adaptive: cp = '{}': '{}' is not a whole number of segments in [1, 1000]", text, word));
    cp.push_back(v);
  }
  if (cp.empty())
    throw std::invalid_argument("adaptive: cp is empty: give one segment count per level, e.g. cp=\"2 2 3 3 3 4\"");
  if (cp.size() > 12)
    throw std::invalid_argument(fmt::format("adaptive: cp = '{}' has {} levels; at most 12", text, cp.size()));
  return cp;
}

AdaptiveOptions read_options(const Json& o) {
  AdaptiveOptions a{
      o.at("budget").get<std::int64_t>(), o.at("horizon").get<double>(), parse_cp(o.at("cp").get<std::string>()),
      o.at("exploration").get<double>(),  o.at("uniform").get<double>(), o.at("prefix").get<double>(),
      o.at("suffix").get<double>()};
  a.shape = input_shape_of(o.at("input_shape").get<std::string>());
  if (!(a.uniform + a.prefix + a.suffix > 0.0))
    throw std::invalid_argument(
        "adaptive: uniform, prefix and suffix are all 0: a tried child could never be chosen again");
  if (o.contains("local_budget")) {
    a.local_budget = o.at("local_budget").get<std::int64_t>();
    a.local_step = o.at("local_step").get<double>();
    a.local_after = o.at("local_after").get<std::int64_t>();
    a.local_segments = o.at("local_segments").get<std::size_t>();
  }
  return a;
}

class AdaptiveSearch final : public Planner {
 public:
  explicit AdaptiveSearch(AdaptiveOptions o) : o_(std::move(o)) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_signal_system(ctx.system, o_.horizon, o_.shape, /*parameters=*/false);
    SignalSimulations sims(ctx, o_.budget, signal_horizon(ctx.system, o_.horizon), o_.shape);
    Pass pass(o_, sims, signal_horizon(ctx.system, o_.horizon), ctx.seed);
    TrialStatus status = TrialStatus::budget;
    try {
      status = pass.run();
    } catch (const SearchOver& over) {
      status = over.status;
    }
    PlannerOutcome out = sims.outcome(status);
    pass.add_metrics(out.metrics);
    return out;
  }

 private:
  // The search's tree and its passes.
  class Pass {
   public:
    Pass(const AdaptiveOptions& o, SignalSimulations& sims, double horizon, std::uint64_t seed)
        : o_(o), sims_(sims), rng_(seed), slot_(sims.slot(0)), horizon_(horizon) {
      const Box& box = sims.input_box();
      const std::size_t m = box.lo.size();
      for (std::size_t l = 0; l < o.cp.size(); ++l) {
        Level level;
        level.duration = horizon / o.cp[l];
        const std::vector<double> f = adaptive::level_fractions(m, static_cast<int>(l));
        for (std::size_t i = 0; i < f.size(); ++i)
          level.values.push_back(box.lo[i % m] + f[i] * (box.hi[i % m] - box.lo[i % m]));
        level.actions = f.size() / m;
        levels_.push_back(std::move(level));
      }
      new_node(0.0);
    }

    // Passes until the budget is spent (budget) or every action is dead (not_found); a
    // falsification, the deadline or a cancellation throws SearchOver out of it.
    TrialStatus run() {
      for (std::int64_t i = 0; i < o_.budget; ++i) {
        if (nodes_.front().alive() == 0) return TrialStatus::not_found;
        ++passes_;
        if (!descend()) continue;  // an exhausted node: a pass without a simulation
        const double rho = play_out();
        back_up(rho);
        if (o_.local_budget > 0) {
          if (rho < best_) {
            best_ = rho;
            keep_best();
            since_best_ = 0;
          } else if (++since_best_ >= wait_) {
            // A local search that found nothing better doubles the wait before the next one.
            wait_ = polish() ? o_.local_after : 2 * wait_;
            since_best_ = 0;
          }
        }
      }
      return TrialStatus::budget;
    }

    void add_metrics(Json& metrics) const {
      metrics["passes"] = passes_;
      metrics["tree_nodes"] = nodes_.size();
      metrics["pruned"] = pruned_;
      if (o_.local_budget > 0) {
        metrics["local_searches"] = local_searches_;
        metrics["local_simulations"] = local_simulations_;
      }
    }

   private:
    struct Level {
      double duration = 0.0;       // the segment: how long an action holds its value, s
      std::vector<double> values;  // actions × inputs
      std::size_t actions = 0;
    };
    struct Edge {
      std::uint32_t action, child;
    };
    // One level's actions at a node: untried (todo) and tried and kept (done); the others
    // (leaves, pruned children) are dead.
    struct Bin {
      std::vector<std::uint32_t> todo;
      std::vector<Edge> done;
      std::size_t alive() const { return todo.size() + done.size(); }
    };
    struct Node {
      double time = 0.0;      // the prefix's end, s (a sum of segments)
      std::size_t piece = 0;  // where its input change takes effect: the first multiple of δt at or after time
      double prefix_upper = std::numeric_limits<double>::infinity();  // the prefix move's rank
      double best = std::numeric_limits<double>::infinity();          // the suffix move's rank
      std::vector<Bin> bins;                                          // one per level
      std::size_t alive() const {
        std::size_t n = 0;
        for (const Bin& b : bins) n += b.alive();
        return n;
      }
    };
    // One step of a pass: from `node`, action `action` of level `level`, to `child` (kLeaf: the
    // horizon); created: the step explored (the child is new, or the action a leaf).
    struct Step {
      std::uint32_t node, level, action, child;
      bool created;
    };
    enum class Move { explore, uniform, prefix, suffix };

    std::uint32_t new_node(double time) {
      Node n;
      n.time = time;
      n.piece = std::min(sims_.pieces(), static_cast<std::size_t>(std::ceil(time / sims_.piece_duration() - 1e-9)));
      n.bins.resize(levels_.size());
      for (std::size_t l = 0; l < levels_.size(); ++l) {
        n.bins[l].todo.resize(levels_[l].actions);
        for (std::uint32_t a = 0; a < levels_[l].actions; ++a) n.bins[l].todo[a] = a;
      }
      nodes_.push_back(std::move(n));
      return static_cast<std::uint32_t>(nodes_.size() - 1);
    }

    double uniform01() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
    std::size_t below(std::size_t n) {
      return static_cast<std::size_t>((static_cast<unsigned __int128>(rng_()) * n) >> 64);
    }
    // An index drawn with probability proportional to weights[i] (some weight > 0).
    std::size_t proportional(const double* weights, std::size_t n) {
      double total = 0.0;
      for (std::size_t i = 0; i < n; ++i) total += weights[i];
      const double x = uniform01() * total;
      double sum = 0.0;
      std::size_t last = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (weights[i] <= 0.0) continue;
        sum += weights[i];
        last = i;
        if (x < sum) return i;
      }
      return last;  // x rounded up to the total
    }

    // The level: weight 2^-l × (alive actions / actions) (FalStar's Bin.probability).
    std::uint32_t choose_level(const Node& n) {
      weights_.resize(levels_.size());
      for (std::size_t l = 0; l < levels_.size(); ++l)
        weights_[l] = std::ldexp(1.0, -static_cast<int>(l)) * static_cast<double>(n.bins[l].alive()) /
                      static_cast<double>(levels_[l].actions);
      return static_cast<std::uint32_t>(proportional(weights_.data(), weights_.size()));
    }

    Move choose_move(const Bin& b) {
      const double w[4] = {b.todo.empty() ? 0.0 : o_.explore, b.done.empty() ? 0.0 : o_.uniform,
                           b.done.empty() ? 0.0 : o_.prefix, b.done.empty() ? 0.0 : o_.suffix};
      return static_cast<Move>(proportional(w, 4));
    }

    // The kept child with the lowest rank, ties drawn uniformly.
    template <class Rank>
    const Edge& lowest(const Bin& b, Rank rank) {
      double least = std::numeric_limits<double>::infinity();
      std::size_t ties = 0, chosen = 0;
      for (std::size_t i = 0; i < b.done.size(); ++i) {
        const double r = rank(nodes_[b.done[i].child]);
        if (r < least || ties == 0) {
          least = r;
          ties = 1;
          chosen = i;
        } else if (r == least && below(++ties) == 0) {  // reservoir: each tie kept with 1 / ties
          chosen = i;
        }
      }
      return b.done[chosen];
    }

    // Root to a leaf: the pass's steps into path_, the signal into the slot. False when it
    // reaches a node with no live action (no simulation this pass).
    bool descend() {
      path_.clear();
      std::uint32_t at = 0;
      while (true) {
        if (nodes_[at].alive() == 0) return false;
        const std::uint32_t l = choose_level(nodes_[at]);
        Bin& bin = nodes_[at].bins[l];
        const Move move = choose_move(bin);
        if (move == Move::explore) {
          const std::size_t i = below(bin.todo.size());
          const std::uint32_t action = bin.todo[i];
          bin.todo[i] = bin.todo.back();
          bin.todo.pop_back();
          const double end = nodes_[at].time + levels_[l].duration;
          if (end >= horizon_ * (1.0 - 1e-12)) {  // FalStar: T <= t + dt
            path_.push_back({at, l, action, kLeaf, true});
            break;
          }
          const std::uint32_t child = new_node(end);  // invalidates references into nodes_
          path_.push_back({at, l, action, child, true});
          at = child;
          continue;
        }
        const Edge e = move == Move::uniform  ? bin.done[below(bin.done.size())]
                       : move == Move::prefix ? lowest(bin, [](const Node& c) { return c.prefix_upper; })
                                              : lowest(bin, [](const Node& c) { return c.best; });
        path_.push_back({at, l, e.action, e.child, false});
        at = e.child;
      }
      // The signal: each step's value over its segment, cut at the horizon.
      keep_path(pass_ends_, pass_values_);
      write_signal(pass_ends_, pass_values_.data());
      return true;
    }

    // The path's segments: their ends (pieces of δt) and values (segment-major).
    void keep_path(std::vector<std::size_t>& ends, std::vector<double>& values) const {
      const std::size_t m = sims_.input_box().lo.size();
      ends.clear();
      values.clear();
      for (const Step& s : path_) {
        ends.push_back(s.child == kLeaf ? sims_.pieces() : nodes_[s.child].piece);
        const double* u = levels_[s.level].values.data() + static_cast<std::size_t>(s.action) * m;
        values.insert(values.end(), u, u + m);
      }
    }

    // The slot's signal from segments (ends in pieces of δt, values segment-major). Constant:
    // each segment holds its value. Linear: the value is the control point at the segment's end,
    // the line runs from the control point at its start (the first segment's: its own value).
    void write_signal(const std::vector<std::size_t>& ends, const double* values) {
      const std::size_t m = sims_.input_box().lo.size();
      const bool linear = sims_.shape() == InputShape::linear;
      if (linear) std::copy(values, values + m, slot_.start.begin());
      std::size_t from = 0;
      for (std::size_t s = 0; s < ends.size(); ++s) {
        const double* u = values + s * m;
        for (std::size_t k = from; k < ends[s]; ++k) {
          if (!linear) {
            std::copy(u, u + m, slot_.pieces[k].u.begin());
            continue;
          }
          const std::vector<double>& a =
              from == 0 ? slot_.start : slot_.pieces[from - 1].u;  // the control point at `from`
          const double w = static_cast<double>(k + 1 - from) / static_cast<double>(ends[s] - from);
          for (std::size_t i = 0; i < m; ++i)
            slot_.pieces[k].u[i] = k + 1 == ends[s] ? u[i] : stl::linear_value(a[i], u[i], w);
        }
        from = std::max(from, ends[s]);
      }
    }

    // One simulation of the pass's signal, counted (throws SearchOver at the search's end).
    double play_out() {
      sims_.check_budget();
      sims_.simulate(slot_);
      return sims_.account(slot_);
    }

    // The pass's result into the tree: subtree bests along the path, and each new child kept or
    // pruned by its prefix's robustness interval.
    void back_up(double rho) {
      const stl::SimulatedTrace& trace = slot_.simulator.trace();
      for (const Step& s : path_) {
        Node& n = nodes_[s.node];
        n.best = std::min(n.best, rho);
        if (!s.created || s.child == kLeaf) continue;
        Node& child = nodes_[s.child];
        child.best = std::min(child.best, rho);
        // The prefix: the samples up to the child's time (pieces 0 .. piece - 1); a trace that
        // ended before (the system's invariant) is a prefix as it stands.
        const std::size_t samples = sims_.samples_through(trace, child.piece);
        const stl::Interval bounds = slot_.monitor.prefix_bounds(trace, samples, true);
        if (bounds.lower < 0.0) {
          child.prefix_upper = bounds.upper;
          nodes_[s.node].bins[s.level].done.push_back({s.action, s.child});
        } else {
          ++pruned_;
        }
      }
    }

    // adaptive-local: when local_after passes in a row have not lowered the best robustness, the
    // best signal so far is polished by a short Nelder-Mead (NLopt) over its segments' values,
    // continuous within the input box, the segments' times fixed, started at its values with a
    // first step of local_step of each range, for at most local_budget simulations of the run's
    // budget; what it finds becomes the best signal, which the next local search starts from.
    // The tree chooses the signal's shape (where the input changes, and roughly to what); the
    // local search moves the values off the dyadic levels into the bands between them, where the
    // tree has stalled. Its simulations add nothing to the tree.
    void keep_best() { keep_path(best_ends_, best_values_); }

    bool polish() {
      const std::size_t m = sims_.input_box().lo.size();
      // The free values: the last local_segments segments' (all: 0), the earlier ones held.
      const std::size_t segments = best_ends_.size();
      const std::size_t free = o_.local_segments == 0 ? segments : std::min(segments, o_.local_segments);
      first_free_ = (segments - free) * m;
      std::vector<double> x(best_values_.begin() + static_cast<std::ptrdiff_t>(first_free_), best_values_.end());
      std::vector<double> lo(x.size()), hi(x.size());
      for (std::size_t k = 0; k < x.size(); ++k) {
        lo[k] = sims_.input_box().lo[k % m];
        hi[k] = sims_.input_box().hi[k % m];
      }
      struct State {
        Pass* pass;
        std::int64_t left;
        double best;
        std::vector<double> best_x;
        std::optional<SearchOver> over;
      } state{this, o_.local_budget, best_, {}, std::nullopt};
      nlopt::opt opt(nlopt::LN_NELDERMEAD, static_cast<unsigned>(x.size()));
      opt.set_lower_bounds(lo);
      opt.set_upper_bounds(hi);
      opt.set_min_objective(
          [](const std::vector<double>& v, std::vector<double>&, void* data) {
            auto* s = static_cast<State*>(data);
            if (s->left <= 0) throw nlopt::forced_stop();
            --s->left;
            try {
              const double rho = s->pass->simulate_values(v);
              if (rho < s->best) {
                s->best = rho;
                s->best_x = v;
              }
              return std::isfinite(rho) ? rho : std::numeric_limits<double>::max();
            } catch (const SearchOver& over) {
              s->over = over;
              throw nlopt::forced_stop();
            }
          },
          &state);
      std::vector<double> step(x.size());
      for (std::size_t k = 0; k < x.size(); ++k) step[k] = o_.local_step * (hi[k] - lo[k]);
      opt.set_initial_step(step);
      ++local_searches_;
      double value = 0.0;
      try {
        opt.optimize(x, value);
      } catch (const std::exception&) {
        // The search is over (re-thrown below), or the local budget or NLopt ended this one.
      }
      local_simulations_ += o_.local_budget - state.left;
      if (state.over) throw *state.over;
      if (!(state.best < best_)) return false;
      best_ = state.best;
      std::copy(state.best_x.begin(), state.best_x.end(),
                best_values_.begin() + static_cast<std::ptrdiff_t>(first_free_));
      return true;
    }

    // One simulation of the best signal with its free values (from first_free_ on) set to v
    // (segment-major), counted.
    double simulate_values(const std::vector<double>& v) {
      const std::size_t m = sims_.input_box().lo.size();
      pass_values_ = best_values_;
      for (std::size_t at = first_free_; at < pass_values_.size(); ++at)
        pass_values_[at] = std::clamp(v[at - first_free_], sims_.input_box().lo[at % m], sims_.input_box().hi[at % m]);
      write_signal(best_ends_, pass_values_.data());
      sims_.check_budget();
      sims_.simulate(slot_);
      return sims_.account(slot_);
    }

    const AdaptiveOptions& o_;
    SignalSimulations& sims_;
    Rng rng_;
    SignalSlot& slot_;
    std::vector<Level> levels_;
    std::vector<Node> nodes_;
    std::vector<Step> path_;
    std::vector<double> weights_;
    double horizon_;
    std::int64_t passes_ = 0, pruned_ = 0, local_searches_ = 0, local_simulations_ = 0;
    double best_ = std::numeric_limits<double>::infinity();
    std::int64_t since_best_ = 0, wait_ = o_.local_after;
    std::vector<std::size_t> pass_ends_;  // this pass's signal: its segments' ends (pieces)
    std::vector<double> pass_values_;     // and their values, segment-major
    std::vector<std::size_t> best_ends_;  // the best signal: its segments' ends (pieces)
    std::vector<double> best_values_;     // and their values, segment-major
    std::size_t first_free_ = 0;          // the local search's first free value in best_values_
  };

  AdaptiveOptions o_;
};

void check_adaptive_system(const System& system, const Json& options) {
  const AdaptiveOptions o = read_options(options);
  check_signal_system(system, o.horizon, o.shape, /*parameters=*/false);
}

std::vector<OptionSpec> adaptive_options() {
  return {
      {"budget", 1500, "passes per run, each at most one simulation (ARCH-COMP: 1500)", "[1, 100000000]"},
      {"horizon", 0.0, "length of the input signal, s (0: the requirement's horizon)", "[0, 1e6]"},
      {"cp", "2 2 3 3 3 4",
       "segments per level (FalStar's control points): level l holds an input for horizon / cp_l s, a change taking "
       "effect at the next multiple of δt; level l's values cost l (corners 0, n/2^k costs k, summed over inputs)"},
      {"exploration", 0.25, "weight of the explore move (an untried action)", "(0, 1]"},
      {"uniform", 0.25, "weight of the uniform move (a random kept child)", "[0, 1]"},
      {"prefix", 0.25, "weight of the prefix move (the child with the lowest prefix robustness bound)", "[0, 1]"},
      {"suffix", 0.25, "weight of the suffix move (the child with the lowest simulation robustness below it)",
       "[0, 1]"},
      input_shape_option()};
}

}  // namespace

MethodEntry adaptive_method() {
  return {"adaptive",
          "FalStar's probabilistically adaptive tree search (Ernst et al. 2019): input levels refined corners first, "
          "pruned by the prefix robustness bound",
          adaptive_options(),
          [](const Json& o) { return std::make_unique<AdaptiveSearch>(read_options(o)); },
          check_adaptive_system,
          true};
}

MethodEntry adaptive_local_method() {
  std::vector<OptionSpec> options = adaptive_options();
  options.push_back({"local_budget", 20, "simulations of each local search (Nelder-Mead over a new best pass's values)",
                     "[1, 100000]"});
  options.push_back(
      {"local_step", 0.125, "the local search's first step, as a fraction of each input's range", "(0, 1]"});
  options.push_back(
      {"local_segments", 0, "the trailing segments whose values the local search moves (0: all)", "[0, 1000]"});
  options.push_back({"local_after", 20,
                     "passes in a row without a new best robustness before a local search from the best",
                     "[1, 100000]"});
  return {"adaptive-local",
          "tree-optimiser hybrid: FalStar's adaptive tree chooses the signal's shape; where it stalls, the best signal "
          "is polished by a short Nelder-Mead over its values (NLopt)",
          std::move(options),
          [](const Json& o) { return std::make_unique<AdaptiveSearch>(read_options(o)); },
          check_adaptive_system,
          true};
}

}  // namespace hyfal
