// Intra-trial parallelism (issue 12): with a fixed `batch`, a trial's results do not depend on
// the number of threads — the same statuses, nodes, propagations, integration steps and
// byte-identical witnesses at --threads 1 and 2 — for every method on suites with different
// kinds of inputs (a fixed grid, a driver's state-dependent box, parameters searched by RRFT).
// Node caps, not time, end the trials, so the outcomes are deterministic. Also run under
// ThreadSanitizer (the slots of a round run concurrently against one lock-free store).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "core/run/option_spec.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/util/rng.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;
using Sets = std::vector<std::pair<std::string, std::string>>;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Case {
  std::string suite;
  Sets instance;
  std::int64_t max_nodes;
};

// Every method that declares the option `batch` (the test below requires all of them to).
std::vector<const MethodEntry*> batched_methods() {
  std::vector<const MethodEntry*> out;
  for (const MethodEntry& m : all_methods())
    for (const OptionSpec& o : m.options)
      if (o.key == "batch") out.push_back(&m);
  return out;
}

std::vector<TrialJob> jobs_for(const std::string& batch) {
  const std::vector<Case> cases = {{"thermostat", {}, 1500},
                                   {"navigation", {{"n", "4"}, {"driver", "student"}}, 1500},
                                   {"navigation", {{"n", "8"}, {"driver", "random"}}, 1500},
                                   {"blimp", {}, 400}};
  std::vector<TrialJob> jobs;
  for (const Case& c : cases) {
    const SuiteEntry* suite = find_suite(c.suite);
    const Json instance = resolve_options(suite->parameters, c.instance);
    std::shared_ptr<const System> sys = suite->make(instance);
    for (const MethodEntry* m : batched_methods()) {
      const Json options = resolve_options(m->options, {{"batch", batch}});
      if (m->check_system) {
        try {
          m->check_system(*sys, options);
        } catch (const std::invalid_argument&) {
          continue;  // e.g. HyDICE without a decomposition
        }
      }
      for (int t = 0; t < 2; ++t) {
        TrialJob j;
        j.key = {"batch", c.suite, instance.dump(), m->name, options.dump(), t};
        j.system = sys;
        j.method = m;
        j.method_options = options;
        j.limits = {120.0, c.max_nodes};
        j.seed = trial_seed(5, c.suite, j.key.instance, m->name, t);
        jobs.push_back(std::move(j));
      }
    }
  }
  return jobs;
}

struct Outcome {
  TrialStatus status;
  std::int64_t nodes, propagations, steps;
  std::string metrics, witness;
};

std::map<std::string, Outcome> run_at(const std::vector<TrialJob>& jobs, int threads, const fs::path& dir) {
  EngineOptions options;
  options.threads = threads;
  options.witness_dir = dir.string();
  std::map<std::string, Outcome> out;
  run_trials(jobs, options, [&](const TrialRecord& r) {
    const std::string key = r.key.suite + " " + r.key.instance + " " + r.key.method + " t" + std::to_string(r.key.trial_index);
    if (std::getenv("HYFAL_BATCH_VERBOSE"))
      std::fprintf(stderr, "%-90s %-10s %7lld nodes %6.2f s\n", key.c_str(), std::string(to_string(r.status)).c_str(),
                   static_cast<long long>(r.nodes), r.wall_s);
    out[key] = {r.status, r.nodes, r.propagations, r.integration_steps, r.metrics,
                r.witness.empty() ? std::string() : read_file(r.witness)};
  });
  return out;
}

TEST(Batch, EveryMethodDeclaresIt) {
  std::vector<std::string> names;
  for (const MethodEntry* m : batched_methods()) names.push_back(m->name);
  for (const MethodEntry& m : all_methods())
    // OMPL's planners grow one motion at a time inside OMPL: no batches; the optimisation
    // falsifiers evaluate one simulation at a time (pagmo's and NLopt's algorithms call the
    // fitness in sequence); FalStar's adaptive search chooses each pass from the ones before, and
    // the gradient descent each step from the gradient before.
    if (!m.name.starts_with("ompl-") && m.name != "random" && m.name != "annealing" && m.name != "cmaes" &&
        m.name != "nelder-mead" && !m.name.starts_with("adaptive") && m.name != "gradient")
      EXPECT_NE(std::find(names.begin(), names.end(), m.name), names.end()) << m.name << " has no option batch";
}

TEST(Batch, ResultsAtAFixedBatchDoNotDependOnTheThreadCount) {
  const fs::path dir = fs::temp_directory_path() / ("hyfal-batch-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::vector<TrialJob> jobs = jobs_for("8");
  ASSERT_FALSE(jobs.empty());
  const auto one = run_at(jobs, 1, dir / "t1");
  const auto two = run_at(jobs, 2, dir / "t2");
  ASSERT_EQ(one.size(), jobs.size());
  int falsified = 0;
  for (const auto& [key, a] : one) {
    for (const auto* other : {&two}) {
      const Outcome& b = other->at(key);
      EXPECT_EQ(a.status, b.status) << key;
      EXPECT_EQ(a.nodes, b.nodes) << key;
      EXPECT_EQ(a.propagations, b.propagations) << key;
      EXPECT_EQ(a.steps, b.steps) << key;
      EXPECT_EQ(a.metrics, b.metrics) << key;
      EXPECT_EQ(a.witness, b.witness) << key << ": the witnesses differ";
    }
    EXPECT_NE(a.status, TrialStatus::error) << key;
    falsified += a.status == TrialStatus::falsified;
  }
  EXPECT_GT(falsified, 0) << "not vacuous: some trials find a witness";
  fs::remove_all(dir);
}

// A batch is a different search from the sequential one (slots do not see their round's
// nodes), but batch = 1 is the sequential algorithm: the option's default.
TEST(Batch, BatchOneIsTheDefault) {
  for (const MethodEntry& m : all_methods()) {
    const Json defaults = resolve_options(m.options, {});
    if (defaults.contains("batch")) EXPECT_EQ(defaults.at("batch").get<int>(), 1) << m.name;
  }
}

// SlotRounds (a helper standing by between rounds): every slot of every round runs exactly once,
// its writes are seen by the coordinator after run() (ThreadSanitizer checks the ordering), and
// the helper does take slots. Rounds continue until it has (at most 20 s), so a busy machine
// slows the test rather than failing it.
TEST(SlotRounds, EverySlotOfEveryRoundRunsOnceOnEitherThread) {
  tbb::task_arena arena(2);
  constexpr std::size_t kSlots = 8;
  std::vector<int> runs(kSlots), seen;
  std::atomic<std::size_t> by_helper{0};
  std::size_t rounds_run = 0;
  const auto caller = std::this_thread::get_id();
  TrialCpuClock cpu;
  arena.execute([&] {
    with_slot_rounds(&cpu, [&](SlotRounds& rounds) {
      const auto t0 = std::chrono::steady_clock::now();
      auto body = [&](std::size_t s) {
        volatile double x = 1.0;
        for (int i = 0; i < 2000; ++i) x = x * 1.0000001 + 1e-9;  // a few µs of work
        ++runs[s];
        if (std::this_thread::get_id() != caller) by_helper.fetch_add(1, std::memory_order_relaxed);
      };
      while (rounds_run < 200 || (by_helper.load() == 0 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20))) {
        rounds.run(kSlots, body);
        ++rounds_run;
        for (std::size_t s = 0; s < kSlots; ++s) {
          EXPECT_EQ(runs[s], 1) << "round " << rounds_run << " slot " << s;
          runs[s] = 0;
        }
      }
    });
  });
  EXPECT_GT(by_helper.load(), 0u) << "the helper never took a slot in " << rounds_run << " rounds";
  EXPECT_GT(cpu.helper_seconds(), 0.0) << "the helper's slots count toward cpu_s";
}

// Commits come in slot order, each after its slot's body has finished (its writes visible), and
// stop for the round when one returns true (the later bodies still run); a body that throws
// stops the commits at its slot and its exception comes out of run().
TEST(SlotRounds, CommitsInSlotOrderAfterTheirBodies) {
  tbb::task_arena arena(2);
  arena.execute([&] {
    with_slot_rounds(nullptr, [&](SlotRounds& rounds) {
      constexpr std::size_t kSlots = 8;
      std::vector<int> value(kSlots);
      for (int round = 0; round < 500; ++round) {
        std::vector<std::size_t> committed;
        std::atomic<int> ran{0};
        auto body = [&](std::size_t s) {
          volatile double x = 1.0;
          for (int i = 0; i < 500 * static_cast<int>(s % 3); ++i) x = x * 1.0000001;
          value[s] = round * 100 + static_cast<int>(s);
          ran.fetch_add(1);
        };
        const std::size_t stop_at = round % 2 ? 3 : kSlots;  // odd rounds: commit 3 ends the round
        rounds.run(kSlots, body, [&](std::size_t s) {
          EXPECT_EQ(value[s], round * 100 + static_cast<int>(s)) << "committed before its body finished";
          committed.push_back(s);
          return s == stop_at;
        });
        EXPECT_EQ(ran.load(), static_cast<int>(kSlots));
        const std::size_t want = std::min(stop_at + 1, kSlots);
        ASSERT_EQ(committed.size(), want) << "round " << round;
        for (std::size_t i = 0; i < want; ++i) EXPECT_EQ(committed[i], i);
      }
      std::vector<std::size_t> committed;
      auto failing = [&](std::size_t s) {
        if (s == 5) throw std::runtime_error("slot 5");
      };
      EXPECT_THROW(rounds.run(kSlots, failing, [&](std::size_t s) {
        committed.push_back(s);
        return false;
      }), std::runtime_error);
      EXPECT_EQ(committed, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
    });
  });
}

// With one thread the coordinator runs every slot itself; a body's exception is rethrown by
// run() after the round, and leaves no helper waiting (the call returns).
TEST(SlotRounds, OneThreadAndExceptions) {
  for (int threads : {1, 2}) {
    tbb::task_arena arena(threads);
    const auto caller = std::this_thread::get_id();
    std::atomic<int> elsewhere{0}, ran{0};
    bool thrown = false;
    arena.execute([&] {
      try {
        with_slot_rounds(nullptr, [&](SlotRounds& rounds) {
          for (int round = 0; round < 50; ++round) {
            auto body = [&](std::size_t s) {
              ran.fetch_add(1);
              if (std::this_thread::get_id() != caller) elsewhere.fetch_add(1);
              if (round == 40 && s == 5) throw std::runtime_error("slot 5");
            };
            rounds.run(8, body);
          }
        });
      } catch (const std::runtime_error& e) {
        thrown = std::string(e.what()) == "slot 5";
      }
    });
    EXPECT_TRUE(thrown) << threads << " threads";
    EXPECT_EQ(ran.load(), 41 * 8) << threads << " threads: every slot of the failing round still ran";
    if (threads == 1) {
      EXPECT_EQ(elsewhere.load(), 0);
    }
  }
}

}  // namespace
}  // namespace hyfal
