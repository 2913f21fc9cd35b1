// HyDICE / HyDICE[NoLeads] at batch = 1 pinned to recorded numbers, so that work on the lead
// search, the planner's structure or the integrator that must not change results does not:
// the same leads must come out in the same A* order, so nodes, propagations, integration steps,
// lead counts, lead expansions and the witness's end state stay bit for bit what they were (the
// committed paper tables depend on it). Each trial is capped by nodes, not time, so that it is a
// deterministic function of its seed. Re-recorded once, on purpose, when the navigation
// heuristic became the region distance (issue 12, 2026-12-03: other leads, so other trials;
// HyDICE[NoLeads], which has no leads, kept its numbers); the earlier pins held through the
// dense indexing, the 4-ary heap, the Syclop-like split and the batch machinery.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/run/method_entry.hpp"
#include "core/util/rng.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/trajectory.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

struct Pinned {
  const char* method;
  int n;
  const char* driver;
  int property;
  const char* status;
  std::int64_t nodes, propagations, integration_steps, leads, lead_expansions;
  std::uint64_t end_hash;  // splitmix64 chain over the witness's final_x bits (0: no witness)
};

std::uint64_t hash_state(const std::vector<double>& x) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (double v : x) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = splitmix64(h ^ b);
  }
  return h;
}

Pinned run(const char* method, int n, const char* driver, int property, std::int64_t max_nodes) {
  const SuiteEntry* s = find_suite("navigation");
  auto sys = s->make(resolve_options(
      s->parameters, {{"n", std::to_string(n)}, {"property", std::to_string(property)}, {"driver", driver}}));
  auto planner = find_method(method)->make(resolve_options(find_method(method)->options, {}));
  const PlannerContext ctx{*sys, sys->info().parameters, 77, PlannerLimits{1e6, max_nodes}, {}};
  const PlannerOutcome out = planner->solve(ctx);
  Pinned p{method, n, driver, property, "", out.counters.nodes, out.counters.propagations,
           out.counters.integration_steps, 0, 0, 0};
  p.status = out.status == TrialStatus::falsified ? "falsified"
             : out.status == TrialStatus::node_cap ? "node_cap"
                                                   : "other";
  if (out.metrics.contains("leads")) {
    p.leads = out.metrics["leads"].get<std::int64_t>();
    p.lead_expansions = out.metrics["lead_expansions"].get<std::int64_t>();
  }
  if (out.trajectory) p.end_hash = hash_state(out.trajectory->final_x);
  return p;
}

// See test_hydice_pinned.inc for when they were recorded.
const Pinned kPinned[] = {
#include "test_hydice_pinned.inc"
};

// The default test set runs the cheaper pins (n = 64, the falsifying Random and Highway trials
// and one HyDICE[NoLeads] run: a few seconds); HYFAL_LONG_TESTS=1 runs every pin (about 40 s in
// Release: the n = 256 trials and the node-capped ones).
bool long_tests() { return std::getenv("HYFAL_LONG_TESTS") != nullptr; }

bool cheap(const Pinned& p) {
  if (p.n != 64) return false;
  if (std::string(p.method) == "hydice-noleads") return std::string(p.driver) == "random";
  return std::string(p.status) == "falsified" && std::string(p.driver) != "student" && p.nodes < 25'000;
}

TEST(HydicePinned, BatchOneReproducesTheRecordedTrials) {
  int ran = 0;
  for (const Pinned& want : kPinned) {
    if (!long_tests() && !cheap(want)) continue;
    ++ran;
    const std::int64_t cap = want.n >= 256 ? 150'000 : 60'000;
    const Pinned got = run(want.method, want.n, want.driver, want.property, cap);
    std::printf("  {\"%s\", %d, \"%s\", %d, \"%s\", %lld, %lld, %lld, %lld, %lld, 0x%016llxull},\n", got.method,
                got.n, got.driver, got.property, got.status, static_cast<long long>(got.nodes),
                static_cast<long long>(got.propagations), static_cast<long long>(got.integration_steps),
                static_cast<long long>(got.leads), static_cast<long long>(got.lead_expansions),
                static_cast<unsigned long long>(got.end_hash));
    const std::string what = std::string(want.method) + " n=" + std::to_string(want.n) + " " + want.driver +
                             " property " + std::to_string(want.property);
    EXPECT_STREQ(got.status, want.status) << what;
    EXPECT_EQ(got.nodes, want.nodes) << what;
    EXPECT_EQ(got.propagations, want.propagations) << what;
    EXPECT_EQ(got.integration_steps, want.integration_steps) << what;
    EXPECT_EQ(got.leads, want.leads) << what;
    EXPECT_EQ(got.lead_expansions, want.lead_expansions) << what;
    EXPECT_EQ(got.end_hash, want.end_hash) << what;
  }
  EXPECT_GE(ran, 4);
}

// A batch (B = 8 slots a round, each with its own stream) gives the same trial on 1 and on 2
// threads: status, counters, lead statistics and the witness, piece by piece.
TEST(HydiceBatch, SameTrialOnOneAndTwoThreads) {
  for (const char* method : {"hydice", "hydice-noleads"}) {
    for (const char* driver : {"random", "highway"}) {
      const SuiteEntry* s = find_suite("navigation");
      auto sys = s->make(resolve_options(s->parameters, {{"n", "64"}, {"property", "1"}, {"driver", driver}}));
      auto solve = [&](int threads) {
        auto planner = find_method(method)->make(resolve_options(find_method(method)->options, {{"batch", "8"}}));
        const PlannerContext ctx{*sys, sys->info().parameters, 77, PlannerLimits{1e6, long_tests() ? 60'000 : 20'000}, {}};
        PlannerOutcome out;
        tbb::task_arena arena(threads);
        arena.execute([&] { out = planner->solve(ctx); });
        return out;
      };
      const PlannerOutcome one = solve(1), two = solve(2);
      const std::string what = std::string(method) + " " + driver;
      std::printf("  %s batch 8: %s, %lld nodes, %lld propagations\n", what.c_str(),
                  one.status == TrialStatus::falsified ? "falsified" : "not falsified",
                  static_cast<long long>(one.counters.nodes), static_cast<long long>(one.counters.propagations));
      EXPECT_EQ(one.status, two.status) << what;
      EXPECT_EQ(one.counters.nodes, two.counters.nodes) << what;
      EXPECT_EQ(one.counters.propagations, two.counters.propagations) << what;
      EXPECT_EQ(one.counters.integration_steps, two.counters.integration_steps) << what;
      EXPECT_EQ(one.metrics.dump(), two.metrics.dump()) << what;
      ASSERT_EQ(one.trajectory.has_value(), two.trajectory.has_value()) << what;
      if (!one.trajectory) continue;
      ASSERT_EQ(one.trajectory->pieces.size(), two.trajectory->pieces.size()) << what;
      for (std::size_t i = 0; i < one.trajectory->pieces.size(); ++i) {
        const auto& a = one.trajectory->pieces[i];
        const auto& b = two.trajectory->pieces[i];
        EXPECT_EQ(a.mode, b.mode);
        EXPECT_EQ(a.u, b.u);
        EXPECT_EQ(a.duration, b.duration);
        EXPECT_EQ(a.x_end, b.x_end);
      }
      EXPECT_EQ(one.trajectory->final_x, two.trajectory->final_x) << what;
    }
  }
}

}  // namespace
}  // namespace hyfal
