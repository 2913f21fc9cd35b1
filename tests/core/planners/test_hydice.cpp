// HyDICE (core/planners/hydice, seed 002 Sect. 3): leads on a hand-made decomposition graph,
// the weight and selection formulas, D_avail, and HyDICE / HyDICE[NoLeads] falsifying small
// navigation instances with witnesses that validate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <limits>
#include <set>
#include <string>

#include <fmt/format.h>

#include "core/search/input_grid.hpp"
#include "core/run/option_spec.hpp"
#include "core/planners/hydice/hydice.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/navigation/navigation.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

// A hand graph: 0 - 1 - 5 (short) and 0 - 3 - 4 - 5 (long); 5 is unsafe; 2 is a dead end off 1.
class FakeDecomposition final : public Decomposition {
 public:
  FakeDecomposition() {
    auto edge = [&](RegionId a, RegionId b) {
      adj_[a].push_back(b);
      adj_[b].push_back(a);
    };
    edge(0, 1);
    edge(1, 5);
    edge(1, 2);
    edge(0, 3);
    edge(3, 4);
    edge(4, 5);
    edge(7, 8);
  }
  RegionId region_of(Mode, std::span<const double> x) const override { return static_cast<RegionId>(x[0]); }
  double volume(RegionId) const override { return 1.0; }
  void neighbors(RegionId r, std::vector<RegionId>& out) const override {
    auto it = adj_.find(r);
    out = it == adj_.end() ? std::vector<RegionId>{} : it->second;
  }
  bool is_unsafe(RegionId r) const override { return r == 5; }
  void project(Mode, std::span<const double> x, std::span<double, 2> out) const override {
    out[0] = x[0];
    out[1] = 0.0;
  }
  double cell_size() const override { return 0.1; }
  // The exact G_D distance to region 5 (an admissible A* heuristic); the island 7 - 8 has none.
  double hops_to_unsafe(RegionId r) const override {
    static const std::map<RegionId, double> hops{{0, 2}, {1, 1}, {2, 2}, {3, 2}, {4, 1}, {5, 0}};
    auto it = hops.find(r);
    return it == hops.end() ? std::numeric_limits<double>::infinity() : it->second;
  }
  bool adjacent(RegionId a, RegionId b) const {
    const auto& v = adj_.at(a);
    return std::find(v.begin(), v.end(), b) != v.end();
  }

 private:
  std::map<RegionId, std::vector<RegionId>> adj_;
};

TEST(HydiceLead, ShortestPathFollowsTheWeights) {
  const FakeDecomposition d;
  const std::vector<RegionId> starts{0};
  // Equal weights: the fewest edges.
  EXPECT_EQ(hydice_lead(d, starts, [](RegionId) { return 1.0; }, nullptr), (std::vector<RegionId>{0, 1, 5}));
  // Region 1 nearly exhausted (w = 0.01): 1/(w0 w1) + 1/(w1 w5) = 200 > 3 for the long way.
  EXPECT_EQ(hydice_lead(d, starts, [](RegionId r) { return r == 1 ? 0.01 : 1.0; }, nullptr),
            (std::vector<RegionId>{0, 3, 4, 5}));
  // Edge cost 1/(w_i w_j): the short way costs 2/w1 against 3 for the long way, so w1 = 0.6
  // (3.33) still takes the long way and w1 = 0.7 (2.86) the short one.
  EXPECT_EQ(hydice_lead(d, starts, [](RegionId r) { return r == 1 ? 0.6 : 1.0; }, nullptr),
            (std::vector<RegionId>{0, 3, 4, 5}));
  EXPECT_EQ(hydice_lead(d, starts, [](RegionId r) { return r == 1 ? 0.7 : 1.0; }, nullptr),
            (std::vector<RegionId>{0, 1, 5}));
  // Start inside the unsafe region: the lead is that region alone.
  const std::vector<RegionId> at_goal{5};
  EXPECT_EQ(hydice_lead(d, at_goal, [](RegionId) { return 1.0; }, nullptr), (std::vector<RegionId>{5}));
  // No unsafe region reachable.
  const std::vector<RegionId> nowhere{42};
  EXPECT_TRUE(hydice_lead(d, nowhere, [](RegionId) { return 1.0; }, nullptr).empty());
}

TEST(HydiceLead, AStarFindsTheDijkstraLeadAndPrunesUnreachableRegions) {
  const FakeDecomposition d;
  const std::vector<RegionId> starts{0};
  LeadSearch search;  // one workspace for every search below, as the planner uses it
  for (const double w1 : {0.01, 0.6, 0.7, 1.0, 5.0}) {
    const auto weight = [w1](RegionId r) { return r == 1 ? w1 : 1.0; };
    const auto dijkstra = hydice_lead(d, starts, weight, nullptr, 0.0);
    // h = hops x (the cheapest edge cost, 1 / max(w)^2): admissible, so A* is exact.
    const double cheapest = 1.0 / std::pow(std::max(1.0, w1), 2);
    EXPECT_EQ(search.find(d, starts, weight, nullptr, cheapest), dijkstra) << w1;
    EXPECT_LE(search.expanded(), 6u);
  }
  // With the heuristic along the short way the search expands the lead and nothing else.
  EXPECT_EQ(search.find(d, starts, [](RegionId) { return 1.0; }, nullptr, 1.0), (std::vector<RegionId>{0, 1, 5}));
  EXPECT_EQ(search.expanded(), 2u);  // 0 and 1; 5 ends the search when popped
  // A start with no path to an unsafe region (hops = inf) is pruned at once.
  const std::vector<RegionId> island{7};
  EXPECT_TRUE(search.find(d, island, [](RegionId) { return 1.0; }, nullptr, 1.0).empty());
  EXPECT_EQ(search.expanded(), 0u);
}

TEST(HydiceLead, RandomPathsAreValidAndTakeBothWays) {
  const FakeDecomposition d;
  const std::vector<RegionId> starts{0};
  Rng rng(7);
  int short_way = 0, long_way = 0;
  for (int i = 0; i < 400; ++i) {
    const auto lead = hydice_lead(d, starts, {}, &rng);
    ASSERT_GE(lead.size(), 2u);
    EXPECT_EQ(lead.front(), 0u);
    EXPECT_EQ(lead.back(), 5u);
    for (std::size_t k = 1; k < lead.size(); ++k) EXPECT_TRUE(d.adjacent(lead[k - 1], lead[k]));
    (lead.size() == 3 ? short_way : long_way)++;
  }
  EXPECT_GT(short_way, 40);
  EXPECT_GT(long_way, 40);
}

TEST(HydiceWeights, Formulas) {
  const HydiceExponents unit{1.0, 1.0, 1.0};
  EXPECT_DOUBLE_EQ(hydice_lead_weight(unit, 0.25, 4.0, 2.0), 0.5);          // vol cov / t
  EXPECT_DOUBLE_EQ(hydice_selection_weight(unit, 0.25, 4.0, 2.0), 0.03125);  // vol / (t cov)
  const HydiceExponents e{2.0, 0.5, 3.0};
  EXPECT_DOUBLE_EQ(hydice_lead_weight(e, 0.5, 16.0, 2.0), 0.25 * 4.0 / 8.0);
  EXPECT_DOUBLE_EQ(hydice_selection_weight(e, 0.5, 16.0, 2.0), 0.25 / (8.0 * 4.0));
  // More coverage: higher lead weight, lower selection weight; more time: both lower.
  EXPECT_GT(hydice_lead_weight(unit, 1, 5, 1), hydice_lead_weight(unit, 1, 4, 1));
  EXPECT_LT(hydice_selection_weight(unit, 1, 5, 1), hydice_selection_weight(unit, 1, 4, 1));
  EXPECT_LT(hydice_lead_weight(unit, 1, 4, 3), hydice_lead_weight(unit, 1, 4, 2));
  EXPECT_LT(hydice_selection_weight(unit, 1, 4, 3), hydice_selection_weight(unit, 1, 4, 2));
}

TEST(HydiceSelection, CellsByInverseSquareSelectionsAndWeightedPick) {
  Rng rng(3);
  const std::vector<std::uint32_t> sel{0, 1};  // weights 1 and 1/4: P(0) = 0.8
  int zero = 0;
  const int draws = 20000;
  for (int i = 0; i < draws; ++i) zero += hydice_pick_cell(sel, rng) == 0;
  EXPECT_NEAR(zero / double(draws), 0.8, 0.015);
  const std::vector<double> w{0.0, 3.0, 1.0};
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < draws; ++i) ++counts[hydice_pick_weighted(w, rng)];
  EXPECT_EQ(counts[0], 0);
  EXPECT_NEAR(counts[1] / double(draws), 0.75, 0.015);
}

TEST(HydiceSelection, AvailableRegionsScanTheLeadBackwards) {
  Rng rng(5);
  const std::vector<RegionId> lead{0, 1, 2, 3};
  // Only 0 and 1 reached: 1 is met first (|D_avail| = 0, probability 1), 0 joins with 1/2.
  auto reached = [](RegionId r) { return r <= 1; };
  int with_zero = 0;
  const int draws = 20000;
  for (int i = 0; i < draws; ++i) {
    const auto a = hydice_available(lead, reached, rng);
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a.front(), 1u);
    with_zero += a.size() == 2;
  }
  EXPECT_NEAR(with_zero / double(draws), 0.5, 0.015);
  // All reached: the last region of the lead is always available.
  for (int i = 0; i < 100; ++i) EXPECT_EQ(hydice_available(lead, [](RegionId) { return true; }, rng).front(), 3u);
}

// --- navigation --------------------------------------------------------------------------------

using Sets = std::vector<std::pair<std::string, std::string>>;

std::shared_ptr<const System> make(const Sets& sets) {
  const SuiteEntry* s = find_suite("navigation");
  return s->make(resolve_options(s->parameters, sets));
}

// The property of instance (n, seed) whose terrain route (BFS over open passages) is shortest,
// preferring routes without the slow SDDrive terrains.
int short_property(int n, std::uint64_t seed) {
  const NavigationInstance g = NavigationInstance::generate(n, seed, 1.0);
  int best = -1;
  std::pair<int, int> best_key{1 << 30, 1 << 30};
  for (int i = 0; i < NavigationInstance::kProperties; ++i) {
    const auto pr = g.properties()[i];
    std::vector<int> prev(g.terrains(), -2);
    std::deque<Mode> queue{pr.start};
    prev[pr.start] = -1;
    while (!queue.empty()) {
      const Mode q = queue.front();
      queue.pop_front();
      for (NavSide s : {NavSide::east, NavSide::north, NavSide::west, NavSide::south}) {
        if (!g.open(q, s)) continue;
        const Mode r = g.neighbour(q, s);
        if (prev[r] != -2) continue;
        prev[r] = static_cast<int>(q);
        queue.push_back(r);
      }
    }
    int length = 0, slow = 0;
    for (int q = prev[pr.unsafe]; q != -1; q = prev[q]) {
      ++length;
      slow += g.vehicle(static_cast<Mode>(q)) == NavVehicle::sddrive;
    }
    const std::pair<int, int> key{slow, length};
    if (key < best_key) {
      best_key = key;
      best = i;
    }
  }
  return best;
}

TEST(HydiceNavigation, NavigationProvidesADecomposition) {
  auto sys = make({{"n", "4"}});
  const Decomposition* d = sys->decomposition();
  ASSERT_NE(d, nullptr);
  const auto maze = navigation_instance(*sys);
  // Regions of terrain q: 4 of them; neighbours never cross a wall.
  std::vector<RegionId> nb;
  for (Mode q = 0; q < maze->terrains(); ++q) {
    const auto c = maze->centre(q);
    const std::vector<double> x{c[0] - 0.25, c[1] - 0.25, 0, 0, 0};
    const RegionId r = d->region_of(q, x);
    EXPECT_EQ(r / 4, q);
    EXPECT_DOUBLE_EQ(d->volume(r), 0.25);
    d->neighbors(r, nb);
    for (RegionId s : nb) {
      const Mode q2 = s / 4;
      if (q2 == q) continue;
      bool via_open = false;
      for (NavSide side : {NavSide::east, NavSide::north, NavSide::west, NavSide::south})
        via_open = via_open || (maze->open(q, side) && maze->neighbour(q, side) == q2);
      EXPECT_TRUE(via_open) << q << " -> " << q2;
    }
  }
  const Mode unsafe = maze->properties()[0].unsafe;
  EXPECT_TRUE(d->is_unsafe(unsafe * 4 + 3));
  EXPECT_FALSE(d->is_unsafe(maze->properties()[0].start * 4));
  EXPECT_EQ(find_suite("thermostat")->make(resolve_options(find_suite("thermostat")->parameters, {}))->decomposition(),
            nullptr);
}

void falsify(const char* method, int n, std::uint64_t seed, const char* driver = "random", int property = -1) {
  if (property < 0) property = short_property(n, seed);
  auto sys = make({{"n", std::to_string(n)}, {"seed", std::to_string(seed)}, {"property", std::to_string(property)},
                   {"driver", driver}});
  auto planner = find_method(method)->make(resolve_options(find_method(method)->options, {}));
  const PlannerContext ctx{*sys, sys->info().parameters, 2024, PlannerLimits{8.0, 2'000'000}, {}};
  const PlannerOutcome out = planner->solve(ctx);
  ASSERT_EQ(out.status, TrialStatus::falsified) << method << " n = " << n << ": " << out.counters.nodes << " nodes";
  ASSERT_TRUE(out.trajectory);
  Witness w;
  w.suite = sys->info().suite;
  w.instance = sys->info().instance;
  w.method = method;
  w.state_names = sys->info().state_names;
  w.input_names = sys->info().input_names;
  w.trajectory = *out.trajectory;
  const ValidationReport report = validate_witness(*sys, w);
  EXPECT_TRUE(report.valid) << report.reason;
  EXPECT_LE(report.final_spec, 1e-6);
  std::printf("[hydice] %s %s n = %d seed %d property %d: %lld nodes, %zu pieces, %s regions\n", method, driver, n,
              static_cast<int>(seed), property, static_cast<long long>(out.counters.nodes),
              out.trajectory->pieces.size(), out.metrics["regions_reached"].dump().c_str());
  // Deterministic from the seed.
  const PlannerOutcome again = find_method(method)->make(resolve_options(find_method(method)->options, {}))->solve(ctx);
  EXPECT_EQ(again.counters.nodes, out.counters.nodes);
  EXPECT_EQ(again.trajectory->final_x, out.trajectory->final_x);
}

TEST(HydiceNavigation, HydiceFalsifiesN4AndN8) {
  falsify("hydice", 4, 1);
  falsify("hydice", 8, 1);
}

TEST(HydiceNavigation, NoLeadsFalsifiesN4AndN8) {
  falsify("hydice-noleads", 4, 1);
  falsify("hydice-noleads", 8, 1);
}

TEST(HydiceNavigation, HydiceFalsifiesUnderEveryDriverAndALongerRoute) {
  // The witness validator checks each piece's u against the driver's interval at x_start.
  falsify("hydice", 8, 1, "student");
  falsify("hydice", 8, 1, "highway");
  falsify("hydice", 32, 1, "random", 0);  // property 0: the route crosses tens of terrains
}

// hops_to_unsafe is the region distance in G_D (a breadth-first search over d.neighbors here,
// independent of the decomposition's packed level-by-level one), at least the terrain distance
// in the maze and at most twice it plus one (a terrain is crossed in one or two region edges).
TEST(HydiceNavigation, HopsToUnsafeIsTheRegionDistance) {
  for (int n : {1, 16, 37}) {
    for (int property : {0, 3}) {
      auto sys = make({{"n", std::to_string(n)}, {"property", std::to_string(property)}});
      const Decomposition* d = sys->decomposition();
      const auto maze = navigation_instance(*sys);
      const auto pr = maze->properties()[property];
      const Mode unsafe = maze->place_mode(pr.unsafe);  // n = 1: the places are quarters of terrain 0
      std::vector<int> dist(maze->terrains(), -1);
      std::deque<Mode> queue{unsafe};
      dist[unsafe] = 0;
      while (!queue.empty()) {
        const Mode q = queue.front();
        queue.pop_front();
        for (NavSide side : {NavSide::east, NavSide::north, NavSide::west, NavSide::south})
          if (maze->open(q, side) && dist[maze->neighbour(q, side)] < 0) {
            dist[maze->neighbour(q, side)] = dist[q] + 1;
            queue.push_back(maze->neighbour(q, side));
          }
      }
      std::vector<int> rdist(maze->terrains() * 4, -1);
      std::deque<RegionId> rq;
      for (RegionId r = 0; r < rdist.size(); ++r)
        if (d->is_unsafe(r)) {
          rdist[r] = 0;
          rq.push_back(r);
        }
      ASSERT_FALSE(rq.empty());
      std::vector<RegionId> nb;
      while (!rq.empty()) {
        const RegionId r = rq.front();
        rq.pop_front();
        d->neighbors(r, nb);
        for (RegionId s : nb)
          if (rdist[s] < 0) {
            rdist[s] = rdist[r] + 1;
            rq.push_back(s);
          }
      }
      int longer = 0;
      for (Mode q = 0; q < maze->terrains(); ++q) {
        const int manhattan = std::abs(maze->row(q) - maze->row(unsafe)) + std::abs(maze->col(q) - maze->col(unsafe));
        for (RegionId r = q * 4; r < q * 4 + 4; ++r) {
          const std::string what = fmt::format("n={} property {} region {}", n, property, r);
          ASSERT_GE(rdist[r], 0) << what;  // every terrain is connected (spanning-tree maze)
          EXPECT_EQ(d->hops_to_unsafe(r), rdist[r]) << what;
          if (n == 1) continue;  // one terrain: the quarters, all one edge from the unsafe one
          EXPECT_GE(rdist[r], dist[q]) << what;
          EXPECT_GE(rdist[r], manhattan) << what;
          EXPECT_LE(rdist[r], 2 * dist[q] + 1) << what;
          longer += rdist[r] > dist[q] + 1;
        }
      }
      if (n > 1) {
        EXPECT_GT(longer, 0) << "n=" << n;  // the terrain distance would not be as tight
      }
    }
  }
  // An unreachable region gets inf: no such region in a spanning-tree maze, so the unsafe
  // regions themselves check the other end: 0.
  auto sys = make({{"n", "4"}});
  const Decomposition* d = sys->decomposition();
  for (RegionId r = 0; r < 64; ++r)
    if (d->is_unsafe(r)) {
      EXPECT_EQ(d->hops_to_unsafe(r), 0.0);
    }
}

TEST(NavigationDriverInputs, GridMapsOntoTheDriverIntervalAndValidatorChecksIt) {
  auto sys = make({{"n", "4"}, {"driver", "student"}});
  ASSERT_TRUE(sys->state_dependent_inputs());
  EXPECT_FALSE(make({{"n", "4"}})->state_dependent_inputs());  // RandomDriver: U itself
  const auto maze = navigation_instance(*sys);
  Mode car = 0;
  while (maze->vehicle(car) != NavVehicle::scar) ++car;
  // SCar at 1.5 m/s (a = 0.5): StudentDriver brakes, u0 in [-0.8, -0.64]; u1 free.
  const std::vector<double> x{0.5, 0.5, 0.0, 1.5, 0.0};
  InputGrid grid(*sys);
  grid.at(car, x);
  ASSERT_EQ(grid.count(), 9u);
  std::set<double> u0;
  for (std::size_t j = 0; j < grid.count(); ++j) {
    u0.insert(grid.input(j)[0]);
    EXPECT_GE(grid.input(j)[0], -0.8);
    EXPECT_LE(grid.input(j)[0], -0.64);
  }
  ASSERT_EQ(u0.size(), 3u);  // levels keep their places, endpoints exact
  EXPECT_EQ(*u0.begin(), -0.8);
  EXPECT_NEAR(*std::next(u0.begin()), -0.72, 1e-15);
  EXPECT_EQ(*u0.rbegin(), navigation_driver_interval(NavDriver::student, NavVehicle::scar, x).hi[0]);

  // A HyDICE witness under StudentDriver validates; with one input moved outside the driver's
  // interval (still inside U) it does not.
  const int property = short_property(8, 1);
  // T = 1 s: a longer witness, so that some piece starts where the driver narrows U.
  auto s8 = make({{"n", "8"}, {"driver", "student"}, {"property", std::to_string(property)}, {"step", "1"}});
  auto planner = find_method("hydice")->make(resolve_options(find_method("hydice")->options, {}));
  const PlannerOutcome out = planner->solve(PlannerContext{*s8, s8->info().parameters, 7, PlannerLimits{8.0, 2'000'000}, {}});
  ASSERT_EQ(out.status, TrialStatus::falsified);
  Witness w;
  w.suite = "navigation";
  w.instance = s8->info().instance;
  w.method = "hydice";
  w.state_names = s8->info().state_names;
  w.input_names = s8->info().input_names;
  w.trajectory = *out.trajectory;
  ASSERT_TRUE(validate_witness(*s8, w).valid);
  bool moved = false;
  for (auto& piece : w.trajectory.pieces) {
    std::vector<double> lo(2), hi(2);
    s8->input_bounds(piece.mode, piece.x_start, lo, hi);
    const Box& box = s8->inputs(piece.mode).box;
    for (int k = 0; k < 2 && !moved; ++k) {
      if (hi[k] < box.hi[k] - 1e-3) {
        piece.u[k] = box.hi[k];
        moved = true;
      } else if (lo[k] > box.lo[k] + 1e-3) {
        piece.u[k] = box.lo[k];
        moved = true;
      }
    }
    if (moved) break;
  }
  ASSERT_TRUE(moved) << "no piece with a driver interval narrower than U";
  const ValidationReport bad = validate_witness(*s8, w);
  EXPECT_FALSE(bad.valid);
  EXPECT_NE(bad.reason.find("admissible"), std::string::npos) << bad.reason;
}

}  // namespace
}  // namespace hyfal
