// HyDICE, seed 002 Sect. 3 (Plaku, Kavraki & Vardi): Alg. 2 with the discrete search of
// Sect. 3.2 and the motion planner of Sect. 3.3 (Alg. 3 = Propagator::propagate).
//
// Needs a Decomposition from the system (System::decomposition()); throws otherwise.
// Choices the paper leaves open (documented here, options in hydice_method()):
//  - Time. t(D) and t_σ are measured in propagations, not seconds, so that a trial is a
//    deterministic function of ctx.seed: t(D) = 1 + (propagations started from states in D)
//    (the 1 keeps w finite for a region not yet extended); t_σ = max(`t_sigma`, regions the
//    lead search expanded / kExpansionsPerPropagation) propagations per lead — the paper's t_σ
//    is wall time, which the second term approximates: a long lead search buys a long step.
//  - cov(D) = number of coverage cells (side Decomposition::cell_size() on the projection)
//    holding at least one tree state; cells are keyed by (region, ix, iy) in a hash map.
//  - ν, ζ, τ = 1, 2, 0.5 by default (the paper calls them normalization constants and gives no
//    values). Chosen by a sweep on navigation, random driver, property 0, seed 1, nodes to a
//    witness (2 trials each): (1, 1, 1) 305k / 326k at 64² and no witness in 30 s at 128²;
//    (1, 2, 0.5) 38k / 57k at 64², 84k / 113k at 128², 129k / 138k at 256². With ζ = 2 a
//    well-covered region is a cheap edge, so leads run through the tree to its frontier instead
//    of fanning out across the maze; τ = 0.5 still makes a region that keeps failing dearer.
//    A region not reached yet has the lead weight vol^ν (as cov = t = 1).
//  - Leads: with probability `shortest_probability` (0.9, Sect. 4) the shortest path for edge cost
//    1/(w_i w_j); else a random path, the shortest for i.i.d. edge costs uniform in (0, 1]. Both
//    by A* over the implicit graph (LeadSearch; only regions it touches are stored) with
//    h(r) = `lead_heuristic` x Decomposition::hops_to_unsafe(r) x c, c = the cost 1/(w_a w_b) of
//    an edge between two unreached regions of the start region's volume (1 for random paths).
//    Deliberately a weighted A*, not an admissible one: hops_to_unsafe is a lower bound on hops
//    (navigation: the exact region distance in G_D), and c is the exact cost of a hop on
//    unreached ground (where the lead leaves the tree, with every region of the navigation
//    decomposition the same volume), so that beyond the tree h is exact and the search runs
//    along a shortest path without fanning out (issue 12: with the terrain distance, up to 2x
//    short of the region distance, a navigation 1024² lead expanded 41 k regions on average,
//    with the region distance 1.2 k, and trials took half the time); but inside a well-covered
//    tree an edge costs far less than c (w grows with cov^ζ), so there h overestimates and the
//    search runs greedily toward the unsafe set instead of flooding the tree; regions expanded
//    are never reopened. The lead is then not always the exact shortest path of Sect. 3.2.3;
//    `lead_heuristic` = 0 gives plain Dijkstra (exact), and the default is kept because the
//    committed tables were produced with it (an admissible price per hop, the smallest edge
//    cost, tends to 0 as coverage grows and degenerates to Dijkstra, which floods the tree).
//    Regions with no path to an unsafe one (hops = inf) are never queued.
//  - Lead search cost (issue 12): the regions a search touches are indexed densely where the
//    decomposition is dense (Decomposition::dense_size; navigation), in paged flat arrays reset
//    by a stamp, instead of an open-addressing hash table; the reached regions' estimates are
//    indexed the same way (the weight of every touched region is read); the open list is an
//    indexed 4-ary heap with decrease-key instead of a lazy binary heap; the neighbours' cells
//    are prefetched. Equivalence: entries are still created in the same order (their index
//    breaks ties), the weights are the same expressions, and the A* order (f, h, entry) is a
//    total order in which an entry's f only decreases, so any exact priority queue pops the
//    same sequence: the same leads come out (test_hydice_pinned pins nodes, propagations, leads
//    and lead expansions of fixed trials recorded before the change).
//  - Structure (issue 12, as OMPL splits Syclop): HydiceSearch is the fixed lead / availability
//    layer (leads, D_avail, t(D), cov(D), the outer loop of Alg. 2); the motion-planning step
//    varies: SequentialStep (batch = 1) or BatchStep, both built from HydiceSearch's draw /
//    propagate / commit phases.
//  - Batches (`batch` = B > 1, core/search/parallel_slots.hpp): one round = B motion steps toward the
//    current lead's D_avail (or, without leads, every reached region). The selection weights
//    w_sel (t(D), cov(D)) are those of the round's start; in slot order, slot s draws its region,
//    coverage cell (the cell's selection count grows as each slot selects, as in the sequential
//    step) and state from its own stream Rng(slot_seed(seed, round, s)); then, in parallel,
//    each slot draws its inputs from the rest of its stream and propagates, with its own
//    propagator and buffers, from its state in the tree as the round found it; the slots
//    commit in slot order (t(D) counts, nodes, coverage cells; the first slot reaching the
//    unsafe set wins; the node cap is checked before each commit, so it is exact), each as soon
//    as it has run, while later slots may still be propagating (SlotRounds: a helper thread
//    stands by between rounds, core/search/parallel_slots.hpp). A round counts B motion steps
//    toward t_σ. Leads, D_avail and the random paths keep using the trial's stream Rng(seed);
//    rounds are numbered over the whole trial.
//    With batches the lead search is pipelined (issue 12 item 5): lead k + 1 is searched while
//    the tree grows along lead k, on the lead weights frozen when that growth started (so it
//    runs on a free thread; on one thread the two simply run in turn), and its D_avail is drawn
//    after the growth (HydiceSearch::run_pipelined).
//    Results depend on B, never on the number of threads; B = 1 is the sequential step with
//    the trial's one stream, exactly the algorithm before batches existed.
//  - v_safe's edges go to the regions of the initial states (every initial state is a root of
//    the one tree, so a witness may start from any of them).
//  - Inputs (`inputs`): `box` draws u uniformly from the admissible box at the selected state
//    (System::input_bounds: the navigation drivers' intervals of Sect. 4.1.2, U otherwise);
//    `set` draws a random element of the suite's Ū (mapped onto that box by InputGrid, as every
//    other planner sees it); `auto` (default) = what the suite declares
//    (SystemInfo::continuous_random_inputs): box for navigation (every driver of Sect. 4.1.2,
//    RandomDriver included, draws u uniformly from an interval), set otherwise (the suite's
//    discretization is its choice: aircraft wind at {−w, 0, w}², whose persistent extremes drive
//    the conflicts — uniform draws from [−w, w]² timed out in 20 s on every random N = 10 trial
//    where Ū solves them in well under a second). Each input is applied for the suite's δt
//    (SystemInfo::step_duration); with controls > 1 the end
//    state nearest (on the projection) to the centre of the next lead region is kept — a
//    steering step the paper does not have; controls = 1 (the default) is the paper's.
//  - State selection: cell ∝ 1/nsel² with nsel = selections so far + 1; then a state of the cell
//    uniformly. A propagation that makes no progress (rejected, or zero time without a jump) adds
//    no node but still counts toward t(D) and t_σ.
//  - hydice-noleads (HyDICE[NoLeads] of Sect. 4): no discrete search; D_avail = every reached
//    region, and one motion-planning step for the whole budget.
#include "core/planners/hydice/hydice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <queue>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

#include "core/planners/rrt/rrt_extension.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/input_grid.hpp"
#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"

namespace hyfal {

namespace {
// x^e without std::pow for the exponents in use (the weights are evaluated per region expanded).
double power(double x, double e) {
  if (e == 1.0) return x;
  if (e == 2.0) return x * x;
  if (e == 0.5) return std::sqrt(x);
  if (e == 0.0) return 1.0;
  return std::pow(x, e);
}
}  // namespace

double hydice_lead_weight(const HydiceExponents& e, double vol, double cov, double t) {
  return power(vol, e.nu) * power(cov, e.zeta) / power(t, e.tau);
}

double hydice_selection_weight(const HydiceExponents& e, double vol, double cov, double t) {
  return power(vol, e.nu) / (power(t, e.tau) * power(cov, e.zeta));
}

void RegionSlots::attach(const Decomposition& d) {
  if (dec_ != &d || dense_size_ != d.dense_size()) {
    dec_ = &d;
    dense_size_ = d.dense_size();
    dense_ = d.dense_size() > 0;
    pages_.clear();
    table_.clear();
    if (dense_) pages_.resize(static_cast<std::size_t>((d.dense_size() + kPageMask) >> kPageBits));
    // Open addressing starts at 2^12 slots (64 KB) and doubles at load 1/2: the start only saves
    // the first few doublings (a navigation lead search touches 10^3-10^6 regions).
    else
      table_.assign(std::size_t{1} << 12, HashSlot{});
  }
  clear();
}

void RegionSlots::clear() {
  live_ = 0;
  if (++stamp_ != 0) return;
  // The stamp wrapped (after 2^32 clears): forget every stale stamp so none can match again.
  for (auto& page : pages_)
    if (page) std::fill(page.get(), page.get() + (kPageMask + 1), DenseCell{});
  std::fill(table_.begin(), table_.end(), HashSlot{});
  stamp_ = 1;
}

std::unique_ptr<RegionSlots::DenseCell[]> RegionSlots::new_page() const {
  return std::make_unique<DenseCell[]>(kPageMask + 1);  // stamp 0: never the current one
}

std::uint32_t RegionSlots::find(RegionId r) const {
  if (dense_) {
    const std::uint64_t i = dec_->dense_index(r);
    const auto& page = pages_[i >> kPageBits];
    if (!page) return kNone;
    const DenseCell& c = page[i & kPageMask];
    return c.stamp == stamp_ ? c.value : kNone;
  }
  if (table_.empty()) return kNone;
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = static_cast<std::size_t>(splitmix64(r)) & mask;; i = (i + 1) & mask) {
    const HashSlot& sl = table_[i];
    if (sl.stamp != stamp_) return kNone;
    if (sl.region == r) return sl.value;
  }
}

std::uint32_t RegionSlots::hashed_find_or_insert(RegionId r, std::uint32_t value, bool& fresh) {
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = static_cast<std::size_t>(splitmix64(r)) & mask;; i = (i + 1) & mask) {
    HashSlot& sl = table_[i];
    if (sl.stamp != stamp_) {  // empty in this generation: claim it
      sl = HashSlot{r, value, stamp_};
      fresh = true;
      if (2 * ++live_ > table_.size()) grow();  // keep the load below 1/2
      return value;
    }
    if (sl.region == r) {
      fresh = false;
      return sl.value;
    }
  }
}

void RegionSlots::grow() {
  std::vector<HashSlot> old;
  old.swap(table_);
  table_.assign(old.size() * 2, HashSlot{});
  const std::size_t mask = table_.size() - 1;
  for (const HashSlot& sl : old) {
    if (sl.stamp != stamp_) continue;
    std::size_t i = static_cast<std::size_t>(splitmix64(sl.region)) & mask;
    while (table_[i].stamp == stamp_) i = (i + 1) & mask;
    table_[i] = sl;
  }
}

std::vector<RegionId> LeadSearch::find(const Decomposition& d, std::span<const RegionId> starts,
                                       const std::function<double(RegionId)>& weight, Rng* rng,
                                       double heuristic_edge_cost, std::size_t max_expanded) {
  slots_.attach(d);
  entries_.clear();
  heap_pos_.clear();
  expanded_ = 0;
  // A*: ordered by f = dist + h, ties to the smaller h (the deeper region), h = hops_to_unsafe
  // * heuristic_edge_cost; a region with no path to an unsafe one (hops = inf) is never queued.
  auto h_of = [&](double hops) {
    if (std::isinf(hops)) return hops;
    return heuristic_edge_cost > 0.0 ? heuristic_edge_cost * hops : 0.0;
  };
  // The rank of h in the queue's key: hops itself (saturated at 2^32 - 1; a fractional bound
  // would only merge ranks, so that ties break by entry), or 0 when every h is 0.
  auto h_rank_of = [&](double hops) -> std::uint32_t {
    if (!(heuristic_edge_cost > 0.0)) return 0;
    return hops >= 4294967295.0 ? 0xffffffffu : static_cast<std::uint32_t>(hops);
  };
  open_.clear();
  // The open list is an indexed 4-ary heap with decrease-key: each queued region has exactly
  // one item holding its current f, so the pops come out in the same order as the lazy binary
  // heap this replaced (the order (f, h, entry) is total: h is fixed per entry, and an entry's
  // f only ever strictly decreases), with no stale items and a shallower heap.
  auto place = [&](std::size_t i, const OpenItem& it) {
    open_[i] = it;
    heap_pos_[it.entry()] = static_cast<std::uint32_t>(i);
  };
  auto sift_up = [&](std::size_t i, OpenItem it) {
    while (i > 0) {
      const std::size_t parent = (i - 1) / 4;
      if (!(open_[parent] > it)) break;
      place(i, open_[parent]);
      i = parent;
    }
    place(i, it);
  };
  auto pop_min = [&]() {
    const std::uint32_t top = open_[0].entry();
    const OpenItem last = open_.back();
    open_.pop_back();
    const std::size_t n = open_.size();
    if (n > 0) {
      std::size_t i = 0;
      while (true) {
        const std::size_t first = 4 * i + 1;
        if (first >= n) break;
        std::size_t best = first;
        const std::size_t end = std::min(first + 4, n);
        for (std::size_t c = first + 1; c < end; ++c) best = open_[best] > open_[c] ? c : best;
        if (!(last > open_[best])) break;
        place(i, open_[best]);
        i = best;
      }
      place(i, last);
    }
    heap_pos_[top] = kNotQueued;
    return top;
  };
  auto push = [&](const OpenItem& it) {  // a new item, or a smaller f for a queued entry
    const std::uint32_t at = heap_pos_[it.entry()];
    if (at == kNotQueued) {
      open_.push_back(it);
      sift_up(open_.size() - 1, it);
    } else {
      sift_up(at, it);
    }
  };
  for (RegionId s : starts) {
    const double hops = d.hops_to_unsafe(s);
    const double hs = h_of(hops);
    if (std::isinf(hs)) continue;
    bool fresh;
    const std::uint32_t k = entry_of(s, fresh);
    if (!fresh) continue;  // a duplicate start
    entries_[k].h = hs;
    entries_[k].h_rank = h_rank_of(hops);
    push(OpenItem::make(hs, entries_[k].h_rank, k));
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto w_of = [&](std::size_t k) {
    if (std::isnan(entries_[k].w)) entries_[k].w = weight(entries_[k].region);
    return entries_[k].w;
  };
  while (!open_.empty()) {
    const std::uint32_t k = pop_min();
    entries_[k].done = true;
    const RegionId r = entries_[k].region;
    const double dist = entries_[k].dist;
    if (d.is_unsafe(r)) {  // the edge to v_unsafe costs nothing
      std::vector<RegionId> lead;
      for (std::uint32_t x = k; x != kNoParent; x = entries_[x].parent) lead.push_back(entries_[x].region);
      std::reverse(lead.begin(), lead.end());
      return lead;
    }
    if (++expanded_ > max_expanded) break;
    d.neighbors(r, nb_);
    for (RegionId s : nb_) slots_.prefetch(s);
    const double wr = rng ? 0.0 : w_of(k);
    for (RegionId s : nb_) {
      bool fresh;
      const std::uint32_t j = entry_of(s, fresh);
      if (fresh) {
        const double hops = d.hops_to_unsafe(s);
        entries_[j].h = h_of(hops);
        entries_[j].h_rank = h_rank_of(hops);
      } else if (entries_[j].done) {
        continue;
      }
      if (std::isinf(entries_[j].h)) continue;
      const double cost = rng ? 1.0 - unit(*rng) : 1.0 / (wr * w_of(j));
      const double nd = dist + cost;
      if (!fresh && !(nd < entries_[j].dist)) continue;
      entries_[j].dist = nd;
      entries_[j].parent = k;
      push(OpenItem::make(nd + entries_[j].h, entries_[j].h_rank, j));
    }
  }
  return {};
}

std::vector<RegionId> hydice_lead(const Decomposition& d, std::span<const RegionId> starts,
                                  const std::function<double(RegionId)>& weight, Rng* rng, double heuristic_edge_cost,
                                  std::size_t max_expanded) {
  LeadSearch search;
  return search.find(d, starts, weight, rng, heuristic_edge_cost, max_expanded);
}

std::vector<RegionId> hydice_available(std::span<const RegionId> lead, const std::function<bool(RegionId)>& reached,
                                       Rng& rng) {
  std::vector<RegionId> avail;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = lead.size(); i-- > 0;) {
    if (!reached(lead[i])) continue;
    if (std::find(avail.begin(), avail.end(), lead[i]) != avail.end()) continue;
    if (unit(rng) * static_cast<double>(1 + avail.size()) < 1.0) avail.push_back(lead[i]);
  }
  return avail;
}

namespace {
// Index i in [0, count) drawn with probability ∝ weight(i) (>= 0, some > 0): one uniform draw
// on [0, Σ w), then the first i whose cumulative weight passes it. The weights are evaluated
// twice (sum, walk) instead of stored, so that no buffer is allocated per draw; both passes
// compute the same doubles in the same order, so the pick is the stored-vector pick exactly.
template <class Weight, class Urbg>
std::size_t pick_weighted_by(std::size_t count, Weight&& weight, Urbg& rng) {
  double total = 0.0;
  for (std::size_t i = 0; i < count; ++i) total += weight(i);
  double r = std::uniform_real_distribution<double>(0.0, total)(rng);
  for (std::size_t i = 0; i < count; ++i) {
    const double w = weight(i);
    if (r < w) return i;
    r -= w;
  }
  for (std::size_t i = count; i-- > 0;)  // rounding: the last positive weight
    if (weight(i) > 0.0) return i;
  return 0;
}

// A coverage cell ∝ 1/nsel² (Sect. 3.3.2), nsel = selections(i) + 1.
template <class Selections, class Urbg>
std::size_t pick_by_inverse_square(std::size_t count, Selections&& selections, Urbg& rng) {
  return pick_weighted_by(
      count,
      [&](std::size_t i) {
        const double n = 1.0 + selections(i);
        return 1.0 / (n * n);
      },
      rng);
}
}  // namespace

namespace {
template <class Urbg>
std::size_t hydice_pick_weighted_by(std::span<const double> w, Urbg& rng) {
  return pick_weighted_by(
      w.size(), [&](std::size_t i) { return w[i]; }, rng);
}
}  // namespace

std::size_t hydice_pick_weighted(std::span<const double> w, Rng& rng) { return hydice_pick_weighted_by(w, rng); }

std::size_t hydice_pick_cell(std::span<const std::uint32_t> selections, Rng& rng) {
  return pick_by_inverse_square(
      selections.size(), [&](std::size_t i) { return selections[i]; }, rng);
}

namespace {

// t_σ >= (regions the lead search expanded) / 50: the paper's t_σ is wall time, and when this was
// set one propagation (~10-40 µs on the navigation vehicles) cost about as much as 50 region
// expansions of the lead search (~0.3 µs each), so a lead search kept <= ~50 % of the time
// (perf, navigation 1024², property 0: 59 % in the lead search). It is a count, not a clock, so
// that trials stay deterministic; the issue-12 lead search is cheaper per expansion, but the
// constant stays so that the committed tables (which depend on t_σ) do not change.
constexpr std::int64_t kExpansionsPerPropagation = 50;

// The values come only from the resolved options (their defaults and ranges are declared once, in
// exponent_options() and hydice_method() below); no default is repeated here.
struct HydiceOptions {
  bool leads;
  std::int64_t t_sigma;
  double shortest_probability;
  double lead_heuristic;
  std::int64_t controls;
  std::int64_t batch;
  enum class Inputs { automatic, set, box } inputs;
  HydiceExponents e;
};

// `o` is resolved against the declared options (core/run/option_spec.hpp checks types and ranges).
HydiceOptions parse_options(const Json& o, bool leads) {
  HydiceOptions h{};
  h.leads = leads;
  h.e.nu = o.at("nu").get<double>();
  h.e.zeta = o.at("zeta").get<double>();
  h.e.tau = o.at("tau").get<double>();
  h.controls = o.at("controls").get<std::int64_t>();
  h.batch = o.at("batch").get<std::int64_t>();
  const std::string inputs = o.at("inputs").get<std::string>();
  if (inputs == "auto")
    h.inputs = HydiceOptions::Inputs::automatic;
  else if (inputs == "set")
    h.inputs = HydiceOptions::Inputs::set;
  else if (inputs == "box")
    h.inputs = HydiceOptions::Inputs::box;
  else
    throw std::invalid_argument(fmt::format("hydice: inputs must be auto, set or box (got '{}')", inputs));
  if (leads) {  // HyDICE[NoLeads] has no lead options: t_sigma etc. stay unused
    h.t_sigma = o.at("t_sigma").get<std::int64_t>();
    h.shortest_probability = o.at("shortest_probability").get<double>();
    h.lead_heuristic = o.at("lead_heuristic").get<double>();
  }
  return h;
}

// HyDICE runs on the suite's region decomposition (seed 002 Sect. 3.2).
void check_hydice_system(const System& sys, const Json&) {
  // HyDICE's leads run to the decomposition's unsafe regions: an STL requirement names no region
  // to reach (its violation is a property of a whole trace), so HyDICE searches reachability only.
  if (sys.info().requirement)
    throw std::invalid_argument(
        "HyDICE needs target regions, which an STL requirement does not give "
        "(use rrt, rrt-dstar, rrft or enhanced-rrt; or requirement= empty for the unsafe set)");
  if (!sys.decomposition())
    throw std::invalid_argument(
        fmt::format("suite '{}' provides no region decomposition, which HyDICE needs", sys.info().suite));
}

struct CellKey {
  RegionId region;
  std::int64_t ix, iy;
  bool operator==(const CellKey&) const = default;
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(splitmix64(
        k.region ^ splitmix64(static_cast<std::uint64_t>(k.ix) ^ splitmix64(static_cast<std::uint64_t>(k.iy)))));
  }
};

struct Cell {
  std::vector<NodeId> nodes;
  std::uint32_t selections = 0;
};

struct RegionData {
  RegionId id = 0;
  double volume = 0.0;
  std::int64_t propagations = 0;     // t(D) - 1
  std::vector<std::uint32_t> cells;  // indices into the cell table
  bool available = false;
  bool changed = false;  // t(D) or cov(D) changed since the last snapshot_lead_weights
};

// The lead / availability layer of Alg. 2 (OMPL's Syclop::solve): the tree, the reached regions
// with their estimates t(D) and cov(D) and coverage cells, D_avail, the current lead, and the
// outer loop (a lead, then a motion-planning step of t_σ propagations). It stays fixed; the
// motion step that grows the tree along the lead varies (SequentialStep, BatchStep below), as
// Syclop's subclasses implement selectAndExtend. The motion step is split into its three phases
// so that a batch can run them apart: draw (Alg. 2:9-10 and Alg. 3:1: region, cell, state,
// inputs; uses the RNG), propagate (Alg. 3: reads the frozen tree, writes only its own scratch),
// commit (Alg. 2:12-14: counts, the new node, the witness).
class HydiceSearch {
 public:
  // What one motion step drew: the selected region (an index into regions_), state and inputs.
  struct Draw {
    std::uint32_t region = 0;
    NodeId s = 0;
    Mode q = 0;
    RegionId selected = 0;                                                        // the region of D_avail drawn
    std::array<double, 2> target{std::numeric_limits<double>::quiet_NaN(), 0.0};  // steering (NaN: none)
    std::vector<double> inputs;                                                   // `controls` inputs, m each
    // choose()'s scratch, one per draw so that the slots of a batch choose concurrently.
    std::optional<InputGrid> grid;
    std::vector<double> ulo, uhi;
    std::vector<RegionId> nb;
  };
  // What its propagations produced: the kept end state (the nearest to the steering target; a
  // witness wins) and the counts.
  struct Outcome {
    bool any = false;  // some propagation made progress (RrtExtension::makes_progress)
    PropagationResult r;
    std::vector<double> x, u, x_try;
    std::int64_t propagations = 0, integration_steps = 0;
  };

  HydiceSearch(const HydiceOptions& o, const PlannerContext& ctx, PlannerOutcome& out)
      : o_(o),
        ctx_(ctx),
        sys_(ctx.system),
        info_(sys_.info()),
        dec_(sys_.decomposition()),
        out_(out),
        c_(out.counters),
        m_(info_.input_names.size()),
        prop_(sys_.make_propagator()),
        budget_(ctx),
        rng_(ctx.seed),
        cell_(dec_->cell_size()),
        tree_(info_.dim(), m_),
        draw_box_(o.inputs == HydiceOptions::Inputs::box ||
                  (o.inputs == HydiceOptions::Inputs::automatic && info_.continuous_random_inputs)) {
    prop_->set_interrupt(budget_.interrupt());  // a propagation past the deadline ends as rejected
    region_slot_.attach(*dec_);
    std::vector<std::vector<double>> starts{info_.initial_state};
    for (const auto& x0 : info_.other_initial_states) starts.push_back(x0);
    for (const auto& x0 : starts) {
      const NodeId id = add_node(kNoNode, info_.initial_mode, info_.initial_mode, x0, {}, 0.0, -1);
      start_regions_.push_back(dec_->region_of(info_.initial_mode, x0));
      if (!out_.trajectory && sys_.spec(info_.initial_mode, x0, ctx.parameters) <= 0.0) finish(id);
    }
    // The A* heuristic's cost per hop: the cost 1/(w_a w_b) of a G_D edge between two regions not
    // reached yet (cov = t = 1), at the start region's volume. See the header: exact per hop on
    // unreached ground, a deliberate overestimate inside a well-covered tree.
    unreached_edge_cost_ = 1.0 / std::pow(std::pow(dec_->volume(start_regions_.front()), o_.e.nu), 2.0);
  }

  // Alg. 2's outer loop: while the budget lasts, a lead (Alg. 2:6) and a motion-planning step of
  // t_σ motion steps along it (Alg. 2:7-14); HyDICE[NoLeads] has one step for the whole budget.
  template <class MotionStep>
  void run(MotionStep& step) {
    if (o_.leads && o_.batch > 1) {
      run_pipelined(step);
      return report();
    }
    while (!out_.trajectory) {
      if (auto why = budget_.exhausted(c_.nodes)) {
        out_.status = *why;
        break;
      }
      std::int64_t steps = std::numeric_limits<std::int64_t>::max();
      if (o_.leads) {
        const auto t_sigma = next_lead();
        if (!t_sigma) break;
        steps = *t_sigma;
      }
      step.grow(*this, steps);
    }
    report();
  }

  // With batches, the next lead is searched while the tree grows along the current one (two
  // tasks of one parallel_slots; with one thread they simply run one after the other). The next
  // lead uses the estimates frozen when that growth started (a snapshot of every reached
  // region's lead weight), and the trial's stream, which the batch step does not use; its
  // D_avail is drawn after the growth, against the regions reached by then. So lead k + 1 sees
  // the tree as lead k's step found it, not as it left it: deterministic, whatever the threads.
  template <class MotionStep>
  void run_pipelined(MotionStep& step) {
    if (out_.trajectory) return;
    auto t_sigma = next_lead();
    while (t_sigma && !out_.trajectory) {
      if (auto why = budget_.exhausted(c_.nodes)) {
        out_.status = *why;
        break;
      }
      snapshot_lead_weights();
      LeadFound next;
      parallel_slots(2, ctx_.cpu, [&](std::size_t task) {
        if (task == 0)
          step.grow(*this, *t_sigma);
        else
          next = search_lead(true);
      });
      if (out_.trajectory) break;
      t_sigma = adopt_lead(std::move(next));
    }
  }

  void report() {
    out_.metrics["regions_reached"] = regions_.size();
    out_.metrics["coverage_cells"] = cells_.size();
    if (o_.leads) {
      out_.metrics["leads"] = leads_;
      out_.metrics["random_leads"] = random_leads_;
      out_.metrics["failed_leads"] = failed_leads_;
      out_.metrics["lead_expansions"] = expansions_;
      out_.metrics["random_lead_expansions"] = random_expansions_;
    }
  }

  // Alg. 2:6 — the lead (Sect. 3.2.3) and D_avail (Sect. 3.3.1). Returns t_σ in motion steps,
  // or nothing when no unsafe region is reachable in G_D at all (status not_found).
  std::optional<std::int64_t> next_lead() { return adopt_lead(search_lead(false)); }

  // A lead and the regions its search expanded.
  struct LeadFound {
    std::vector<RegionId> lead;
    std::size_t expanded = 0;
  };
  // The search of Alg. 2:6: the shortest path for the weights as they stand (or, `snapshot`, as
  // snapshot_lead_weights froze them), or a random path. Uses the trial's stream.
  LeadFound search_lead(bool snapshot) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    ++leads_;
    LeadFound f;
    if (unit(rng_) < o_.shortest_probability) {
      const std::function<double(RegionId)> weight =
          snapshot ? std::function<double(RegionId)>([this](RegionId r) { return snapshot_weight(r); })
                   : std::function<double(RegionId)>([this](RegionId r) { return lead_weight(r); });
      f.lead = lead_search_.find(*dec_, start_regions_, weight, nullptr, o_.lead_heuristic * unreached_edge_cost_);
    } else {
      ++random_leads_;
      f.lead = lead_search_.find(*dec_, start_regions_, {}, &rng_, o_.lead_heuristic * 1.0);
      random_expansions_ += static_cast<std::int64_t>(lead_search_.expanded());
    }
    f.expanded = lead_search_.expanded();
    return f;
  }

  // Makes `found` the current lead and draws its D_avail (Sect. 3.3.1). Returns t_σ in motion
  // steps, or nothing when no unsafe region is reachable in G_D at all (status not_found).
  std::optional<std::int64_t> adopt_lead(LeadFound found) {
    std::vector<RegionId> lead = std::move(found.lead);
    if (lead.empty()) {
      ++failed_leads_;
      if (failed_leads_ == 1 && leads_ == 1) {  // no unsafe region reachable in G_D at all
        out_.status = TrialStatus::not_found;
        return std::nullopt;
      }
      lead = start_regions_;
    }
    lead_position_.clear();  // only steering (controls > 1) reads it: a hash insert per lead region
    if (o_.controls > 1)
      for (std::size_t i = 0; i < lead.size(); ++i) lead_position_.emplace(lead[i], i);
    current_lead_.swap(lead);
    for (RegionId r : avail_) region(r).available = false;
    avail_ = hydice_available(
        current_lead_, [this](RegionId r) { return reached(r); }, rng_);
    for (RegionId r : avail_) region(r).available = true;
    // t_σ: at least t_sigma propagations, more when the lead search was long, so that the
    // discrete search keeps a bounded share of the time (the paper's t_σ is wall time).
    expansions_ += static_cast<std::int64_t>(found.expanded);
    return std::max<std::int64_t>(o_.t_sigma, static_cast<std::int64_t>(found.expanded) / kExpansionsPerPropagation);
  }

  // Freezes the lead weight of every reached region for search_lead(true).
  // Incremental: a region's index never changes (regions are only appended), and its weight
  // changes only with its t(D) or cov(D), so only the regions reached since the last snapshot
  // and those whose estimates changed are (re)computed: the same weights as recomputing all of
  // them (this was 1.8 % of a batch-8 trial, serial between two growths).
  void snapshot_lead_weights() {
    if (snap_w_.empty()) snap_slots_.attach(*dec_);
    const std::size_t before = snap_w_.size();
    snap_w_.resize(regions_.size());
    for (std::size_t i = before; i < regions_.size(); ++i) {
      bool fresh;
      snap_slots_.find_or_insert(regions_[i].id, static_cast<std::uint32_t>(i), fresh);
      snap_w_[i] = lead_weight(regions_[i].id);
    }
    for (std::uint32_t i : changed_) {
      regions_[i].changed = false;
      if (i < before) snap_w_[i] = lead_weight(regions_[i].id);
    }
    changed_.clear();
  }
  double snapshot_weight(RegionId r) const {
    const std::uint32_t i = snap_slots_.find(r);
    return i == RegionSlots::kNone ? power(dec_->volume(r), o_.e.nu) : snap_w_[i];
  }

  // w_sel of every region of D_avail (Sect. 3.3.1), as the estimates stand now.
  void selection_weights(std::vector<double>& wsel) const {
    wsel.resize(avail_.size());
    for (std::size_t i = 0; i < avail_.size(); ++i) {
      const RegionData& rd = regions_[region_slot_.find(avail_[i])];
      wsel[i] = hydice_selection_weight(o_.e, rd.volume, static_cast<double>(rd.cells.size()),
                                        1.0 + static_cast<double>(rd.propagations));
    }
  }

  // Alg. 2:9-10 and Alg. 3:1 — a region of D_avail by `wsel`, a coverage cell of it ∝ 1/nsel²
  // (its selection counted now), a state of the cell uniformly, then the inputs: `controls`
  // draws uniformly from the admissible box at x_s (the driver) or from Ū, and, with
  // controls > 1, the steering target. The order of the draws is the sequential algorithm's.
  template <class Urbg>
  void select(Urbg& g, std::span<const double> wsel, Draw& d) {
    const RegionId selected = avail_[hydice_pick_weighted_by(wsel, g)];
    d.region = region_slot_.find(selected);
    const RegionData& rd = regions_[d.region];
    const std::size_t ci = pick_by_inverse_square(
        rd.cells.size(), [&](std::size_t i) { return cells_[rd.cells[i]].selections; }, g);
    Cell& cl = cells_[rd.cells[ci]];
    ++cl.selections;
    d.s = cl.nodes[std::uniform_int_distribution<std::size_t>(0, cl.nodes.size() - 1)(g)];
    d.q = tree_.info(d.s).mode;
    d.selected = selected;
  }
  // The rest of the draw, from x_s: reads the tree and the estimates only, and writes only d.
  template <class Urbg>
  void choose(Urbg& g, Draw& d) const {
    const auto x_s = tree_.state(d.s);
    if (draw_box_) {
      d.ulo.resize(m_);
      d.uhi.resize(m_);
      sys_.input_bounds(d.q, x_s, d.ulo, d.uhi);
    } else {
      if (!d.grid) d.grid.emplace(sys_);
      d.grid->at(d.q, x_s);
    }
    d.target = {std::numeric_limits<double>::quiet_NaN(), 0.0};
    if (o_.controls > 1) d.target = steering_target(d.selected, g, d.nb);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    d.inputs.resize(static_cast<std::size_t>(o_.controls) * m_);
    for (std::int64_t j = 0; j < o_.controls; ++j) {
      double* u = d.inputs.data() + static_cast<std::size_t>(j) * m_;
      if (draw_box_) {
        draw_uniform_input(g, d.ulo, d.uhi, std::span<double>(u, m_));
      } else {
        const auto gi = d.grid->input(std::uniform_int_distribution<std::size_t>(0, d.grid->count() - 1)(g));
        std::copy(gi.begin(), gi.end(), u);
      }
    }
  }
  void draw(Rng& g, std::span<const double> wsel, Draw& d) {
    select(g, wsel, d);
    choose(g, d);
  }

  // Alg. 3 (PropagateForward) for each drawn input, from x_s for the suite's δt; keeps the end
  // state nearest (on the projection) to the steering target, a witness first. Reads the tree
  // and the decomposition only: slots of a batch run it concurrently, each with its propagator.
  void propagate(Propagator& prop, const Draw& d, Outcome& o) const {
    const std::size_t n = info_.dim();
    o.x.resize(n);
    o.x_try.resize(n);
    o.u.resize(m_);
    o.any = false;
    o.propagations = o.integration_steps = 0;
    const auto x_s = tree_.state(d.s);
    double best = std::numeric_limits<double>::infinity();
    for (std::int64_t j = 0; j < o_.controls; ++j) {
      const std::span<const double> u(d.inputs.data() + static_cast<std::size_t>(j) * m_, m_);
      const PropagationResult r = prop.propagate(d.q, x_s, u, ctx_.parameters, info_.step_duration, o.x_try);
      ++o.propagations;
      o.integration_steps += r.steps;
      if (!RrtExtension::makes_progress(r)) continue;
      double score = 0.0;
      if (!std::isnan(d.target[0])) {
        double pr[2];
        dec_->project(r.mode, o.x_try, std::span<double, 2>(pr, 2));
        score = std::hypot(pr[0] - d.target[0], pr[1] - d.target[1]);
      }
      if (RrtExtension::reached_unsafe(r)) score = -1.0;  // a witness wins
      if (score < best) {
        best = score;
        o.r = r;
        o.x.swap(o.x_try);
        std::copy(u.begin(), u.end(), o.u.begin());
        o.any = true;
      }
    }
  }

  // Alg. 2:12-14 — the counts toward t(D) of the selected region (every propagation counts,
  // also one that made no progress), the new node, the witness. Returns whether the search
  // ended (a witness, or the node cap reached).
  bool commit(const Draw& d, const Outcome& o) {
    regions_[d.region].propagations += o.propagations;
    mark_changed(d.region);
    c_.propagations += o.propagations;
    c_.integration_steps += o.integration_steps;
    if (!o.any) return false;
    const NodeId id = add_node(d.s, d.q, o.r.mode, o.x, o.u, o.r.duration, o.r.transition);
    if (RrtExtension::reached_unsafe(o.r)) finish(id);
    return out_.trajectory.has_value() || c_.nodes >= ctx_.limits.max_nodes;
  }

  bool done() const { return out_.trajectory.has_value(); }
  const NodeStore& tree() const { return tree_; }
  bool out_of_budget() const { return budget_.exhausted(c_.nodes).has_value(); }
  bool at_node_cap() const { return c_.nodes >= ctx_.limits.max_nodes; }
  Rng& rng() { return rng_; }
  Propagator& propagator() { return *prop_; }
  const SearchBudget& budget() const { return budget_; }
  const PlannerContext& ctx() const { return ctx_; }

 private:
  NodeId add_node(NodeId parent, Mode edge_mode, Mode mode, std::span<const double> x, std::span<const double> u,
                  double duration, int transition) {
    const NodeId id = tree_.add(parent, edge_mode, mode, x, u, duration, transition);
    ++c_.nodes;
    const RegionId r = dec_->region_of(mode, x);
    bool fresh;
    const std::uint32_t ri = region_slot_.find_or_insert(r, static_cast<std::uint32_t>(regions_.size()), fresh);
    if (fresh) {
      RegionData& added = regions_.emplace_back();
      added.id = r;
      added.volume = dec_->volume(r);
    }
    RegionData& rd = regions_[ri];
    double pr[2];
    dec_->project(mode, x, std::span<double, 2>(pr, 2));
    const CellKey key{r, static_cast<std::int64_t>(std::floor(pr[0] / cell_)),
                      static_cast<std::int64_t>(std::floor(pr[1] / cell_))};
    auto [cit, new_cell] = cell_index_.try_emplace(key, static_cast<std::uint32_t>(cells_.size()));
    if (new_cell) {
      cells_.emplace_back();
      rd.cells.push_back(cit->second);
      mark_changed(ri);
    }
    cells_[cit->second].nodes.push_back(id);
    if (!rd.available) {  // a newly reached region joins D_avail (Sect. 3.3.1)
      rd.available = true;
      avail_.push_back(r);
    }
    return id;
  }
  void finish(NodeId leaf) {
    out_.status = TrialStatus::falsified;
    out_.trajectory = trajectory_from_tree(sys_, *prop_, tree_, leaf, ctx_.parameters);
  }
  void mark_changed(std::uint32_t ri) {
    if (regions_[ri].changed) return;
    regions_[ri].changed = true;
    changed_.push_back(ri);
  }
  RegionData& region(RegionId r) { return regions_[region_slot_.find(r)]; }
  bool reached(RegionId r) const { return region_slot_.find(r) != RegionSlots::kNone; }
  // w_i(q) of Sect. 3.2.3; a region not reached yet has cov = t = 1.
  double lead_weight(RegionId r) const {
    const std::uint32_t ri = region_slot_.find(r);
    if (ri == RegionSlots::kNone) return power(dec_->volume(r), o_.e.nu);
    const RegionData& rd = regions_[ri];
    return hydice_lead_weight(o_.e, rd.volume, static_cast<double>(rd.cells.size()),
                              1.0 + static_cast<double>(rd.propagations));
  }
  // Where to steer from region r: the region after r on the current lead; off the lead (or
  // without leads) the centre of a random neighbour of r in G_D.
  template <class Urbg>
  std::array<double, 2> steering_target(RegionId r, Urbg& g, std::vector<RegionId>& nb) const {
    auto it = lead_position_.find(r);
    if (it != lead_position_.end() && it->second + 1 < current_lead_.size())
      return dec_->centre(current_lead_[it->second + 1]);
    dec_->neighbors(r, nb);
    if (nb.empty()) return dec_->centre(r);
    return dec_->centre(nb[std::uniform_int_distribution<std::size_t>(0, nb.size() - 1)(g)]);
  }

  const HydiceOptions& o_;
  const PlannerContext& ctx_;
  const System& sys_;
  const SystemInfo& info_;
  const Decomposition* dec_;
  PlannerOutcome& out_;
  PlannerCounters& c_;
  const std::size_t m_;
  std::unique_ptr<Propagator> prop_;
  const SearchBudget budget_;
  Rng rng_;
  const double cell_;
  NodeStore tree_;
  // The reached regions' data, indexed through a RegionSlots (dense arrays on a dense
  // decomposition: the lead weight is read for every region the lead search touches).
  RegionSlots region_slot_;
  std::vector<RegionData> regions_;
  std::unordered_map<CellKey, std::uint32_t, CellKeyHash> cell_index_;
  std::vector<Cell> cells_;
  std::vector<RegionId> avail_;  // D_avail
  std::vector<RegionId> start_regions_, current_lead_;
  std::unordered_map<RegionId, std::size_t> lead_position_;
  double unreached_edge_cost_ = 0.0;
  LeadSearch lead_search_;
  RegionSlots snap_slots_;  // the reached regions when the lead weights were frozen
  std::vector<double> snap_w_;
  std::vector<std::uint32_t> changed_;  // regions with `changed` set
  const bool draw_box_;
  std::int64_t leads_ = 0, random_leads_ = 0, failed_leads_ = 0, expansions_ = 0, random_expansions_ = 0;
};

// The budget (wall clock, node cap) is read every 16 motion steps: a step is one or a few
// propagations (10-40 µs each on navigation), so the deadline is overshot by well under a
// millisecond, and the clock is not read per propagation (each propagation also polls the
// budget's interrupt, so a late one ends as rejected anyway).
constexpr std::int64_t kBudgetCheckEvery = 16;

// The sequential motion step (batch = 1), the paper's Alg. 2:8-14: one selection and its
// propagation(s) at a time, against the live estimates, with the trial's one RNG stream.
class SequentialStep {
 public:
  void grow(HydiceSearch& search, std::int64_t steps) {
    for (std::int64_t k = 0; k < steps && !search.done(); ++k) {
      if (k > 0 && k % kBudgetCheckEvery == 0 && search.out_of_budget()) break;
      search.selection_weights(wsel_);
      search.draw(search.rng(), wsel_, draw_);
      search.propagate(search.propagator(), draw_, outcome_);
      if (search.commit(draw_, outcome_) && !search.done()) break;  // the node cap
    }
  }

 private:
  std::vector<double> wsel_;
  HydiceSearch::Draw draw_;
  HydiceSearch::Outcome outcome_;
};

// The batch motion step (batch = B > 1, core/search/parallel_slots.hpp): see the header.
class BatchStep {
 public:
  BatchStep(const System& sys, const SearchBudget& budget, std::size_t batch) : slots_(batch) {
    for (Slot& s : slots_) {
      s.prop = sys.make_propagator();
      s.prop->set_interrupt(budget.interrupt());
    }
  }
  void grow(HydiceSearch& search, std::int64_t steps) {
    const std::size_t batch = slots_.size();
    const std::uint64_t seed = search.ctx().seed;
    // A slot's choice of inputs and its propagation run in parallel; so does the seeding of its
    // stream for the next round, whose first value is drawn there too (seeding an mt19937_64
    // and its first twist take ~2 µs a slot: 7.5 % of a batch-8 trial's CPU under perf, all of
    // it serial before).
    auto body = [&](std::size_t s) {
      Slot& sl = slots_[s];
      search.choose(sl.stream, sl.draw);
      search.propagate(*sl.prop, sl.draw, sl.outcome);
      sl.prepare(seed, round_, s);
    };
    // Rounds of ~100 µs: a helper stands by for the whole growth (SlotRounds) rather than a
    // fork and join per round.
    with_slot_rounds(search.ctx().cpu, [&](SlotRounds& rounds) {
      for (std::int64_t k = 0; k < steps && !search.done(); k += static_cast<std::int64_t>(batch)) {
        if (k > 0 && search.out_of_budget()) break;
        // Select (region, cell, state), in slot order, each slot with its own stream, against
        // the estimates of the round's start (t(D) and cov(D) change only in the commits below).
        search.selection_weights(wsel_);
        for (std::size_t s = 0; s < batch; ++s) {
          if (slots_[s].prepared != round_) slots_[s].prepare(seed, round_, s);
          search.select(slots_[s].stream, wsel_, slots_[s].draw);
        }
        ++round_;
        // Choose the inputs and propagate in parallel, against the tree as the round found it.
        // Commit in slot order, each slot as soon as it has run (the bodies read only the tree's
        // existing rows, which the lock-free store never moves, and nothing else commit
        // writes); the first slot reaching the unsafe set ends the search, and the node cap is
        // checked before each commit so that it is exact.
        bool ended = false;
        rounds.run(batch, body, [&](std::size_t s) {
          if (search.at_node_cap()) return true;
          return ended = search.commit(slots_[s].draw, slots_[s].outcome);
        });
        if (ended || search.at_node_cap()) break;
      }
    });
  }

 private:
  // Rng(slot_seed(seed, round, slot)) with its first value drawn ahead: the same sequence.
  struct PrimedStream {
    using result_type = Rng::result_type;
    static constexpr result_type min() { return Rng::min(); }
    static constexpr result_type max() { return Rng::max(); }
    result_type operator()() {
      if (fresh) {
        fresh = false;
        return first;
      }
      return g();
    }
    Rng g;
    result_type first = 0;
    bool fresh = false;
  };
  struct Slot {
    std::unique_ptr<Propagator> prop;
    HydiceSearch::Draw draw;
    HydiceSearch::Outcome outcome;
    PrimedStream stream;
    std::uint64_t prepared = std::numeric_limits<std::uint64_t>::max();  // the round `stream` is for
    void prepare(std::uint64_t seed, std::uint64_t round, std::size_t s) {
      stream.g.seed(slot_seed(seed, round, s));
      stream.first = stream.g();
      stream.fresh = true;
      prepared = round;
    }
  };
  std::vector<Slot> slots_;
  std::vector<double> wsel_;
  std::uint64_t round_ = 0;
};

class Hydice final : public Planner {
 public:
  explicit Hydice(HydiceOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_hydice_system(ctx.system, Json());
    PlannerOutcome out;
    HydiceSearch search(o_, ctx, out);
    if (o_.batch <= 1) {
      SequentialStep step;
      search.run(step);
    } else {
      BatchStep step(ctx.system, search.budget(), static_cast<std::size_t>(o_.batch));
      search.run(step);
    }
    if (ctx.trees) ctx.trees->add(0, search.tree());  // --save-trees: after the search, a copy
    return out;
  }

 private:
  HydiceOptions o_;
};

std::vector<OptionSpec> exponent_options() {
  return {{"controls", 1,
           "inputs drawn per selected state; the end state nearest the next lead region is kept (1: the paper's one "
           "random input)",
           "[1, 1024]"},
          {"inputs", "auto",
           "how an input is drawn: box (uniform over the admissible box), set (a random element of the suite's Ū), "
           "auto (as the suite declares: box for navigation's drivers, set otherwise)",
           "auto|set|box"},
          {"nu", 1.0, "ν: exponent of vol in w = vol^ν cov^ζ / t^τ and w_sel = vol^ν / (t^τ cov^ζ)", "[0, 10]"},
          {"zeta", 2.0, "ζ: exponent of cov (coverage cells of the region)", "[0, 10]"},
          {"tau", 0.5, "τ: exponent of t (1 + propagations from the region)", "[0, 10]"},
          batch_option()};
}

}  // namespace

MethodEntry hydice_method() {
  auto options = exponent_options();
  options.push_back({"t_sigma", 100, "t_σ: propagations per lead (motion-planning step)", "[1, 100000000]"});
  options.push_back(
      {"shortest_probability", 0.9, "probability that a lead is the shortest path (else a random path)", "[0, 1]"});
  options.push_back(
      {"lead_heuristic", 1.0, "A* weight on hops_to_unsafe x (cost of an unreached edge); 0 = Dijkstra", "[0, 100]"});
  return {"hydice", "HyDICE of seed 002 (Alg. 2): leads over the suite's region decomposition guide the motion planner",
          std::move(options), [](const Json& o) { return std::make_unique<Hydice>(parse_options(o, true)); },
          check_hydice_system};
}

MethodEntry hydice_noleads_method() {
  return {"hydice-noleads",
          "HyDICE[NoLeads] of seed 002 Sect. 4: HyDICE's motion planner over every reached region, no discrete search",
          exponent_options(), [](const Json& o) { return std::make_unique<Hydice>(parse_options(o, false)); },
          check_hydice_system};
}

}  // namespace hyfal
