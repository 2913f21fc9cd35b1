// The trial engine under failure: a witness that cannot be written (its folder cannot be made,
// or the disk is full) and a sink that throws stop the run promptly, leave no temporary file and
// store nothing of the trials they stopped; the claim hook decides which jobs run.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;

// A planner that searches until its budget or a stop request ends it (a long trial in flight).
std::atomic<int> sleepers_started{0}, sleepers_finished{0};
class SleeperPlanner : public Planner {
 public:
  PlannerOutcome solve(const PlannerContext& ctx) override {
    ++sleepers_started;
    const SearchBudget budget(ctx);
    PlannerOutcome out;
    while (const auto why = budget.exhausted(0)) {
      out.status = *why;
      ++sleepers_finished;
      return out;
    }
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      if (const auto why = budget.exhausted(0)) {
        out.status = *why;
        ++sleepers_finished;
        return out;
      }
    }
  }
};
const MethodEntry kSleeper{"sleeper", "searches until stopped", {}, [](const Json&) {
                             return std::unique_ptr<Planner>(std::make_unique<SleeperPlanner>());
                           }};

std::shared_ptr<const System> thermostat() {
  const SuiteEntry* s = find_suite("thermostat");
  return s->make(resolve_options(s->parameters, {}));
}

TrialJob make_job(const MethodEntry* method, int index, double timeout_s) {
  static const auto sys = thermostat();
  TrialJob j;
  j.key = {"engine-test", "thermostat", sys->info().instance.dump(), method->name, "{}", index};
  j.system = sys;
  j.method = method;
  j.method_options = resolve_options(method->options, {});
  j.limits = {timeout_s, 200000};
  j.seed = trial_seed(42, j.key.suite, j.key.instance, j.key.method, index);
  return j;
}

// One falsifying thermostat trial (it writes a witness), then two long trials.
std::vector<TrialJob> falsifier_then_long_trials() {
  return {make_job(find_method("rrt"), 0, 60.0), make_job(&kSleeper, 1, 60.0), make_job(&kSleeper, 2, 60.0)};
}

std::vector<fs::path> temporaries(const fs::path& root) {
  std::vector<fs::path> found;
  if (!fs::exists(root)) return found;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.path().extension() == ".tmp") found.push_back(e.path());
  return found;
}

class TrialEngineFailure : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("hyfal_test_engine_") + test->name() + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    sleepers_started = 0;
    sleepers_finished = 0;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs the jobs on two threads; returns the seconds it took and the exception's message.
  std::pair<double, std::string> run_expecting_failure(const std::vector<TrialJob>& jobs, const EngineOptions& eo,
                                                       const TrialSink& sink, bool environment) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string message;
    try {
      run_trials(jobs, eo, sink);
      ADD_FAILURE() << "the run did not fail";
    } catch (const EnvironmentError& e) {
      EXPECT_TRUE(environment) << e.what();
      message = e.what();
    } catch (const std::exception& e) {
      EXPECT_FALSE(environment) << e.what();
      message = e.what();
    }
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), message};
  }

  fs::path dir_;
};

TEST_F(TrialEngineFailure, WitnessFolderThatCannotBeMadeStopsTheRun) {
  std::ofstream(dir_ / "plain") << "a regular file where the witness folder should go\n";
  EngineOptions eo;
  eo.threads = 2;
  eo.witness_dir = (dir_ / "plain" / "wit").string();
  int sunk = 0;
  const auto [seconds, message] =
      run_expecting_failure(falsifier_then_long_trials(), eo, [&](const TrialRecord&) { ++sunk; }, true);
  EXPECT_NE(message.find("cannot write witness"), std::string::npos) << message;
  EXPECT_EQ(sunk, 0) << "neither the failed trial nor the stopped ones are stored";
  EXPECT_LT(seconds, 20.0) << "the long trials in flight were not stopped";
  EXPECT_EQ(sleepers_started.load(), sleepers_finished.load());
  EXPECT_TRUE(temporaries(dir_).empty());
}

TEST_F(TrialEngineFailure, DiskFullWitnessLeavesNoTemporaryFile) {
  // The witness' temporary file is a link to /dev/full: every write to it fails with ENOSPC,
  // as on a full disk, without filling one.
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto jobs = falsifier_then_long_trials();
  EngineOptions eo;
  eo.threads = 2;
  eo.witness_dir = (dir_ / "wit").string();
  const fs::path witness = witness_path(eo.witness_dir, jobs[0].key);
  fs::create_directories(witness.parent_path());
  fs::create_symlink("/dev/full", witness.string() + ".tmp");
  int sunk = 0;
  const auto [seconds, message] = run_expecting_failure(jobs, eo, [&](const TrialRecord&) { ++sunk; }, true);
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_NE(message.find(witness.string()), std::string::npos) << message;
  EXPECT_EQ(sunk, 0);
  EXPECT_LT(seconds, 20.0);
  EXPECT_TRUE(temporaries(dir_).empty()) << temporaries(dir_).front();
  EXPECT_FALSE(fs::exists(witness));
}

TEST_F(TrialEngineFailure, ThrowingSinkStopsTheTrialsInFlight) {
  // The quick trial first: oneTBB runs the first half of the range on the calling thread and
  // the second half (a long trial) on the other, which is in flight when the sink throws.
  std::vector<TrialJob> jobs = {make_job(find_method("rrt"), 0, 60.0), make_job(&kSleeper, 1, 60.0)};
  EngineOptions eo;
  eo.threads = 2;
  int calls = 0;
  const auto [seconds, message] = run_expecting_failure(
      jobs, eo,
      [&](const TrialRecord&) {
        ++calls;
        throw std::runtime_error("database disk is full");
      },
      false);
  EXPECT_EQ(message, "database disk is full");
  EXPECT_EQ(calls, 1) << "no trial reaches the sink after it failed";
  EXPECT_LT(seconds, 20.0);
  EXPECT_EQ(sleepers_started.load(), sleepers_finished.load());
}

TEST_F(TrialEngineFailure, ClaimHookDecidesWhichJobsRun) {
  std::vector<TrialJob> jobs;
  for (int i = 0; i < 6; ++i) jobs.push_back(make_job(find_method("rrt"), i, 60.0));
  EngineOptions eo;
  eo.threads = 2;
  std::vector<std::int64_t> asked, run;
  run_trials(
      jobs, eo, [&](const TrialRecord& r) { run.push_back(r.key.trial_index); },
      [&](const TrialJob& job) {
        asked.push_back(job.key.trial_index);
        return job.key.trial_index % 2 == 0;
      });
  std::sort(asked.begin(), asked.end());
  std::sort(run.begin(), run.end());
  EXPECT_EQ(asked, (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(run, (std::vector<std::int64_t>{0, 2, 4}));
  // A claim that throws fails the run like a sink that throws.
  EXPECT_THROW(run_trials(jobs, eo, [](const TrialRecord&) {},
                          [](const TrialJob&) -> bool { throw std::runtime_error("locked"); }),
               std::runtime_error);
}

TEST_F(TrialEngineFailure, CallersCancelStillStopsTrials) {
  std::stop_source cancel;
  EngineOptions eo;
  eo.threads = 1;
  eo.cancel = cancel.get_token();
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel.request_stop();
  });
  std::vector<TrialStatus> statuses;
  const auto t0 = std::chrono::steady_clock::now();
  run_trials({make_job(&kSleeper, 0, 60.0)}, eo, [&](const TrialRecord& r) { statuses.push_back(r.status); });
  canceller.join();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0);
  EXPECT_EQ(statuses, (std::vector<TrialStatus>{TrialStatus::timeout}));
}

}  // namespace
}  // namespace hyfal
