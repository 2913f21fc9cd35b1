// Planner and trial engine: RRT falsifies the thermostat with a witness that validates, a
// corrupted witness is rejected, results do not depend on the thread count, a failing trial
// is recorded as an error while the run goes on.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

std::shared_ptr<const System> thermostat() {
  const SuiteEntry* s = find_suite("thermostat");
  return s->make(resolve_options(s->parameters, {}));
}

Witness witness_of(const System& sys, Trajectory t) { return make_witness(sys, "rrt", 0, std::move(t)); }

PlannerOutcome solve_thermostat(std::uint64_t seed) {
  auto sys = thermostat();
  auto planner = find_method("rrt")->make(resolve_options(find_method("rrt")->options, {}));
  const PlannerContext ctx{*sys, sys->info().parameters, seed, PlannerLimits{60.0, 200000}, {}};
  return planner->solve(ctx);
}

TEST(Rrt, FalsifiesThermostatAndWitnessValidates) {
  auto sys = thermostat();
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    PlannerOutcome out = solve_thermostat(seed);
    ASSERT_EQ(out.status, TrialStatus::falsified) << "seed " << seed;
    ASSERT_TRUE(out.trajectory);
    const Trajectory& t = *out.trajectory;
    EXPECT_LE(t.final_spec, 0.0);
    // Counterexamples lie at x2 in [2, 2.25] (see suites/thermostat/thermostat.cpp).
    EXPECT_GE(t.final_x[1], 2.0 - 1e-9);
    EXPECT_LE(t.final_x[1], 2.25 + 1e-9);
    EXPECT_GE(out.counters.nodes, 2);
    EXPECT_GE(out.counters.propagations, out.counters.nodes - 1);
    const auto report = validate_witness(*sys, witness_of(*sys, t));
    EXPECT_TRUE(report.valid) << report.reason;
    // Round trip through JSON keeps it valid.
    const Witness back = witness_from_json(to_json(witness_of(*sys, t)));
    EXPECT_TRUE(validate_witness(*sys, back).valid);
  }
}

TEST(Witness, CorruptionsAreRejected) {
  auto sys = thermostat();
  const Trajectory good = *solve_thermostat(5).trajectory;
  ASSERT_GE(good.pieces.size(), 3u);
  auto check_invalid = [&](Trajectory t, const char* what) {
    const auto r = validate_witness(*sys, witness_of(*sys, std::move(t)));
    EXPECT_FALSE(r.valid) << what;
    EXPECT_FALSE(r.reason.empty());
  };
  {
    Trajectory t = good;
    t.pieces[1].x_end[0] += 1e-3;
    check_invalid(t, "x_end moved");
  }
  {
    Trajectory t = good;
    t.pieces[0].u[0] = 5.0;  // outside U_on = [2, 4]
    check_invalid(t, "input outside U");
  }
  {
    Trajectory t = good;
    t.pieces[2].duration *= 1.5;
    check_invalid(t, "duration changed");
  }
  {
    Trajectory t = good;  // stop early: the final state is safe
    t.pieces.resize(t.pieces.size() - 2);
    t.final_x = t.pieces.back().x_end;
    t.final_mode = t.pieces.back().mode;
    check_invalid(t, "truncated");
  }
  {
    Trajectory t = good;  // skip a required transition: flow past the guard in one mode
    for (auto& p : t.pieces) p.transition = -1;
    check_invalid(t, "transitions removed");
  }
  EXPECT_THROW(witness_from_json(Json::parse(R"({"format":"hyfal-witness/1"})")), WitnessError);
  EXPECT_THROW(witness_from_json(Json::parse("[1,2]")), WitnessError);
}

// A piece may leave its states out (SystemInfo::sparse_witness_states): the JSON omits them, the
// witness still validates (re-simulated from the validator's own state), the states that are
// recorded are still compared, and a state of the wrong size is still malformed.
TEST(Witness, PiecesWithoutStatesAreReSimulated) {
  auto sys = thermostat();
  Trajectory t = *solve_thermostat(5).trajectory;
  ASSERT_GE(t.pieces.size(), 3u);
  t.pieces[1].x_start.clear();
  t.pieces[1].x_end.clear();
  const Json j = to_json(witness_of(*sys, t));
  EXPECT_FALSE(j["pieces"][1].contains("x_start"));
  EXPECT_FALSE(j["pieces"][1].contains("x_end"));
  EXPECT_TRUE(j["pieces"][0].contains("x_end"));
  const Witness back = witness_from_json(j);
  EXPECT_TRUE(back.trajectory.pieces[1].x_end.empty());
  const auto report = validate_witness(*sys, back);
  EXPECT_TRUE(report.valid) << report.reason;
  Trajectory moved = t;
  moved.pieces[2].x_end[0] += 1e-3;
  EXPECT_FALSE(validate_witness(*sys, witness_of(*sys, moved)).valid);
  Trajectory wrong = t;
  wrong.pieces[1].x_end = {1.0};
  const auto bad = validate_witness(*sys, witness_of(*sys, wrong));
  EXPECT_FALSE(bad.valid);
  EXPECT_TRUE(bad.malformed);
}

std::vector<TrialJob> thermostat_jobs(int n, const MethodEntry* method) {
  auto sys = thermostat();
  std::vector<TrialJob> jobs;
  for (int i = 0; i < n; ++i) {
    TrialJob j;
    j.key = {"test", "thermostat", sys->info().instance.dump(), method->name, "{}", i};
    j.system = sys;
    j.method = method;
    j.method_options = resolve_options(method->options, {});
    j.limits = {60.0, 200000};
    j.seed = trial_seed(42, j.key.suite, j.key.instance, j.key.method, i);
    jobs.push_back(std::move(j));
  }
  return jobs;
}

std::vector<TrialRecord> run_sorted(const std::vector<TrialJob>& jobs, int threads, const std::string& dir) {
  EngineOptions eo;
  eo.threads = threads;
  eo.witness_dir = dir;
  std::vector<TrialRecord> out;
  run_trials(jobs, eo, [&](const TrialRecord& r) { out.push_back(r); });
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.key.trial_index < b.key.trial_index; });
  return out;
}

TEST(TrialEngine, IdenticalResultsAtOneAndTwoThreads) {
  const auto dir = std::filesystem::temp_directory_path() / "hyfal_test_engine";
  std::filesystem::remove_all(dir);
  const auto jobs = thermostat_jobs(12, find_method("rrt"));
  const auto a = run_sorted(jobs, 1, (dir / "a").string());
  const auto b = run_sorted(jobs, 2, (dir / "b").string());
  ASSERT_EQ(a.size(), 12u);
  ASSERT_EQ(b.size(), 12u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].status, TrialStatus::falsified);
    EXPECT_TRUE(a[i].validated);
    EXPECT_EQ(a[i].seed, b[i].seed);
    EXPECT_EQ(a[i].status, b[i].status);
    EXPECT_EQ(a[i].nodes, b[i].nodes);
    EXPECT_EQ(a[i].propagations, b[i].propagations);
    EXPECT_EQ(a[i].integration_steps, b[i].integration_steps);
    EXPECT_EQ(a[i].threads, 1);
    EXPECT_EQ(b[i].threads, 2);
    ASSERT_TRUE(std::filesystem::exists(a[i].witness));
    std::ifstream fa(a[i].witness), fb(b[i].witness);
    const std::string sa((std::istreambuf_iterator<char>(fa)), {}), sb((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_EQ(sa, sb);  // byte-identical witnesses
  }
  // Different trials get different seeds and different searches.
  EXPECT_NE(a[0].seed, a[1].seed);
  std::filesystem::remove_all(dir);
}

class ThrowingPlanner : public Planner {
 public:
  PlannerOutcome solve(const PlannerContext& ctx) override {
    if (ctx.seed % 2 == 0) throw std::runtime_error("deliberate failure");
    PlannerOutcome out;
    out.status = TrialStatus::not_found;
    return out;
  }
};

TEST(TrialEngine, AFailingTrialIsRecordedAndTheRunGoesOn) {
  const MethodEntry flaky{"flaky", "throws on even seeds", {}, [](const Json&) { return std::make_unique<ThrowingPlanner>(); }};
  const auto jobs = thermostat_jobs(10, &flaky);
  const auto recs = run_sorted(jobs, 2, "");
  ASSERT_EQ(recs.size(), 10u);
  int errors = 0;
  for (const auto& r : recs) {
    if (r.seed % 2 == 0) {
      EXPECT_EQ(r.status, TrialStatus::error);
      EXPECT_EQ(r.error, "deliberate failure");
      ++errors;
    } else {
      EXPECT_EQ(r.status, TrialStatus::not_found);
    }
    EXPECT_FALSE(r.started_at.empty());
    EXPECT_GE(r.wall_s, 0.0);
  }
  EXPECT_GT(errors, 0);
}

TEST(TrialEngine, NodeCapAndTimeoutAreReported) {
  auto sys = thermostat();
  auto planner = find_method("rrt")->make(resolve_options(find_method("rrt")->options, {}));
  const PlannerContext capped{*sys, {}, 1, PlannerLimits{60.0, 50}, {}};
  const auto out = planner->solve(capped);
  EXPECT_EQ(out.status, TrialStatus::node_cap);
  EXPECT_EQ(out.counters.nodes, 50);
  std::stop_source cancel;
  cancel.request_stop();
  const PlannerContext cancelled{*sys, {}, 1, PlannerLimits{60.0, 100000}, cancel.get_token()};
  EXPECT_EQ(planner->solve(cancelled).status, TrialStatus::timeout);
}

TEST(Seeds, DependOnEveryKeyPartOnly) {
  const auto s = trial_seed(1, "thermostat", "{}", "rrt", 3);
  EXPECT_EQ(s, trial_seed(1, "thermostat", "{}", "rrt", 3));
  EXPECT_NE(s, trial_seed(2, "thermostat", "{}", "rrt", 3));
  EXPECT_NE(s, trial_seed(1, "other", "{}", "rrt", 3));
  EXPECT_NE(s, trial_seed(1, "thermostat", "{\"a\":1}", "rrt", 3));
  EXPECT_NE(s, trial_seed(1, "thermostat", "{}", "rrt2", 3));
  EXPECT_NE(s, trial_seed(1, "thermostat", "{}", "rrt", 4));
  EXPECT_GE(s, 0);
}

}  // namespace
}  // namespace hyfal
