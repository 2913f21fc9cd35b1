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
//    h(r) = `lead_heuristic` x Decomposition::hops_to_unsafe(r) x c, c = the cost of an edge
//    between two unreached regions (1 for random paths): exact on unreached ground, where
//    the lead leaves the tree, and an overestimate inside a well-covered tree, where it makes
//    the search greedy. Regions with no path to an unsafe one (hops = inf) are never queued.
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
#include <queue>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

#include "core/inputs.hpp"
#include "core/tree.hpp"

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
    else table_.assign(std::size_t{1} << 12, HashSlot{});
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
  expanded_ = 0;
  // A*: ordered by f = dist + h, ties to the smaller h (the deeper region), h = hops_to_unsafe
  // * heuristic_edge_cost; a region with no path to an unsafe one (hops = inf) is never queued.
  auto h_of = [&](RegionId r) {
    const double hops = d.hops_to_unsafe(r);
    if (std::isinf(hops)) return hops;
    return heuristic_edge_cost > 0.0 ? heuristic_edge_cost * hops : 0.0;
  };
  open_.clear();
  // The open list is an indexed 4-ary heap with decrease-key: each queued region has exactly
  // one item holding its current f, so the pops come out in the same order as the lazy binary
  // heap this replaced (the order (f, h, entry) is total: h is fixed per entry, and an entry's
  // f only ever strictly decreases), with no stale items and a shallower heap.
  auto place = [&](std::size_t i, const OpenItem& it) {
    open_[i] = it;
    entries_[it.entry].heap_pos = static_cast<std::uint32_t>(i);
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
    const std::uint32_t top = open_[0].entry;
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
        for (std::size_t c = first + 1; c < end; ++c)
          if (open_[best] > open_[c]) best = c;
        if (!(last > open_[best])) break;
        place(i, open_[best]);
        i = best;
      }
      place(i, last);
    }
    entries_[top].heap_pos = kNotQueued;
    return top;
  };
  auto push = [&](const OpenItem& it) {  // a new item, or a smaller f for a queued entry
    const std::uint32_t at = entries_[it.entry].heap_pos;
    if (at == kNotQueued) {
      open_.push_back(it);
      sift_up(open_.size() - 1, it);
    } else {
      sift_up(at, it);
    }
  };
  for (RegionId s : starts) {
    const double hs = h_of(s);
    if (std::isinf(hs)) continue;
    bool fresh;
    const std::uint32_t k = entry_of(s, fresh);
    if (!fresh) continue;  // a duplicate start
    entries_[k].h = hs;
    push(OpenItem{hs, hs, k});
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
        entries_[j].h = h_of(s);
      } else if (entries_[j].done) {
        continue;
      }
      if (std::isinf(entries_[j].h)) continue;
      const double cost = rng ? 1.0 - unit(*rng) : 1.0 / (wr * w_of(j));
      const double nd = dist + cost;
      if (!fresh && !(nd < entries_[j].dist)) continue;
      entries_[j].dist = nd;
      entries_[j].parent = k;
      push(OpenItem{nd + entries_[j].h, entries_[j].h, j});
    }
  }
  return {};
}

std::vector<RegionId> hydice_lead(const Decomposition& d, std::span<const RegionId> starts,
                                  const std::function<double(RegionId)>& weight, Rng* rng,
                                  double heuristic_edge_cost, std::size_t max_expanded) {
  LeadSearch search;
  return search.find(d, starts, weight, rng, heuristic_edge_cost, max_expanded);
}

std::vector<RegionId> hydice_available(std::span<const RegionId> lead,
                                       const std::function<bool(RegionId)>& reached, Rng& rng) {
  std::vector<RegionId> avail;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = lead.size(); i-- > 0;) {
    if (!reached(lead[i])) continue;
    if (std::find(avail.begin(), avail.end(), lead[i]) != avail.end()) continue;
    if (unit(rng) * static_cast<double>(1 + avail.size()) < 1.0) avail.push_back(lead[i]);
  }
  return avail;
}

std::size_t hydice_pick_weighted(std::span<const double> w, Rng& rng) {
  double total = 0.0;
  for (double x : w) total += x;
  double r = std::uniform_real_distribution<double>(0.0, total)(rng);
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (r < w[i]) return i;
    r -= w[i];
  }
  for (std::size_t i = w.size(); i-- > 0;)  // rounding: the last positive weight
    if (w[i] > 0.0) return i;
  return 0;
}

std::size_t hydice_pick_cell(std::span<const std::uint32_t> selections, Rng& rng) {
  std::vector<double> w(selections.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double n = 1.0 + selections[i];
    w[i] = 1.0 / (n * n);
  }
  return hydice_pick_weighted(w, rng);
}

namespace {

// One propagation (~10-40 µs on the navigation vehicles) costs about as much as 50 region
// expansions of the lead search (~0.3 µs each): t_σ >= expanded / 50 keeps leads <= ~50 % of
// the time.
constexpr std::int64_t kExpansionsPerPropagation = 50;

// The values come only from the resolved options (their defaults and ranges are declared once, in
// exponent_options() and hydice_method() below); no default is repeated here.
struct HydiceOptions {
  bool leads;
  std::int64_t t_sigma;
  double shortest_probability;
  double lead_heuristic;
  std::int64_t controls;
  enum class Inputs { automatic, set, box } inputs;
  HydiceExponents e;
};

// `o` is resolved against the declared options (core/options.hpp checks types and ranges).
HydiceOptions parse_options(const Json& o, bool leads) {
  HydiceOptions h{};
  h.leads = leads;
  h.e.nu = o.at("nu").get<double>();
  h.e.zeta = o.at("zeta").get<double>();
  h.e.tau = o.at("tau").get<double>();
  h.controls = o.at("controls").get<std::int64_t>();
  const std::string inputs = o.at("inputs").get<std::string>();
  if (inputs == "auto") h.inputs = HydiceOptions::Inputs::automatic;
  else if (inputs == "set") h.inputs = HydiceOptions::Inputs::set;
  else if (inputs == "box") h.inputs = HydiceOptions::Inputs::box;
  else throw std::invalid_argument(fmt::format("hydice: inputs must be auto, set or box (got '{}')", inputs));
  if (leads) {  // HyDICE[NoLeads] has no lead options: t_sigma etc. stay unused
    h.t_sigma = o.at("t_sigma").get<std::int64_t>();
    h.shortest_probability = o.at("shortest_probability").get<double>();
    h.lead_heuristic = o.at("lead_heuristic").get<double>();
  }
  return h;
}

// HyDICE runs on the suite's region decomposition (seed 002 Sect. 3.2).
void check_hydice_system(const System& sys, const Json&) {
  if (!sys.decomposition())
    throw std::invalid_argument(fmt::format("suite '{}' provides no region decomposition, which HyDICE needs",
                                            sys.info().suite));
}

struct CellKey {
  RegionId region;
  std::int64_t ix, iy;
  bool operator==(const CellKey&) const = default;
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(splitmix64(k.region ^ splitmix64(static_cast<std::uint64_t>(k.ix) ^
                                                                     splitmix64(static_cast<std::uint64_t>(k.iy)))));
  }
};

struct Cell {
  std::vector<NodeId> nodes;
  std::uint32_t selections = 0;
};

struct RegionData {
  double volume = 0.0;
  std::int64_t propagations = 0;  // t(D) - 1
  std::vector<std::uint32_t> cells;  // indices into the cell table
  bool available = false;
};

class Hydice final : public Planner {
 public:
  explicit Hydice(HydiceOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    const System& sys = ctx.system;
    const SystemInfo& info = sys.info();
    check_hydice_system(sys, Json());
    const Decomposition* dec = sys.decomposition();
    const std::size_t n = info.dim(), m = info.input_names.size();
    const std::span<const double> p = ctx.parameters;
    PlannerOutcome out;
    PlannerCounters& c = out.counters;
    auto prop = sys.make_propagator();
    const SearchBudget budget(ctx);
    prop->set_interrupt(budget.interrupt());  // a propagation past the deadline ends as rejected
    Rng rng(ctx.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double cell = dec->cell_size();

    NodeStore tree(n, m);
    // The reached regions' data, indexed through a RegionSlots (dense arrays on a dense
    // decomposition: the lead weight is read for every region the lead search touches).
    RegionSlots region_slot;
    region_slot.attach(*dec);
    std::vector<RegionData> regions;
    auto region = [&](RegionId r) -> RegionData& { return regions[region_slot.find(r)]; };
    std::unordered_map<CellKey, std::uint32_t, CellKeyHash> cell_index;
    std::vector<Cell> cells;
    std::vector<RegionId> avail;  // D_avail
    std::vector<double> wsel;
    std::int64_t leads = 0, random_leads = 0, failed_leads = 0, expansions = 0, random_expansions = 0;
    LeadSearch lead_search;

    auto add_node = [&](NodeId parent, Mode edge_mode, Mode mode, std::span<const double> x,
                        std::span<const double> u, double duration, int transition) {
      const NodeId id = tree.add(parent, edge_mode, mode, x, u, duration, transition);
      ++c.nodes;
      const RegionId r = dec->region_of(mode, x);
      bool fresh;
      const std::uint32_t ri = region_slot.find_or_insert(r, static_cast<std::uint32_t>(regions.size()), fresh);
      if (fresh) regions.emplace_back().volume = dec->volume(r);
      RegionData& rd = regions[ri];
      double pr[2];
      dec->project(mode, x, std::span<double, 2>(pr, 2));
      const CellKey key{r, static_cast<std::int64_t>(std::floor(pr[0] / cell)),
                        static_cast<std::int64_t>(std::floor(pr[1] / cell))};
      auto [cit, new_cell] = cell_index.try_emplace(key, static_cast<std::uint32_t>(cells.size()));
      if (new_cell) {
        cells.emplace_back();
        rd.cells.push_back(cit->second);
      }
      cells[cit->second].nodes.push_back(id);
      if (!rd.available) {  // a newly reached region joins D_avail (Sect. 3.3.1)
        rd.available = true;
        avail.push_back(r);
      }
      return id;
    };
    auto finish = [&](NodeId leaf) {
      out.status = TrialStatus::falsified;
      out.trajectory = trajectory_from_tree(sys, *prop, tree, leaf, p);
    };

    std::vector<std::vector<double>> starts{info.initial_state};
    for (const auto& x0 : info.other_initial_states) starts.push_back(x0);
    std::vector<RegionId> start_regions;
    for (const auto& x0 : starts) {
      const NodeId id = add_node(kNoNode, info.initial_mode, info.initial_mode, x0, {}, 0.0, -1);
      start_regions.push_back(dec->region_of(info.initial_mode, x0));
      if (!out.trajectory && sys.spec(info.initial_mode, x0, p) <= 0.0) finish(id);
    }

    auto lead_weight = [&](RegionId r) {
      const std::uint32_t ri = region_slot.find(r);
      if (ri == RegionSlots::kNone) return power(dec->volume(r), o_.e.nu);  // not reached: cov = t = 1
      const RegionData& rd = regions[ri];
      return hydice_lead_weight(o_.e, rd.volume, static_cast<double>(rd.cells.size()),
                                1.0 + static_cast<double>(rd.propagations));
    };
    auto reached = [&](RegionId r) { return region_slot.find(r) != RegionSlots::kNone; };
    // The cost of a G_D edge between two regions not reached yet (the start region's volume):
    // the A* heuristic's cost per hop.
    const double unreached_edge_cost = 1.0 / std::pow(std::pow(dec->volume(start_regions.front()), o_.e.nu), 2.0);

    std::vector<double> x_new(n), x_try(n), cell_w, ulo(m), uhi(m), u(m), u_best(m);
    const bool draw_box = o_.inputs == HydiceOptions::Inputs::box ||
                          (o_.inputs == HydiceOptions::Inputs::automatic && info.continuous_random_inputs);
    InputGrid grid(sys);
    std::vector<RegionId> current_lead, nb;
    std::unordered_map<RegionId, std::size_t> lead_position;
    // Where to steer from region r: the region after r on the current lead; off the lead (or
    // without leads) the centre of a random neighbour of r in G_D.
    auto steering_target = [&](const Decomposition& d, RegionId r, Rng& g, std::vector<RegionId>& buf) {
      auto it = lead_position.find(r);
      if (it != lead_position.end() && it->second + 1 < current_lead.size()) return d.centre(current_lead[it->second + 1]);
      d.neighbors(r, buf);
      if (buf.empty()) return d.centre(r);
      return d.centre(buf[std::uniform_int_distribution<std::size_t>(0, buf.size() - 1)(g)]);
    };
    std::vector<std::uint32_t> cell_sel;
    while (!out.trajectory) {
      if (auto why = budget.exhausted(c.nodes)) {
        out.status = *why;
        break;
      }
      // Alg. 2:6 — the lead and D_avail.
      std::int64_t steps = std::numeric_limits<std::int64_t>::max();
      if (o_.leads) {
        ++leads;
        std::vector<RegionId> lead;
        if (unit(rng) < o_.shortest_probability) {
          lead = lead_search.find(*dec, start_regions, lead_weight, nullptr, o_.lead_heuristic * unreached_edge_cost);
        } else {
          ++random_leads;
          lead = lead_search.find(*dec, start_regions, {}, &rng, o_.lead_heuristic * 1.0);
          random_expansions += static_cast<std::int64_t>(lead_search.expanded());
        }
        if (lead.empty()) {
          ++failed_leads;
          if (failed_leads == 1 && leads == 1) {  // no unsafe region reachable in G_D at all
            out.status = TrialStatus::not_found;
            break;
          }
          lead = start_regions;
        }
        lead_position.clear();
        for (std::size_t i = 0; i < lead.size(); ++i) lead_position.emplace(lead[i], i);
        current_lead.swap(lead);
        for (RegionId r : avail) region(r).available = false;
        avail = hydice_available(current_lead, reached, rng);
        for (RegionId r : avail) region(r).available = true;
        // t_σ: at least t_sigma propagations, more when the lead search was long, so that the
        // discrete search keeps a bounded share of the time (the paper's t_σ is wall time).
        expansions += static_cast<std::int64_t>(lead_search.expanded());
        steps = std::max<std::int64_t>(o_.t_sigma, static_cast<std::int64_t>(lead_search.expanded()) / kExpansionsPerPropagation);
      }
      // Alg. 2:8-14 — the motion-planning step.
      for (std::int64_t k = 0; k < steps && !out.trajectory; ++k) {
        if (k > 0 && k % 16 == 0 && budget.exhausted(c.nodes)) break;
        wsel.resize(avail.size());
        for (std::size_t i = 0; i < avail.size(); ++i) {
          const RegionData& rd = region(avail[i]);
          wsel[i] = hydice_selection_weight(o_.e, rd.volume, static_cast<double>(rd.cells.size()),
                                            1.0 + static_cast<double>(rd.propagations));
        }
        const RegionId selected = avail[hydice_pick_weighted(wsel, rng)];
        RegionData& rd = region(selected);
        cell_sel.resize(rd.cells.size());
        for (std::size_t i = 0; i < rd.cells.size(); ++i) cell_sel[i] = cells[rd.cells[i]].selections;
        Cell& cl = cells[rd.cells[hydice_pick_cell(cell_sel, rng)]];
        ++cl.selections;
        const NodeId s = cl.nodes[std::uniform_int_distribution<std::size_t>(0, cl.nodes.size() - 1)(rng)];
        // PropagateForward (Alg. 3) under `controls` inputs drawn uniformly from the admissible
        // box at x_s (the driver), keeping the end state nearest the steering target.
        const Mode q = tree.info(s).mode;
        const auto x_s = tree.state(s);
        if (draw_box) sys.input_bounds(q, x_s, ulo, uhi);
        else grid.at(q, x_s);
        std::array<double, 2> target{std::numeric_limits<double>::quiet_NaN(), 0.0};
        if (o_.controls > 1) target = steering_target(*dec, selected, rng, nb);
        double best = std::numeric_limits<double>::infinity();
        PropagationResult best_r;
        for (std::int64_t j = 0; j < o_.controls; ++j) {
          if (draw_box) {
            for (std::size_t i = 0; i < m; ++i) u[i] = ulo[i] + unit(rng) * (uhi[i] - ulo[i]);
          } else {
            const auto g = grid.input(std::uniform_int_distribution<std::size_t>(0, grid.count() - 1)(rng));
            std::copy(g.begin(), g.end(), u.begin());
          }
          const PropagationResult r = prop->propagate(q, x_s, u, p, info.step_duration, x_try);
          ++rd.propagations;
          ++c.propagations;
          c.integration_steps += r.steps;
          if (r.end == PropagationEnd::rejected) continue;
          if (r.duration <= 0.0 && r.end != PropagationEnd::jumped && r.end != PropagationEnd::unsafe) continue;
          double score = 0.0;
          if (!std::isnan(target[0])) {
            double pr[2];
            dec->project(r.mode, x_try, std::span<double, 2>(pr, 2));
            score = std::hypot(pr[0] - target[0], pr[1] - target[1]);
          }
          if (r.end == PropagationEnd::unsafe || r.spec <= 0.0) score = -1.0;  // a witness wins
          if (score < best) {
            best = score;
            best_r = r;
            x_new.swap(x_try);
            u_best.swap(u);
          }
        }
        if (best == std::numeric_limits<double>::infinity()) continue;
        const PropagationResult& r = best_r;
        const NodeId id = add_node(s, q, r.mode, x_new, u_best, r.duration, r.transition);
        if (r.end == PropagationEnd::unsafe || r.spec <= 0.0) finish(id);
        if (c.nodes >= ctx.limits.max_nodes) break;
      }
    }
    out.metrics["regions_reached"] = regions.size();
    out.metrics["coverage_cells"] = cells.size();
    if (o_.leads) {
      out.metrics["leads"] = leads;
      out.metrics["random_leads"] = random_leads;
      out.metrics["failed_leads"] = failed_leads;
      out.metrics["lead_expansions"] = expansions;
      out.metrics["random_lead_expansions"] = random_expansions;
    }
    return out;
  }

 private:
  HydiceOptions o_;
};

std::vector<OptionSpec> exponent_options() {
  return {{"controls", 1, "inputs drawn per selected state; the end state nearest the next lead region is kept (1: the paper's one random input)", "[1, 1024]"},
          {"inputs", "auto", "how an input is drawn: box (uniform over the admissible box), set (a random element of the suite's Ū), auto (as the suite declares: box for navigation's drivers, set otherwise)", "auto|set|box"},
          {"nu", 1.0, "ν: exponent of vol in w = vol^ν cov^ζ / t^τ and w_sel = vol^ν / (t^τ cov^ζ)", "[0, 10]"},
          {"zeta", 2.0, "ζ: exponent of cov (coverage cells of the region)", "[0, 10]"},
          {"tau", 0.5, "τ: exponent of t (1 + propagations from the region)", "[0, 10]"}};
}

}  // namespace

MethodEntry hydice_method() {
  auto options = exponent_options();
  options.push_back({"t_sigma", 100, "t_σ: propagations per lead (motion-planning step)", "[1, 100000000]"});
  options.push_back({"shortest_probability", 0.9, "probability that a lead is the shortest path (else a random path)", "[0, 1]"});
  options.push_back({"lead_heuristic", 1.0, "A* weight on hops_to_unsafe x (cost of an unreached edge); 0 = Dijkstra", "[0, 100]"});
  return {"hydice",
          "HyDICE of seed 002 (Alg. 2): leads over the suite's region decomposition guide the motion planner",
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
