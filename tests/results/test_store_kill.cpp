// A run killed at any instant of its start-up, while it creates its results database, leaves
// nothing that stops the next run (issue 39): the next `hyfal run` completes and stores exactly the
// trials an uninterrupted run stores, `hyfal table` reads the database, no reader is ever told
// "attempt to write a readonly database", and no journal or lock is left behind.
//
// The defect this guards against: SQLite switched a new database to WAL in a rollback-journal
// transaction, and a kill inside it left a hot journal that the store's read-only schema check
// could not roll back, so every later open failed. It was found by killing at random moments; so
// is this test, at many instants rather than one sleep: instants spread over the whole run from
// its spawn, and instants aimed at the creation itself (the first file that appears in the folder,
// seen through inotify, plus a sweep of short delays).
//
// HYFAL_KILL_TEST_BINARY runs the test against another hyfal binary (an older build shows the
// defect); HYFAL_KILL_TEST_VERBOSE prints what each instant left.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <set>
#include <thread>

#include "cli_support.hpp"

namespace {
using namespace hyfal_cli_test;
using Clock = std::chrono::steady_clock;

std::string binary() {
  const char* other = std::getenv("HYFAL_KILL_TEST_BINARY");
  return other != nullptr ? other : HYFAL_BIN;
}

std::string fmt_ms(const char* what, double seconds) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f ms ", seconds * 1e3);
  return text + std::string(what);
}

// The trial columns that do not depend on the machine or the moment.
const char* kTrialColumns =
    "experiment, suite, instance, method, config, trial_index, seed, status, validated, nodes, propagations, "
    "integration_steps, witness, error";

class StoreKillTest : public HyfalBinaryTest {
 protected:
  StoreKillTest() : HyfalBinaryTest("store_kill") {}

  Args run_args() const {
    return {"run", "--suite", "thermostat", "--method", "rrt", "--trials", "3", "--threads", "2", "--db", "k.sqlite",
            "--quiet"};
  }

  // Starts `hyfal run` in work(), its output discarded; returns its pid.
  pid_t spawn_run() {
    const std::string bin = binary();
    Args args = run_args();
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(bin.c_str()));
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string dir = work().string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (::chdir(dir.c_str()) != 0) ::_exit(126);
      const int null = ::open("/dev/null", O_RDWR);
      ::dup2(null, 0), ::dup2(null, 1), ::dup2(null, 2);
      ::execv(bin.c_str(), argv.data());
      ::_exit(127);
    }
    return pid;
  }

  // Kills pid (if it still runs) and reaps it; true if the kill ended it (it had not exited yet).
  static bool kill_and_reap(pid_t pid) {
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  }

  Result run_hyfal_bin(const Args& args) { return run_hyfal(work(), io(), args, 120, "", binary()); }

  // The files in work(), relative, sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> v;
    for (const auto& p : files_under(work())) v.push_back(fs::relative(p, work()).string());
    return v;
  }

  void clear_work() {
    fs::remove_all(work());
    fs::create_directories(work());
  }
};

// What one killed instant left, and whether everything after it was right.
struct Instant {
  std::string when;
  bool killed = false;        // the kill came before the run exited
  bool hot_journal = false;   // it left k.sqlite-journal
  bool had_database = false;  // it left k.sqlite
  std::string problem;        // empty: recovered as it should
};

TEST_F(StoreKillTest, AKilledStartUpNeverLocksTheDatabase) {
  // The uninterrupted run: what every recovery must store, and how long a run takes.
  const auto t0 = Clock::now();
  const Result reference = run_hyfal_bin(run_args());
  const double run_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  ASSERT_EQ(reference.code, 0) << reference;
  const std::string query = std::string("SELECT ") + kTrialColumns + " FROM trials ORDER BY trial_index";
  const SqlResult expected = sql(work() / "k.sqlite", query);
  ASSERT_TRUE(expected.ok) << expected.text;
  ASSERT_EQ(expected.rows.size(), 3u) << expected.text;
  const std::vector<std::string> expected_files = files();
  clear_work();

  // The instants: spread over the run from its spawn; aimed at the database file appearing in the
  // folder and swept over the next 1.2 ms; aimed at the first write into the database file and
  // swept over the next 50 µs. The old creation's window (page 1 written, the journal not yet
  // deleted: the defect's hot journal) opened with that write and lasted a fsync, on this
  // project's machine 0.4-0.8 ms after the file appeared.
  const int spread = 30 / kSlowdown, aimed = 50 / kSlowdown;
  enum Aim { from_spawn, at_creation, at_first_write };
  const auto aim_of = [&](int i) { return i < spread ? from_spawn : i < spread + aimed ? at_creation : at_first_write; };
  std::vector<Instant> instants;
  for (int i = 0; i < spread + 2 * aimed; ++i) {
    const Aim aim = aim_of(i);
    Instant instant;
    int watch = -1;
    if (aim != from_spawn) {
      watch = ::inotify_init1(IN_CLOEXEC | IN_NONBLOCK);
      ASSERT_GE(watch, 0);
      const std::uint32_t events = aim == at_creation ? IN_CREATE | IN_MOVED_TO : IN_MODIFY;
      ASSERT_GE(::inotify_add_watch(watch, work().c_str(), events), 0);
    }
    const auto start = Clock::now();
    const pid_t pid = spawn_run();
    ASSERT_GT(pid, 0);
    if (aim == from_spawn) {
      const auto delay = std::chrono::duration<double>(run_seconds * 1.2 * i / spread);
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(delay));
      instant.when = fmt_ms("after spawn", delay.count());
    } else {
      // Busy-wait on inotify (no sleep's wake-up latency), then on the clock.
      const int k = aim == at_creation ? i - spread : i - spread - aimed;
      const double after = (aim == at_creation ? 1.2e-3 : 0.05e-3) * k / aimed;
      bool seen = false;
      alignas(inotify_event) char buffer[4096];
      while (!seen && Clock::now() - start < std::chrono::seconds(30)) {
        const ssize_t got = ::read(watch, buffer, sizeof buffer);
        for (ssize_t at = 0; at < got;) {
          const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
          seen = seen || (event->len > 0 && std::string(event->name) == "k.sqlite");
          at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
        }
        int status = 0;
        if (!seen && ::waitpid(pid, &status, WNOHANG) == pid) break;  // exited without a file (cannot happen)
      }
      const auto created = Clock::now();
      while (std::chrono::duration<double>(Clock::now() - created).count() < after) {
      }
      instant.when = fmt_ms(aim == at_creation ? "after k.sqlite appeared" : "after the first write into k.sqlite", after);
      ::close(watch);
    }
    instant.killed = kill_and_reap(pid);
    instant.had_database = fs::exists(work() / "k.sqlite");
    instant.hot_journal = fs::exists(work() / "k.sqlite-journal");

    std::string problem;
    // A reader right after the kill: never the misleading readonly message.
    if (instant.had_database) {
      const Result early = run_hyfal_bin({"table", "--db", "k.sqlite"});
      if (contains(early.err, "readonly database")) problem += "table after the kill: " + early.err;
    }
    // The next run completes and stores exactly the uninterrupted run's trials.
    const Result again = run_hyfal_bin(run_args());
    if (again.code != 0) problem += "the next run failed: " + again.err;
    const SqlResult stored = sql(work() / "k.sqlite", query);
    if (!stored.ok || stored.rows != expected.rows) problem += "stored trials differ:\n" + stored.text;
    const Result table = run_hyfal_bin({"table", "--db", "k.sqlite"});
    if (table.code != 0 || !contains(table.out, "| thermostat |")) problem += "table failed: " + table.err;
    // Nothing left behind: no journal, no -wal/-shm, no temporary file; the file takes a write lock.
    if (files() != expected_files) {
      problem += "files left:";
      for (const auto& f : files()) problem += " " + f;
      problem += "\n";
    }
    const SqlResult lock = sql(work() / "k.sqlite", "BEGIN IMMEDIATE; COMMIT;");
    if (!lock.ok) problem += "no write lock: " + lock.text;
    instant.problem = problem;
    instants.push_back(instant);
    if (std::getenv("HYFAL_KILL_TEST_VERBOSE"))
      std::cout << instant.when << ": killed " << instant.killed << ", database " << instant.had_database
                << ", journal " << instant.hot_journal << (problem.empty() ? "" : ", PROBLEM " + problem) << "\n";
    clear_work();
  }

  int killed = 0, with_database = 0, journals = 0, recovered = 0;
  std::string problems;
  for (const auto& instant : instants) {
    killed += instant.killed;
    with_database += instant.killed && instant.had_database;
    journals += instant.hot_journal;
    recovered += instant.killed && instant.problem.empty();
    if (!instant.problem.empty()) problems += "- killed " + instant.when + ": " + instant.problem + "\n";
  }
  std::cout << instants.size() << " instants: " << killed << " killed the run before it ended (" << with_database
            << " of them with a database file already there, " << journals << " with a hot journal), " << recovered
            << " recovered\n";
  EXPECT_TRUE(problems.empty()) << problems;
  // The sweep reached the start-up it is about: kills before, during and after the creation.
  EXPECT_GE(killed, static_cast<int>(instants.size()) / 3);
  EXPECT_GT(with_database, 0);
}

}  // namespace
