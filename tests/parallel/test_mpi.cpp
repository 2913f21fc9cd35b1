// Distributed runs end to end: `mpirun` of the built binary (HYFAL_BIN) on this machine, checked
// against one process. Trial keys, and so seeds, do not depend on --trials, so one reference run
// of 120 thermostat trials serves every test. Registered only when CMake found MPI.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"

#ifndef HYFAL_BIN
#error "HYFAL_BIN (the path of the built hyfal binary) must be defined"
#endif
#ifndef HYFAL_MPIEXEC
#error "HYFAL_MPIEXEC (the path of mpirun) must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using namespace hyfal_cli_test;  // quote, read_text, Result, decode_status

// Single-copy shared memory (CMA) needs ptrace rights that containers often withhold: the plain
// shared-memory path works everywhere.
std::string mpirun(const std::string& extra = "") {
  std::string cmd = "env OMPI_MCA_btl_vader_single_copy_mechanism=none " + quote(HYFAL_MPIEXEC) + " --oversubscribe";
  if (::geteuid() == 0) cmd += " --allow-run-as-root";
  return cmd + (extra.empty() ? "" : " " + extra);
}

class MpiTest : public ::testing::Test {
 protected:
  static fs::path reference_dir() { return fs::temp_directory_path() / ("hyfal-mpi-ref-" + std::to_string(::getpid())); }

  // One process, 120 trials: what every distributed run below must store. Made by the first test
  // that needs it (a failure there fails that test, where a failed SetUpTestSuite would only skip).
  static bool reference_ready() {
    static const bool ok = [] {
      fs::remove_all(reference_dir());
      fs::create_directories(reference_dir());
      const std::string cmd = "cd " + quote(reference_dir().string()) + " && " + quote(HYFAL_BIN) + " " +
                              run_args(120, "ref.sqlite", "ref-w", 2) + " >/dev/null 2>ref.err";
      return decode_status(std::system(cmd.c_str())) == 0;
    }();
    return ok;
  }
  static void TearDownTestSuite() { fs::remove_all(reference_dir()); }

  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hyfal-mpi-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  static std::string run_args(int trials, const std::string& db, const std::string& witnesses, int threads = 1) {
    return "run --suite thermostat --trials " + std::to_string(trials) + " --threads " + std::to_string(threads) +
           " --quiet --db " + db + " --witness-dir " + witnesses;
  }

  // Runs `command` in the test's folder (stdout and stderr to files), with a wall-clock cap.
  Result sh(const std::string& command, int cap_s = 180) {
    static int n = 0;
    const fs::path out = dir_ / ("cmd" + std::to_string(n) + ".out"), err = dir_ / ("cmd" + std::to_string(n) + ".err");
    ++n;
    Result r;
    r.command = command;
    const std::string full = "cd " + quote(dir_.string()) + " && timeout -s KILL " + std::to_string(cap_s) + " sh -c " +
                             quote(command) + " >" + quote(out.string()) + " 2>" + quote(err.string()) + " </dev/null";
    r.code = decode_status(std::system(full.c_str()));
    r.out = read_text(out);
    r.err = read_text(err);
    return r;
  }

  // (index -> seed|status|nodes|propagations|steps|validated|metrics) of a database.
  static std::map<int, std::string> rows(const fs::path& db, int below = 1 << 30) {
    const std::string cmd = "sqlite3 -separator '|' " + quote(db.string()) +
                            " 'SELECT trial_index, seed, status, nodes, propagations, integration_steps, validated, "
                            "metrics FROM trials WHERE trial_index < " + std::to_string(below) + " ORDER BY trial_index'";
    std::map<int, std::string> out;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return out;
    char line[4096];
    while (std::fgets(line, sizeof line, p)) {
      std::string s(line);
      const auto bar = s.find('|');
      out[std::stoi(s.substr(0, bar))] = s.substr(bar + 1);
    }
    ::pclose(p);
    return out;
  }

  // Every stored trial equals the reference's, and its witness file has the reference's bytes.
  void expect_same_as_reference(const fs::path& db, int trials) {
    ASSERT_TRUE(reference_ready()) << read_text(reference_dir() / "ref.err");
    const auto mine = rows(db);
    const auto ref = rows(reference_dir() / "ref.sqlite", trials);
    ASSERT_EQ(static_cast<int>(ref.size()), trials);
    EXPECT_EQ(mine, ref);
    std::size_t witnesses = 0;
    for (const auto& entry : fs::recursive_directory_iterator(reference_dir() / "ref-w")) {
      if (!entry.is_regular_file()) continue;
      const std::string name = entry.path().filename().string();
      const int index = std::stoi(name.substr(name.rfind("-t") + 2));
      if (index >= trials) continue;
      const fs::path twin = dir_ / "w" / fs::relative(entry.path(), reference_dir() / "ref-w");
      ASSERT_TRUE(fs::exists(twin)) << twin;
      EXPECT_EQ(read_text(twin), read_text(entry.path())) << twin;
      ++witnesses;
    }
    EXPECT_EQ(static_cast<int>(witnesses), trials);  // thermostat: every trial falsifies
  }

  int stored(const std::string& db) {
    const Result r = sh("sqlite3 " + db + " 'SELECT count(*) FROM trials' 2>/dev/null || echo 0", 30);
    return r.out.empty() ? 0 : std::atoi(r.out.c_str());
  }

  // Pids of the hyfal processes of this test (their command line names its folder), by rank.
  std::map<int, pid_t> ranks() {
    std::map<int, pid_t> out;
    for (const auto& entry : fs::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      const std::string cmdline = read_text(entry.path() / "cmdline");
      if (cmdline.rfind(HYFAL_BIN, 0) != 0) continue;
      std::error_code ec;
      if (fs::read_symlink(entry.path() / "cwd", ec) != dir_) continue;
      std::string env = read_text(entry.path() / "environ");
      for (std::size_t at = 0; at < env.size();) {
        const std::size_t end = env.find('\0', at);
        const std::string var = env.substr(at, end - at);
        if (var.rfind("OMPI_COMM_WORLD_RANK=", 0) == 0) out[std::stoi(var.substr(21))] = std::stoi(name);
        if (end == std::string::npos) break;
        at = end + 1;
      }
    }
    return out;
  }

  // Starts `command` in the background; returns its pid (a shell whose children are the job).
  pid_t start(const std::string& command) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::setpgid(0, 0);
      const std::string full = "cd " + quote(dir_.string()) + " && exec " + command + " >bg.out 2>bg.err </dev/null";
      ::execl("/bin/sh", "sh", "-c", full.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    return pid;
  }
  // Waits for a background command; its exit code (-1 if it outlived cap_s and was killed).
  int finish(pid_t pid, int cap_s = 180) {
    const auto deadline = Clock::now() + std::chrono::seconds(cap_s);
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
      if (Clock::now() > deadline) {
        ::kill(-pid, SIGKILL);
        for (const auto& [rank, rank_pid] : ranks()) ::kill(rank_pid, SIGKILL);  // each in its own group
        ::waitpid(pid, &status, 0);
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return decode_status(status);
  }
  // Waits until the database holds at least n trials (false after cap_s).
  bool wait_for_stored(const std::string& db, int n, int cap_s = 120) {
    const auto deadline = Clock::now() + std::chrono::seconds(cap_s);
    while (Clock::now() < deadline) {
      if (stored(db) >= n) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

  fs::path dir_;
};

TEST_F(MpiTest, ThreeRanksStoreWhatOneProcessStores) {
  const Result r = sh(mpirun("-n 3") + " " + quote(HYFAL_BIN) + " " + run_args(40, "db.sqlite", "w"));
  ASSERT_EQ(r.code, 0) << r;
  expect_same_as_reference(dir_ / "db.sqlite", 40);
  // Rank 0 alone wrote: the workers created no database or witness folder of their own.
  EXPECT_EQ(stored("db.sqlite"), 40);
}

TEST_F(MpiTest, ReproduceOnTwoRanksStoresWhatOneProcessStores) {
  const std::string args = " reproduce kim-table1 --profile smoke --threads 1 --witness-dir w --out-dir t";
  const Result one = sh(quote(HYFAL_BIN) + args + " --db one.sqlite");
  ASSERT_EQ(one.code, 0) << one;
  const Result two = sh(mpirun("-n 2") + " " + quote(HYFAL_BIN) + args + " --db two.sqlite");
  ASSERT_EQ(two.code, 0) << two;
  const auto a = rows(dir_ / "one.sqlite"), b = rows(dir_ / "two.sqlite");
  EXPECT_FALSE(a.empty());
  // The smoke profile's 10 s cap is wall clock: on a loaded machine a slow trial may time out in
  // one run and not in the other. A trial that timed out in either run is compared by key and
  // seed only; every other one by status, nodes and propagations too.
  const auto all = [&](const fs::path& db) {
    std::map<std::string, std::pair<std::string, std::string>> m;  // key -> (seed, status|nodes|propagations)
    std::istringstream in(sh("sqlite3 -separator '\t' " + db.string() +
                             " 'SELECT method || config || instance || trial_index, seed, status || \" \" || nodes || \" \" || propagations FROM trials'").out);
    for (std::string line; std::getline(in, line);) {
      const auto t1 = line.find('\t'), t2 = line.find('\t', t1 + 1);
      m[line.substr(0, t1)] = {line.substr(t1 + 1, t2 - t1 - 1), line.substr(t2 + 1)};
    }
    return m;
  };
  const auto x = all("one.sqlite"), y = all("two.sqlite");
  ASSERT_EQ(x.size(), y.size());
  std::size_t compared = 0;
  for (const auto& [key, v] : x) {
    ASSERT_TRUE(y.count(key)) << key;
    const auto& w = y.at(key);
    EXPECT_EQ(v.first, w.first) << key;
    if (v.second.starts_with("timeout") || w.second.starts_with("timeout")) continue;
    EXPECT_EQ(v.second, w.second) << key;
    ++compared;
  }
  EXPECT_GE(2 * compared, x.size()) << "most trials finish within the cap";
}

TEST_F(MpiTest, RanksOfAnotherBuildAreRefusedBeforeAnythingIsWritten) {
  const std::string hyfal = quote(HYFAL_BIN) + " " + run_args(20, "db.sqlite", "w");
  const Result r = sh(mpirun("-n 2") + " " + hyfal + " : -n 1 -x HYFAL_TEST_BUILD_ID=other " + hyfal);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("hyfal: error: rank 2 (host "), std::string::npos) << r;
  EXPECT_NE(r.err.find("every rank must run the same build"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(dir_ / "db.sqlite"));
  EXPECT_FALSE(fs::exists(dir_ / "w"));
}

// With a launcher that tolerates a lost rank (OpenMPI: --enable-recovery), the trials of a
// worker killed with -9 go to the other ranks and the run completes, each trial stored once.
TEST_F(MpiTest, TrialsOfAKilledWorkerAreRunByTheOtherRanks) {
  const pid_t job = start("env HYFAL_PEER_TIMEOUT_S=2 " + mpirun("--enable-recovery -n 3") + " " + quote(HYFAL_BIN) +
                          " " + run_args(120, "db.sqlite", "w"));
  ASSERT_TRUE(wait_for_stored("db.sqlite", 20));
  const auto pids = ranks();
  ASSERT_TRUE(pids.count(2)) << "rank 2 not found";
  ::kill(pids.at(2), SIGKILL);
  EXPECT_EQ(finish(job), 0) << read_text(dir_ / "bg.err");
  EXPECT_NE(read_text(dir_ / "bg.err").find("[hyfal] rank 2 (host"), std::string::npos) << read_text(dir_ / "bg.err");
  expect_same_as_reference(dir_ / "db.sqlite", 120);
}

// A worker that dies while its result is on the way (rank 0 has matched the message, its bytes
// are still in the dead rank's memory) neither hangs rank 0 nor silences it for the other worker:
// the run completes on ranks 0 and 1. Before receives were non-blocking this hung for ever.
TEST_F(MpiTest, AWorkerThatDiesSendingAResultLeavesNoHole) {
  const pid_t job = start("env HYFAL_PEER_TIMEOUT_S=2 " + mpirun("--enable-recovery -x HYFAL_TEST_DIE_SENDING_RESULT=2 -n 3") +
                          " " + quote(HYFAL_BIN) + " " + run_args(60, "db.sqlite", "w"));
  EXPECT_EQ(finish(job, 120), 0) << read_text(dir_ / "bg.err");
  EXPECT_NE(read_text(dir_ / "bg.err").find("[hyfal] rank 2 (host"), std::string::npos) << read_text(dir_ / "bg.err");
  EXPECT_EQ(read_text(dir_ / "bg.err").find("lost rank 0"), std::string::npos) << read_text(dir_ / "bg.err");
  expect_same_as_reference(dir_ / "db.sqlite", 60);
}

// kill -9 of the whole job (launcher and every rank): what was committed stays, and the run
// finishes in one process; then the other way round, a one-process run finished on 2 ranks.
TEST_F(MpiTest, AKilledJobResumesAtAnotherRankCount) {
  const std::string args = run_args(120, "db.sqlite", "w");
  const pid_t job = start(mpirun("-n 3") + " " + quote(HYFAL_BIN) + " " + args);
  ASSERT_TRUE(wait_for_stored("db.sqlite", 20));
  ::kill(-job, SIGKILL);
  for (const auto& [rank, pid] : ranks()) ::kill(pid, SIGKILL);
  finish(job);
  const int before = stored("db.sqlite");
  EXPECT_LT(before, 120);
  const Result resumed = sh(quote(HYFAL_BIN) + " " + args);
  ASSERT_EQ(resumed.code, 0) << resumed;
  expect_same_as_reference(dir_ / "db.sqlite", 120);

  const std::string args2 = run_args(120, "db2.sqlite", "w2");
  const pid_t one = start(quote(HYFAL_BIN) + " " + args2);
  ASSERT_TRUE(wait_for_stored("db2.sqlite", 20));
  ::kill(-one, SIGKILL);
  finish(one);
  EXPECT_LT(stored("db2.sqlite"), 120);
  const Result on_two = sh(mpirun("-n 2") + " " + quote(HYFAL_BIN) + " " + args2);
  ASSERT_EQ(on_two.code, 0) << on_two;
  ASSERT_TRUE(reference_ready());
  EXPECT_EQ(rows(dir_ / "db2.sqlite"), rows(reference_dir() / "ref.sqlite", 120));
}

// A worker that loses rank 0 (kill -9 of the coordinator, launcher still up) stops by itself.
TEST_F(MpiTest, WorkersStopWhenRankZeroIsLost) {
  const pid_t job = start("env HYFAL_PEER_TIMEOUT_S=2 " + mpirun("--enable-recovery -n 3") + " " + quote(HYFAL_BIN) +
                          " " + run_args(120, "db.sqlite", "w"));
  ASSERT_TRUE(wait_for_stored("db.sqlite", 10));
  const auto pids = ranks();
  ASSERT_TRUE(pids.count(0));
  ::kill(pids.at(0), SIGKILL);
  EXPECT_GE(finish(job, 60), 0) << "the job outlived rank 0 by a minute";
  const std::string err = read_text(dir_ / "bg.err");
  EXPECT_NE(err.find("lost rank 0"), std::string::npos) << err;
  EXPECT_TRUE(ranks().empty());
  const Result resumed = sh(mpirun("-n 2") + " " + quote(HYFAL_BIN) + " " + run_args(120, "db.sqlite", "w"));
  ASSERT_EQ(resumed.code, 0) << resumed;
  expect_same_as_reference(dir_ / "db.sqlite", 120);
}

}  // namespace
