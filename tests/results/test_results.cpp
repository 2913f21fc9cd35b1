// Tests of results/: the SQLite trial store, the sample statistics and the table writers.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "results/statistics.hpp"
#include "results/store.hpp"
#include "results/table_writer.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// summarize

TEST(Summarize, HandComputedSample) {
  const std::vector<double> sample{5, 3, 1, 4, 2};  // unsorted on purpose: the median sorts
  const SampleSummary summary = summarize(sample);
  EXPECT_EQ(summary.n, 5u);
  EXPECT_DOUBLE_EQ(summary.mean, 3.0);
  EXPECT_DOUBLE_EQ(summary.median, 3.0);
  EXPECT_NEAR(summary.stddev, 1.5811388, 1e-7);  // sqrt(10 / 4)
  // t(0.975, 4) = 2.776445; half-width = 2.776445 * 1.5811388 / sqrt(5) = 1.963243
  EXPECT_NEAR(summary.ci_low, 3.0 - 1.963243, 1e-6);
  EXPECT_NEAR(summary.ci_high, 3.0 + 1.963243, 1e-6);
  EXPECT_EQ(sample, (std::vector<double>{5, 3, 1, 4, 2}));  // the input is left untouched
}

TEST(Summarize, EvenCountMedianIsMeanOfMiddleTwo) {
  const std::vector<double> sample{10, 1, 4, 2};
  const SampleSummary summary = summarize(sample);
  EXPECT_DOUBLE_EQ(summary.median, 3.0);
  EXPECT_DOUBLE_EQ(summary.mean, 4.25);
  // t(0.975, 1) = 12.7062047 for n = 2: the interval is wide.
  const SampleSummary pair = summarize(std::vector<double>{1, 3});
  EXPECT_NEAR(pair.ci_high - pair.mean, 12.7062047 * std::sqrt(2.0) / std::sqrt(2.0), 1e-6);
}

TEST(Summarize, SingleValueHasNoSpreadOrInterval) {
  const SampleSummary summary = summarize(std::vector<double>{7.5});
  EXPECT_EQ(summary.n, 1u);
  EXPECT_DOUBLE_EQ(summary.mean, 7.5);
  EXPECT_DOUBLE_EQ(summary.median, 7.5);
  EXPECT_TRUE(std::isnan(summary.stddev));
  EXPECT_TRUE(std::isnan(summary.ci_low));
  EXPECT_TRUE(std::isnan(summary.ci_high));
}

TEST(Summarize, EmptySampleIsAllNaN) {
  const SampleSummary summary = summarize(std::span<const double>{});
  EXPECT_EQ(summary.n, 0u);
  EXPECT_TRUE(std::isnan(summary.mean));
  EXPECT_TRUE(std::isnan(summary.median));
  EXPECT_TRUE(std::isnan(summary.stddev));
  EXPECT_TRUE(std::isnan(summary.ci_low));
  EXPECT_TRUE(std::isnan(summary.ci_high));
}

// ---------------------------------------------------------------------------------------------
// TrialStore

TrialRecord make_record(std::string method, std::int64_t trial_index,
                        TrialStatus status = TrialStatus::falsified) {
  TrialRecord record;
  record.key = TrialKey{.experiment = "exp1",
                        .suite = "arch",
                        .instance = R"({"name":"at1","T":20})",
                        .method = std::move(method),
                        .config = R"({"budget":1000})",
                        .trial_index = trial_index};
  record.seed = 0x7fff'ffff'ffff'fc00 + trial_index;  // near the 63-bit limit on purpose
  record.status = status;
  record.wall_s = 1.25 + static_cast<double>(trial_index);
  record.cpu_s = 4.5;
  record.nodes = 1000 + trial_index;
  return record;
}

// A temporary directory of its own for each test, removed afterwards.
class TrialStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = fmt::format("hyfal_test_results_{}_{}_{}", ::getpid(), test->test_suite_name(), test->name());
    std::replace(name.begin(), name.end(), '/', '_');  // parameterized tests: Suite/Test/Param
    directory_ = fs::temp_directory_path() / name;
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string database_path() const { return (directory_ / "results.db").string(); }

  // Runs a query through a connection of its own and returns the first column of its first row.
  std::string query_text(const std::string& path, const char* sql) const {
    sqlite3* connection = nullptr;
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &connection, SQLITE_OPEN_READONLY, nullptr),
              SQLITE_OK);
    sqlite3_stmt* statement = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(connection, sql, -1, &statement, nullptr), SQLITE_OK)
        << sqlite3_errmsg(connection);
    std::string text = "<no row>";
    if (sqlite3_step(statement) == SQLITE_ROW) {
      const auto* chars = sqlite3_column_text(statement, 0);
      text = chars == nullptr ? "<null>" : reinterpret_cast<const char*>(chars);
    }
    sqlite3_finalize(statement);
    sqlite3_close(connection);
    return text;
  }

  fs::path directory_;
};

void expect_same_record(const TrialRecord& actual, const TrialRecord& expected) {
  EXPECT_EQ(actual.key, expected.key);
  EXPECT_EQ(actual.seed, expected.seed);
  EXPECT_EQ(actual.status, expected.status);
  EXPECT_EQ(actual.validated, expected.validated);
  EXPECT_DOUBLE_EQ(actual.wall_s, expected.wall_s);
  EXPECT_DOUBLE_EQ(actual.cpu_s, expected.cpu_s);
  EXPECT_EQ(actual.nodes, expected.nodes);
  EXPECT_EQ(actual.propagations, expected.propagations);
  EXPECT_EQ(actual.integration_steps, expected.integration_steps);
  EXPECT_EQ(actual.witness, expected.witness);
  EXPECT_EQ(actual.error, expected.error);
  EXPECT_EQ(actual.threads, expected.threads);
  EXPECT_EQ(actual.host, expected.host);
  EXPECT_EQ(actual.git_commit, expected.git_commit);
  EXPECT_EQ(actual.started_at, expected.started_at);
  EXPECT_EQ(actual.finished_at, expected.finished_at);
}

TEST_F(TrialStoreTest, RoundTripsEveryField) {
  TrialRecord falsified = make_record("rrt", 1);
  falsified.validated = true;
  falsified.propagations = 123456789012;
  falsified.integration_steps = 987654;
  falsified.witness = "witnesses/arch/at1/rrt-1.json";
  falsified.threads = 16;
  falsified.host = "node-07";
  falsified.git_commit = "0123456789abcdef";
  falsified.started_at = "2026-11-22T03:14:15.123Z";
  falsified.finished_at = "2026-11-22T03:14:16.373Z";

  TrialRecord failed = make_record("cma-es", 0, TrialStatus::error);
  failed.error = "integrator diverged: step size 1e-17 at t = 3.2";
  failed.threads = 4;
  failed.host = "node-08";
  failed.git_commit = "fedcba9876543210";
  failed.started_at = "2026-11-22T04:00:00.000Z";
  failed.finished_at = "2026-11-22T04:00:01.000Z";

  auto store = TrialStore::open(database_path());
  const std::int64_t falsified_id = store.insert(falsified);
  const std::int64_t failed_id = store.insert(failed);
  EXPECT_NE(falsified_id, failed_id);

  const std::vector<TrialRecord> loaded = store.load();
  ASSERT_EQ(loaded.size(), 2u);
  // Ordered by method within the same suite and instance: "cma-es" < "rrt".
  expect_same_record(loaded[0], failed);
  expect_same_record(loaded[1], falsified);

  // Empty witness and error are stored as NULL, not as empty text.
  EXPECT_EQ(query_text(database_path(),
                       "SELECT witness FROM trials WHERE method = 'cma-es'"),
            "<null>");
  EXPECT_EQ(query_text(database_path(), "SELECT error FROM trials WHERE method = 'rrt'"),
            "<null>");
  EXPECT_EQ(query_text(database_path(), "SELECT status FROM trials WHERE method = 'rrt'"),
            "falsified");
}

TEST_F(TrialStoreTest, DuplicateKeyThrows) {
  auto store = TrialStore::open(database_path());
  store.insert(make_record("rrt", 3));
  TrialRecord same_key = make_record("rrt", 3);
  same_key.seed = 42;  // only the key decides what is a duplicate
  EXPECT_THROW(store.insert(same_key), StoreError);
  EXPECT_EQ(store.load().size(), 1u);
  // The failed insert leaves the store usable.
  EXPECT_NO_THROW(store.insert(make_record("rrt", 4)));
  EXPECT_EQ(store.load().size(), 2u);
}

TEST_F(TrialStoreTest, AnErroredTrialIsRetriedAndReplaced) {
  TrialStore store = TrialStore::open(database_path());
  store.insert(make_record("rrt", 0, TrialStatus::error));
  store.insert(make_record("rrt", 1));
  EXPECT_EQ(store.stored_trial_indices(make_record("rrt", 0).key), (std::set<std::int64_t>{1}));
  TrialRecord retry = make_record("rrt", 0);
  retry.series = {{"coverage", {{1.0, 0.5}}}};
  store.insert(retry);  // replaces the error row, no duplicate
  const auto rows = store.load();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, TrialStatus::falsified);
  EXPECT_EQ(store.stored_trial_indices(make_record("rrt", 0).key), (std::set<std::int64_t>{0, 1}));
  EXPECT_THROW(store.insert(make_record("rrt", 0)), StoreError);  // a real result is never replaced
}

TEST_F(TrialStoreTest, SeriesAreStoredWithTheirTrialAndReadBackInOrder) {
  TrialStore store = TrialStore::open(database_path());
  TrialRecord r = make_record("rrt", 2);
  r.series = {{"coverage", {{100.0, 0.1}, {200.0, 0.15}, {300.0, 0.18}}}, {"beta", {{50.0, 1.0}}}};
  store.insert(r);
  EXPECT_EQ(store.series_of(r.key, "coverage"),
            (std::vector<std::pair<double, double>>{{100.0, 0.1}, {200.0, 0.15}, {300.0, 0.18}}));
  EXPECT_EQ(store.series_of(r.key, "beta").size(), 1u);
  EXPECT_TRUE(store.series_of(r.key, "missing").empty());
  TrialKey other = r.key;
  other.trial_index = 3;
  EXPECT_TRUE(store.series_of(other, "coverage").empty());
}

TEST_F(TrialStoreTest, StoredTrialIndicesOfOneKey) {
  auto store = TrialStore::open(database_path());
  for (const std::int64_t index : {5, 0, 2}) store.insert(make_record("rrt", index));
  store.insert(make_record("cma-es", 1));

  EXPECT_EQ(store.stored_trial_indices(make_record("rrt", 99).key),
            (std::set<std::int64_t>{0, 2, 5}));
  EXPECT_EQ(store.stored_trial_indices(make_record("cma-es", 0).key),
            (std::set<std::int64_t>{1}));
  TrialKey other_experiment = make_record("rrt", 0).key;
  other_experiment.experiment = "exp2";
  EXPECT_TRUE(store.stored_trial_indices(other_experiment).empty());
}

TEST_F(TrialStoreTest, RowsSurviveClosingAndReopening) {
  {
    auto store = TrialStore::open(database_path());
    store.insert(make_record("rrt", 0));
    TrialRecord second_experiment = make_record("rrt", 0);
    second_experiment.key.experiment = "exp0";
    store.insert(second_experiment);
  }
  auto reopened = TrialStore::open(database_path());
  EXPECT_EQ(reopened.experiments(), (std::vector<std::string>{"exp0", "exp1"}));
  EXPECT_EQ(reopened.load().size(), 2u);
  const std::vector<TrialRecord> exp1 = reopened.load("exp1");
  ASSERT_EQ(exp1.size(), 1u);
  expect_same_record(exp1[0], make_record("rrt", 0));
  EXPECT_TRUE(reopened.load("absent").empty());
}

TEST_F(TrialStoreTest, LoadOrdersByGroupThenTrialIndex) {
  auto store = TrialStore::open(database_path());
  store.insert(make_record("rrt", 2));
  store.insert(make_record("cma-es", 1));
  store.insert(make_record("rrt", 0));
  store.insert(make_record("cma-es", 0));
  std::vector<std::pair<std::string, std::int64_t>> order;
  for (const TrialRecord& record : store.load())
    order.emplace_back(record.key.method, record.key.trial_index);
  EXPECT_EQ(order, (std::vector<std::pair<std::string, std::int64_t>>{
                       {"cma-es", 0}, {"cma-es", 1}, {"rrt", 0}, {"rrt", 2}}));
}

TEST_F(TrialStoreTest, MovedStoreKeepsWorking) {
  auto first = TrialStore::open(database_path());
  first.insert(make_record("rrt", 0));
  TrialStore moved = std::move(first);
  moved.insert(make_record("rrt", 1));
  auto other = TrialStore::open((directory_ / "other.db").string());
  other = std::move(moved);  // closes other.db, takes over results.db
  EXPECT_EQ(other.load().size(), 2u);
  EXPECT_EQ(other.path(), database_path());
}

TEST_F(TrialStoreTest, CreatesMissingParentDirectories) {
  const std::string nested = (directory_ / "a" / "b" / "results.db").string();
  auto store = TrialStore::open(nested);
  store.insert(make_record("rrt", 0));
  EXPECT_TRUE(fs::is_regular_file(nested));
}

TEST_F(TrialStoreTest, TextFileIsNotADatabase) {
  const std::string path = (directory_ / "notes.txt").string();
  std::ofstream(path) << "these are notes, not a SQLite database\n"
                      << std::string(2000, 'x') << "\n";
  try {
    TrialStore::open(path);
    FAIL() << "opening a text file did not throw";
  } catch (const StoreError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'" + path + "' is not a hyfal results database"), std::string::npos)
        << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    EXPECT_EQ(error.kind(), StoreErrorKind::bad_input);
  }
}

TEST_F(TrialStoreTest, DirectoryIsNotADatabase) {
  const std::string path = (directory_ / "a_directory").string();
  fs::create_directories(path);
  for (const bool read_only : {false, true}) {
    try {
      if (read_only)
        TrialStore::open_read_only(path);
      else
        TrialStore::open(path);
      FAIL() << "opening a directory did not throw";
    } catch (const StoreError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_EQ(error.kind(), StoreErrorKind::bad_input);
    }
  }
}

TEST_F(TrialStoreTest, UsesWalAndRecordsSchemaVersion) {
  auto store = TrialStore::open(database_path());
  EXPECT_EQ(query_text(database_path(), "PRAGMA journal_mode"), "wal");
  EXPECT_EQ(query_text(database_path(), "SELECT value FROM meta WHERE key = 'schema_version'"),
            "2");
}

// A database of schema 1 (before the status `budget`: a budget stop was `node_cap`) as a run of
// that time wrote it: the schema's own text, three node_cap rows and a series point.
void write_schema_1_database(const std::string& path) {
  sqlite3* c = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &c), SQLITE_OK);
  const char* sql = R"sql(
PRAGMA journal_mode = WAL;
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
INSERT INTO meta VALUES ('schema_version', '1');
CREATE TABLE trials (
  id INTEGER PRIMARY KEY, experiment TEXT NOT NULL, suite TEXT NOT NULL, instance TEXT NOT NULL,
  method TEXT NOT NULL, config TEXT NOT NULL, trial_index INTEGER NOT NULL, seed INTEGER NOT NULL,
  status TEXT NOT NULL CHECK (status IN ('falsified', 'not_found', 'timeout', 'node_cap', 'error')),
  validated INTEGER NOT NULL CHECK (validated IN (0, 1)), wall_s REAL NOT NULL, cpu_s REAL NOT NULL,
  nodes INTEGER NOT NULL, propagations INTEGER NOT NULL, integration_steps INTEGER NOT NULL, witness TEXT,
  error TEXT, threads INTEGER NOT NULL, host TEXT NOT NULL, git_commit TEXT NOT NULL, started_at TEXT NOT NULL,
  finished_at TEXT NOT NULL, metrics TEXT NOT NULL DEFAULT '{}',
  UNIQUE (experiment, suite, instance, method, config, trial_index));
CREATE TABLE series (trial_id INTEGER NOT NULL REFERENCES trials (id), name TEXT NOT NULL, x REAL NOT NULL,
  y REAL NOT NULL);
CREATE INDEX series_by_trial ON series (trial_id, name);
INSERT INTO trials VALUES (1, 'e', 'cc', '{}', 'cmaes', '{"master_seed":1,"max_nodes":1000000,"options":{"budget":40},"timeout_s":60.0}',
  0, 1, 'node_cap', 0, 1.0, 1.0, 40, 40, 9, NULL, NULL, 1, 'h', 'g', 's', 'f', '{}');
INSERT INTO trials VALUES (2, 'e', 'cc', '{}', 'cmaes', '{"master_seed":1,"max_nodes":7,"options":{"budget":40},"timeout_s":60.0}',
  0, 1, 'node_cap', 0, 1.0, 1.0, 7, 7, 9, NULL, NULL, 1, 'h', 'g', 's', 'f', '{}');
INSERT INTO trials VALUES (3, 'e', 'navigation', '{}', 'rrt', '{"master_seed":1,"max_nodes":500,"options":{"goal_bias":0.05},"timeout_s":60.0}',
  0, 1, 'node_cap', 0, 1.0, 1.0, 500, 500, 9, NULL, NULL, 1, 'h', 'g', 's', 'f', '{}');
INSERT INTO series VALUES (1, 'coverage', 1.0, 0.5);
)sql";
  ASSERT_EQ(sqlite3_exec(c, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(c);
  sqlite3_close(c);
}

// Schema 1's budget stops read as `budget` (a node_cap row whose config sets a budget and that
// has fewer nodes than its node cap; the real node caps stay); a reader changes nothing; a
// writer migrates the file to schema 2, the mapping written, the series kept, and `budget` rows
// can then be stored.
TEST_F(TrialStoreTest, ASchema1DatabaseReadsItsBudgetStopsAsBudgetAndIsMigratedByAWriter) {
  write_schema_1_database(database_path());
  const auto statuses = [](const std::vector<TrialRecord>& rows) {
    std::vector<TrialStatus> s;
    for (const auto& r : rows) s.push_back(r.status);
    return s;
  };
  // load() orders by suite, instance, method, config: the cc rows (max_nodes 1000000, then 7), then navigation.
  const std::vector<TrialStatus> expected{TrialStatus::budget, TrialStatus::node_cap, TrialStatus::node_cap};
  {
    auto reader = TrialStore::open_read_only(database_path());
    EXPECT_EQ(statuses(reader.load()), expected);
  }
  EXPECT_EQ(query_text(database_path(), "SELECT value FROM meta WHERE key = 'schema_version'"), "1");
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM trials WHERE status = 'node_cap'"), "3");
  {
    auto writer = TrialStore::open(database_path());
    const auto rows = writer.load_with_series();
    EXPECT_EQ(statuses(rows), expected);
    ASSERT_EQ(rows[0].series.size(), 1u);
    EXPECT_EQ(rows[0].series[0].first, "coverage");
    writer.insert(make_record("adaptive", 0, TrialStatus::budget));
  }
  EXPECT_EQ(query_text(database_path(), "SELECT value FROM meta WHERE key = 'schema_version'"), "2");
  EXPECT_EQ(query_text(database_path(), "SELECT status FROM trials WHERE id = 1"), "budget");
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM trials WHERE status = 'budget'"), "2");
  EXPECT_EQ(query_text(database_path(), "PRAGMA foreign_key_check"), "<no row>");
  auto again = TrialStore::open(database_path());  // a second writer finds schema 2: nothing to do
  EXPECT_EQ(again.load().size(), 4u);
}

// A child process that dies inside a write transaction in rollback-journal mode, its dirty pages
// spilled to the file (a cache of two pages), leaves the file half-written beside a hot journal:
// what a run killed while its new database switched to WAL left behind (issue 39).
void die_inside_a_write(const std::string& path) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    sqlite3* connection = nullptr;
    if (sqlite3_open(path.c_str(), &connection) != SQLITE_OK) ::_exit(1);
    const auto run = [&](const char* sql) {
      if (sqlite3_exec(connection, sql, nullptr, nullptr, nullptr) != SQLITE_OK) ::_exit(2);
    };
    run("PRAGMA journal_mode = DELETE");
    run("PRAGMA cache_size = 2");
    run("BEGIN IMMEDIATE");
    run("CREATE TABLE filler (x)");
    for (int i = 0; i < 200; ++i) run("INSERT INTO filler VALUES (randomblob(2000))");
    ::_exit(0);  // no COMMIT, no close: as SIGKILL would leave it
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  ASSERT_TRUE(fs::exists(path + "-journal")) << "the child left no journal";
}

// A run killed while it created its database left a hot journal that the read-only schema check
// could not roll back: every later open failed with "attempt to write a readonly database".
TEST_F(TrialStoreTest, ADatabaseWhoseCreationWasKilledOpensAgain) {
  die_inside_a_write(database_path());
  ASSERT_GT(fs::file_size(database_path()), 0u);
  {
    TrialStore store = TrialStore::open(database_path());
    store.insert(make_record("rrt", 0));
  }
  EXPECT_FALSE(fs::exists(database_path() + "-journal"));
  EXPECT_EQ(TrialStore::open_read_only(database_path()).load().size(), 1u);
  EXPECT_EQ(query_text(database_path(), "PRAGMA journal_mode"), "wal");
}

// A reader (hyfal table) on a database with a hot journal rolls it back and reads the last
// commit, instead of failing with "attempt to write a readonly database".
TEST_F(TrialStoreTest, AReaderRollsBackAHotJournalAndReadsTheLastCommit) {
  {
    TrialStore store = TrialStore::open(database_path());
    store.insert(make_record("rrt", 0));
    store.insert(make_record("rrt", 1));
  }
  die_inside_a_write(database_path());
  try {
    EXPECT_EQ(TrialStore::open_read_only(database_path()).load().size(), 2u);
  } catch (const StoreError& e) {
    ADD_FAILURE() << e.what();
  }
  EXPECT_FALSE(fs::exists(database_path() + "-journal"));
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM sqlite_master WHERE name = 'filler'"), "0");
  TrialStore store = TrialStore::open(database_path());  // and a writer goes on with it, in WAL mode
  store.insert(make_record("rrt", 2));
  EXPECT_EQ(store.load().size(), 3u);
  EXPECT_EQ(query_text(database_path(), "PRAGMA journal_mode"), "wal");
}

// A new database is created whole (built unnamed, linked into place): in WAL mode and with its
// schema before any other process can see the file.
TEST_F(TrialStoreTest, ANewDatabaseAppearsWithItsSchemaInWalMode) {
  const std::string path = (directory_ / "sub" / "new.db").string();
  TrialStore store = TrialStore::open(path);
  std::ifstream in(path, std::ios::binary);
  char header[20] = {};
  in.read(header, sizeof header);
  EXPECT_EQ(header[18], 2);  // file format write and read versions: WAL
  EXPECT_EQ(header[19], 2);
  EXPECT_EQ(query_text(path, "SELECT count(*) FROM sqlite_master WHERE type = 'table'"), "4");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(directory_ / "sub")) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names.front(), "new.db");  // and no temporary file beside it (-wal/-shm of the open store aside)
  for (const auto& name : names) EXPECT_EQ(name.rfind("new.db", 0), 0u) << name;
}

TEST_F(TrialStoreTest, StoresSeriesOfATrial) {
  auto store = TrialStore::open(database_path());
  const std::int64_t trial_id = store.insert(make_record("rrt", 0));
  const std::vector<std::pair<double, double>> coverage{{0, 0.0}, {100, 0.25}, {200, 0.5}};
  store.insert_series(trial_id, "coverage", coverage);
  EXPECT_EQ(query_text(database_path(),
                       "SELECT count(*) || ':' || sum(y) FROM series WHERE name = 'coverage'"),
            "3:0.75");
  // A series of a trial that does not exist is refused, and none of its points is kept.
  EXPECT_THROW(store.insert_series(trial_id + 1000, "coverage", coverage), StoreError);
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM series"), "3");
}

// ---------------------------------------------------------------------------------------------
// Checking before writing (no file that is not a hyfal database is ever changed), read-only
// readers, error kinds.

// Runs SQL through a plain connection of its own (read-write, no hyfal involved).
void exec_sql(const std::string& path, const std::string& sql) {
  sqlite3* connection = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &connection, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr),
            SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(connection, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  sqlite3_close(connection);
  ASSERT_EQ(rc, SQLITE_OK) << message << "\n" << sql;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The SQLite side files of path that exist.
std::vector<std::string> side_files(const std::string& path) {
  std::vector<std::string> found;
  for (const char* suffix : {"-wal", "-shm", "-journal"})
    if (fs::exists(path + suffix)) found.push_back(path + suffix);
  return found;
}

struct ForeignFile {
  const char* name;
  const char* sql;       // run on a new database; nullptr: text is written instead
  const char* text;
  const char* message;   // a part of the error
};

class ForeignFileTest : public TrialStoreTest, public ::testing::WithParamInterface<ForeignFile> {};

TEST_P(ForeignFileTest, IsRefusedAsBadInputAndLeftByteIdentical) {
  const ForeignFile& file = GetParam();
  const std::string path = (directory_ / "foreign.db").string();
  if (file.sql) {
    exec_sql(path, file.sql);
    ASSERT_FALSE(HasFailure());
  } else {
    std::ofstream(path, std::ios::binary) << file.text;
  }
  ASSERT_TRUE(side_files(path).empty());
  const std::string before = file_bytes(path);
  for (const bool read_only : {false, true}) {
    SCOPED_TRACE(read_only ? "open_read_only" : "open");
    try {
      if (read_only)
        TrialStore::open_read_only(path);
      else
        TrialStore::open(path);
      ADD_FAILURE() << "opened";
    } catch (const StoreError& error) {
      EXPECT_EQ(error.kind(), StoreErrorKind::bad_input) << error.what();
      EXPECT_NE(std::string(error.what()).find(file.message), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    }
    EXPECT_EQ(file_bytes(path), before) << "the file was changed";
    EXPECT_TRUE(side_files(path).empty()) << side_files(path).front();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Store, ForeignFileTest,
    ::testing::Values(
        ForeignFile{"UnrelatedSqlite", "CREATE TABLE people (name TEXT); INSERT INTO people VALUES ('ada');",
                    nullptr, "is not a hyfal results database: it has no table 'meta'"},
        ForeignFile{"UnrelatedSqliteInWalMode",
                    "PRAGMA journal_mode = WAL; CREATE TABLE people (name TEXT); INSERT INTO people VALUES ('ada');",
                    nullptr, "is not a hyfal results database: it has no table 'meta'"},
        ForeignFile{"SchemaVersion3",
                    "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);"
                    "INSERT INTO meta VALUES ('schema_version', '3'); CREATE TABLE trials (id INTEGER);",
                    nullptr, "schema version 3 is not supported by this build (reads 1 and 2)"},
        ForeignFile{"DifferentTrialsTable",
                    "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);"
                    "INSERT INTO meta VALUES ('schema_version', '1');"
                    "CREATE TABLE trials (id INTEGER PRIMARY KEY, name TEXT);"
                    "CREATE TABLE series (trial_id INTEGER, name TEXT, x REAL, y REAL);",
                    nullptr, "its table 'trials' has no column"},
        ForeignFile{"MetaWithoutVersion", "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);",
                    nullptr, "holds no schema_version"},
        ForeignFile{"TextFile", nullptr, "name,score\nada,3\n", "it is not a SQLite database"},
        ForeignFile{"TruncatedHeader", nullptr, "SQLite format", "it is not a SQLite database"}),
    [](const ::testing::TestParamInfo<ForeignFile>& info) { return std::string(info.param.name); });

TEST_F(TrialStoreTest, EmptyPathIsBadInput) {
  try {
    TrialStore::open("");
    FAIL() << "opened an empty path";
  } catch (const StoreError& error) {
    EXPECT_EQ(error.kind(), StoreErrorKind::bad_input);
  }
}

TEST_F(TrialStoreTest, EmptyFileAndTablelessDatabaseGetTheSchema) {
  const std::string empty = (directory_ / "empty.db").string();
  std::ofstream(empty).close();
  TrialStore::open(empty).insert(make_record("rrt", 0));
  EXPECT_EQ(query_text(empty, "SELECT count(*) FROM trials"), "1");
  // A SQLite database with no table yet (e.g. one another process is creating right now).
  const std::string tableless = (directory_ / "tableless.db").string();
  exec_sql(tableless, "PRAGMA user_version = 0");
  TrialStore::open(tableless).insert(make_record("rrt", 0));
  EXPECT_EQ(query_text(tableless, "SELECT count(*) FROM trials"), "1");
  // A reader does not create anything in an empty file.
  const std::string empty2 = (directory_ / "empty2.db").string();
  std::ofstream(empty2).close();
  EXPECT_THROW(TrialStore::open_read_only(empty2), StoreError);
  EXPECT_EQ(fs::file_size(empty2), 0u);
}

TEST_F(TrialStoreTest, DatabaseWithoutClaimsTableStillOpens) {
  { TrialStore::open(database_path()).insert(make_record("rrt", 0)); }
  exec_sql(database_path(), "DROP TABLE claims");
  {
    auto reader = TrialStore::open_read_only(database_path());
    EXPECT_EQ(reader.load().size(), 1u);
  }
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM sqlite_master WHERE name = 'claims'"), "0")
      << "a reader adds nothing";
  auto writer = TrialStore::open(database_path());
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM sqlite_master WHERE name = 'claims'"), "1");
  EXPECT_TRUE(writer.claim(make_record("rrt", 1).key, ClaimOwner::this_process()));
}

TEST_F(TrialStoreTest, ReaderLeavesNoFilesAndTheBytesUnchanged) {
  { TrialStore::open(database_path()).insert(make_record("rrt", 0)); }
  ASSERT_TRUE(side_files(database_path()).empty()) << "the writer removes its -wal/-shm at close";
  const std::string before = file_bytes(database_path());
  {
    auto reader = TrialStore::open_read_only(database_path());
    EXPECT_EQ(reader.load().size(), 1u);
    EXPECT_EQ(reader.experiments(), (std::vector<std::string>{"exp1"}));
    EXPECT_THROW(reader.insert(make_record("rrt", 1)), std::logic_error);
    EXPECT_THROW(reader.claim(make_record("rrt", 1).key, ClaimOwner::this_process()), std::logic_error);
  }
  EXPECT_TRUE(side_files(database_path()).empty()) << side_files(database_path()).front();
  EXPECT_EQ(file_bytes(database_path()), before);
  // Moving a reader over another closes the latter and cleans up after it as well.
  {
    auto first = TrialStore::open_read_only(database_path());
    auto second = TrialStore::open_read_only(database_path());
    first = std::move(second);
    EXPECT_EQ(first.load().size(), 1u);
  }
  EXPECT_TRUE(side_files(database_path()).empty());
}

TEST_F(TrialStoreTest, ReaderIsNotBlockedByAnOpenWriteTransaction) {
  auto writer = TrialStore::open(database_path());
  writer.insert(make_record("rrt", 0));
  writer.insert(make_record("rrt", 1));
  // A second connection holds the write lock with an uncommitted row.
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open_v2(database_path().c_str(), &holder, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(holder,
                         "BEGIN IMMEDIATE; INSERT INTO meta (key, value) VALUES ('uncommitted', 'x'); "
                         "DELETE FROM trials WHERE trial_index = 0;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  const auto t0 = std::chrono::steady_clock::now();
  {
    auto reader = TrialStore::open_read_only(database_path());
    EXPECT_EQ(reader.load().size(), 2u) << "the reader sees the last commit";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 1.0) << "the reader waited for the writer";
  sqlite3_exec(holder, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(holder);
}

TEST_F(TrialStoreTest, WriterLockedPastTheBusyTimeoutIsAnEnvironmentError) {
  auto store = TrialStore::open(database_path());
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open_v2(database_path().c_str(), &holder, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(holder, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  try {
    store.insert(make_record("rrt", 0));  // waits the 5 s busy timeout
    ADD_FAILURE() << "inserted past a held write lock";
  } catch (const StoreError& error) {
    EXPECT_EQ(error.kind(), StoreErrorKind::environment) << error.what();
    EXPECT_NE(std::string(error.what()).find("locked"), std::string::npos) << error.what();
  }
  sqlite3_exec(holder, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(holder);
  EXPECT_NO_THROW(store.insert(make_record("rrt", 0)));
}

// chattr +i makes a file or folder unwritable even for root (the tests run as root in CI, where
// chmod does not bite). Where chattr is not available (no CAP_LINUX_IMMUTABLE, a file system
// without the attribute) the test is skipped.
class Immutable {
 public:
  explicit Immutable(fs::path path) : path_(std::move(path)) {
    set_ = std::system(("chattr +i '" + path_.string() + "' 2>/dev/null").c_str()) == 0;
  }
  ~Immutable() {
    if (set_) [[maybe_unused]] const int rc = std::system(("chattr -i '" + path_.string() + "'").c_str());
  }
  bool set() const { return set_; }

 private:
  fs::path path_;
  bool set_ = false;
};

TEST_F(TrialStoreTest, ReaderWorksInAReadOnlyFolderAndOnAReadOnlyFile) {
  const fs::path folder = directory_ / "ro";
  const std::string path = (folder / "results.db").string();
  { TrialStore::open(path).insert(make_record("rrt", 0)); }
  const std::string before = file_bytes(path);
  {
    const Immutable lock(folder);
    if (!lock.set()) GTEST_SKIP() << "chattr +i is not available here";
    auto reader = TrialStore::open_read_only(path);
    EXPECT_EQ(reader.load().size(), 1u);
    // A writer cannot work there: that is the machine's refusal, not a bad path.
    try {
      TrialStore::open(path);
      ADD_FAILURE() << "opened for writing in a read-only folder";
    } catch (const StoreError& error) {
      EXPECT_EQ(error.kind(), StoreErrorKind::environment) << error.what();
    }
  }
  EXPECT_TRUE(side_files(path).empty());
  {
    const Immutable lock(path);
    ASSERT_TRUE(lock.set());
    auto reader = TrialStore::open_read_only(path);
    EXPECT_EQ(reader.load().size(), 1u);
  }
  EXPECT_TRUE(side_files(path).empty()) << side_files(path).front();
  EXPECT_EQ(file_bytes(path), before);
}

TEST_F(TrialStoreTest, PermissionLostMidRunIsAnEnvironmentError) {
  auto store = TrialStore::open(database_path());
  store.insert(make_record("rrt", 0));
  ASSERT_TRUE(fs::exists(database_path() + "-wal"));
  {
    const Immutable lock(database_path() + "-wal");  // the log the next commit must append to
    if (!lock.set()) GTEST_SKIP() << "chattr +i is not available here";
    try {
      store.insert(make_record("rrt", 1));
      ADD_FAILURE() << "committed to an unwritable log";
    } catch (const StoreError& error) {
      EXPECT_EQ(error.kind(), StoreErrorKind::environment) << error.what();
    }
  }
  EXPECT_NO_THROW(store.insert(make_record("rrt", 1))) << "the store works again once it may write";
  EXPECT_EQ(store.load().size(), 2u);
}

// ---------------------------------------------------------------------------------------------
// Claims: several processes on one experiment run each trial once.

// A process id that is not running (a child that has exited and been reaped).
std::int64_t dead_pid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  int status = 0;
  waitpid(child, &status, 0);
  return child;
}

ClaimOwner other_owner(const std::string& token) {
  ClaimOwner owner = ClaimOwner::this_process();  // same host, a live process ...
  owner.token = token;                            // ... but another owner
  return owner;
}

TEST_F(TrialStoreTest, ClaimIsExclusiveUntilTheTrialIsStored) {
  auto store = TrialStore::open(database_path());
  const ClaimOwner& self = ClaimOwner::this_process();
  const ClaimOwner other = other_owner("other-owner");
  const TrialKey key = make_record("rrt", 0).key;
  EXPECT_TRUE(store.claim(key, self));
  EXPECT_TRUE(store.claim(key, self)) << "claiming again is harmless";
  EXPECT_FALSE(store.claim(key, other)) << "a live owner keeps its claim";
  EXPECT_EQ(store.progress({key}, other), (std::vector<TrialProgress>{TrialProgress::claimed_by_other}));
  EXPECT_EQ(store.progress({key}, self), (std::vector<TrialProgress>{TrialProgress::needs_runner}))
      << "its own leftover claim does not make a process wait";
  store.insert(make_record("rrt", 0));
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM claims"), "0") << "storing ends the claim";
  EXPECT_FALSE(store.claim(key, other)) << "a stored trial is not run again";
  EXPECT_FALSE(store.claim(key, self));
  EXPECT_EQ(store.progress({key}, other), (std::vector<TrialProgress>{TrialProgress::stored}));

  // A trial stored as an error is retried; once retried (and unclaimed), it counts as done.
  const TrialKey errored = make_record("rrt", 1).key;
  store.insert(make_record("rrt", 1, TrialStatus::error));
  EXPECT_EQ(store.progress({errored}, self), (std::vector<TrialProgress>{TrialProgress::stored_error}));
  EXPECT_TRUE(store.claim(errored, other));
  EXPECT_EQ(store.progress({errored}, self), (std::vector<TrialProgress>{TrialProgress::claimed_by_other}));
  EXPECT_EQ(store.progress({make_record("rrt", 2).key}, self),
            (std::vector<TrialProgress>{TrialProgress::needs_runner}));
}

TEST_F(TrialStoreTest, StaleClaimsAreTakenOver) {
  auto store = TrialStore::open(database_path());
  const ClaimOwner& self = ClaimOwner::this_process();
  ASSERT_GT(self.process_start, 0) << "/proc/self/stat is readable on Linux";
  const auto claim_as = [&](std::int64_t index, ClaimOwner owner) {
    return store.claim(make_record("rrt", index).key, owner);
  };
  // A process on this host that has ended.
  ClaimOwner dead = other_owner("dead");
  dead.pid = dead_pid();
  ASSERT_TRUE(claim_as(0, dead));
  EXPECT_TRUE(claim_as(0, self)) << "the claim of an ended process is stale at once";
  // A reused pid: the pid runs, but it is another process (it started at another time).
  ClaimOwner reused = other_owner("reused");
  reused.process_start = self.process_start + 12345;
  ASSERT_TRUE(claim_as(1, reused));
  EXPECT_TRUE(claim_as(1, self));
  // A zombie is no longer running either.
  const pid_t zombie = fork();
  if (zombie == 0) _exit(0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // exited, not reaped yet
  ClaimOwner zombie_owner = other_owner("zombie");
  zombie_owner.pid = zombie;
  zombie_owner.process_start = 0;
  ASSERT_TRUE(claim_as(2, zombie_owner));
  EXPECT_TRUE(claim_as(2, self));
  int status = 0;
  waitpid(zombie, &status, 0);
  // Another host: alive while its heartbeat is fresh, stale after kClaimStaleAfter.
  ClaimOwner remote = other_owner("remote");
  remote.host = "another-host";
  remote.pid = dead_pid();  // says nothing about a process of another host
  ASSERT_TRUE(claim_as(3, remote));
  EXPECT_FALSE(claim_as(3, self));
  exec_sql(database_path(), fmt::format("UPDATE claims SET heartbeat = heartbeat - {} WHERE token = 'remote'",
                                        kClaimStaleAfter + 1));
  EXPECT_EQ(store.progress({make_record("rrt", 3).key}, self),
            (std::vector<TrialProgress>{TrialProgress::needs_runner}));
  EXPECT_TRUE(claim_as(3, self));
  EXPECT_EQ(query_text(database_path(), "SELECT group_concat(DISTINCT token) FROM claims"), self.token);
}

TEST_F(TrialStoreTest, HeartbeatRefreshesAndReleasesClaims) {
  auto store = TrialStore::open(database_path());
  ClaimOwner owner = other_owner("beating");
  for (const std::int64_t index : {0, 1, 2}) ASSERT_TRUE(store.claim(make_record("rrt", index).key, owner));
  exec_sql(database_path(), "UPDATE claims SET heartbeat = 0");
  EXPECT_EQ(store.refresh_claims(owner), 3);
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM claims WHERE heartbeat > 1e9"), "3");
  {
    const ClaimHeartbeat heartbeat(database_path(), owner);
  }  // a heartbeat that ends hands its owner's claims over
  EXPECT_EQ(query_text(database_path(), "SELECT count(*) FROM claims"), "0");
  EXPECT_EQ(store.refresh_claims(owner), 0);
}

// ---------------------------------------------------------------------------------------------
// summarize_trials

TEST(SummarizeTrials, GroupsInFirstAppearanceOrderAndCounts) {
  std::vector<TrialRecord> trials;
  auto add = [&](std::string method, std::int64_t index, TrialStatus status, double wall_s,
                 bool validated = false) {
    TrialRecord record = make_record(std::move(method), index, status);
    record.wall_s = wall_s;
    record.nodes = static_cast<std::int64_t>(wall_s * 100);
    record.validated = validated;
    trials.push_back(record);
  };
  add("rrt", 0, TrialStatus::falsified, 1.0, true);
  add("cma-es", 0, TrialStatus::not_found, 9.0);
  add("rrt", 1, TrialStatus::timeout, 10.0);
  add("rrt", 2, TrialStatus::error, 1000.0);  // excluded from the time and nodes statistics
  add("rrt", 3, TrialStatus::falsified, 4.0, true);
  add("rrt", 4, TrialStatus::node_cap, 7.0);

  const std::vector<GroupSummary> groups = summarize_trials(trials);
  ASSERT_EQ(groups.size(), 2u);
  const GroupSummary& rrt = groups[0];
  EXPECT_EQ(rrt.method, "rrt");
  EXPECT_EQ(rrt.suite, "arch");
  EXPECT_EQ(rrt.instance, R"({"name":"at1","T":20})");
  EXPECT_EQ(rrt.config, R"({"budget":1000})");
  EXPECT_EQ(rrt.n, 5u);
  EXPECT_EQ(rrt.falsified, 2u);
  EXPECT_EQ(rrt.validated, 2u);
  EXPECT_EQ(rrt.timeouts, 1u);
  EXPECT_EQ(rrt.node_caps, 1u);
  EXPECT_EQ(rrt.not_found, 0u);
  EXPECT_EQ(rrt.errors, 1u);
  EXPECT_DOUBLE_EQ(rrt.falsified_rate, 0.4);
  EXPECT_EQ(rrt.wall_s.n, 4u);
  EXPECT_DOUBLE_EQ(rrt.wall_s.mean, (1.0 + 10.0 + 4.0 + 7.0) / 4);
  EXPECT_DOUBLE_EQ(rrt.wall_s.median, 5.5);
  EXPECT_EQ(rrt.nodes.n, 4u);
  EXPECT_DOUBLE_EQ(rrt.nodes.median, 550.0);

  const GroupSummary& cma_es = groups[1];
  EXPECT_EQ(cma_es.method, "cma-es");
  EXPECT_EQ(cma_es.n, 1u);
  EXPECT_EQ(cma_es.not_found, 1u);
  EXPECT_DOUBLE_EQ(cma_es.falsified_rate, 0.0);
  EXPECT_DOUBLE_EQ(cma_es.wall_s.mean, 9.0);
  EXPECT_TRUE(std::isnan(cma_es.wall_s.stddev));
}

TEST(SummarizeTrials, ConfigSeparatesGroups) {
  TrialRecord small = make_record("rrt", 0);
  TrialRecord large = make_record("rrt", 0);
  large.key.config = R"({"budget":5000})";
  const std::vector<TrialRecord> trials{small, large, small};
  const std::vector<GroupSummary> groups = summarize_trials(trials);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].n, 2u);
  EXPECT_EQ(groups[1].config, R"({"budget":5000})");
}

// ---------------------------------------------------------------------------------------------
// table writers

std::vector<GroupSummary> summarize_statuses(const std::vector<TrialStatus>& statuses) {
  std::vector<TrialRecord> trials;
  for (std::size_t index = 0; index < statuses.size(); ++index)
    trials.push_back(make_record("rrt", static_cast<std::int64_t>(index), statuses[index]));
  return summarize_trials(trials);
}

TEST(ToMarkdown, MarksCensoredGroupsOnly) {
  using enum TrialStatus;
  const std::string uncensored = to_markdown(summarize_statuses({falsified, falsified, not_found}));
  EXPECT_EQ(uncensored.find("≥"), std::string::npos) << uncensored;
  EXPECT_EQ(uncensored.find("⏱"), std::string::npos) << uncensored;

  const std::string censored =
      to_markdown(summarize_statuses({falsified, timeout, timeout, timeout}));
  // Time and nodes medians and means are marked; the standard deviation is not a bound.
  // wall_s 1.25, 2.25, 3.25, 4.25: median and mean 2.75, std 1.29; nodes 1000..1003.
  EXPECT_NE(censored.find("| ≥2.75 | ≥2.75 ± "), std::string::npos) << censored;
  EXPECT_NE(censored.find(" | 1.29 | ≥100"), std::string::npos) << censored;
  EXPECT_NE(censored.find("| 3 ⏱ |"), std::string::npos) << censored;
  // The footnote explaining the mark follows the table.
  EXPECT_NE(censored.find("\n≥ "), std::string::npos) << censored;

  EXPECT_NE(to_markdown(summarize_statuses({falsified, node_cap})).find("≥"), std::string::npos);
  // A method's spent budget is named as such, apart from the run's node cap, and censors too.
  const std::string spent = to_markdown(summarize_statuses({falsified, budget, budget, budget, node_cap}));
  EXPECT_NE(spent.find("| 1 node cap, 3 budget |"), std::string::npos) << spent;
  EXPECT_NE(spent.find("≥"), std::string::npos) << spent;
  // CSV: n 2, falsified 0, validated 0, rate 0, timeouts 0, node_caps 0, budgets 2.
  EXPECT_NE(to_csv(summarize_statuses({budget, budget})).find(",2,0,0,0,0,0,2,0,0,"), std::string::npos);
}

TEST(ToMarkdown, HeaderAndConfigColumn) {
  const std::vector<GroupSummary> one_config = summarize_statuses({TrialStatus::falsified});
  const std::string table = to_markdown(one_config);
  EXPECT_EQ(table.substr(0, table.find('\n')),
            "| suite | instance | method | n | falsified | rate | time median (s) | "
            "time mean ± 95% CI (s) | time std | nodes median | nodes mean ± 95% CI | nodes std | stopped |");

  std::vector<GroupSummary> two_configs = one_config;
  two_configs.push_back(one_config.front());
  two_configs.back().config = R"({"budget":5000})";
  const std::string with_config = to_markdown(two_configs);
  EXPECT_NE(with_config.find("| method | config | n |"), std::string::npos) << with_config;
  EXPECT_NE(with_config.find(R"(| {"budget":5000} |)"), std::string::npos) << with_config;
}

TEST(ToMarkdown, FormatsTimesWithoutExponentAndNodesAsIntegers) {
  std::vector<TrialRecord> trials;
  for (const double wall_s : {0.0123, 0.0125}) {
    TrialRecord record = make_record("rrt", static_cast<std::int64_t>(trials.size()));
    record.wall_s = wall_s;
    record.nodes = trials.empty() ? 1000 : 1002;
    trials.push_back(record);
  }
  const std::string table = to_markdown(summarize_trials(trials));
  EXPECT_NE(table.find("| 0.0124 |"), std::string::npos) << table;   // time median
  EXPECT_NE(table.find("| 1001 |"), std::string::npos) << table;     // nodes median
  EXPECT_EQ(table.find("e-"), std::string::npos) << table;
}

TEST(ToCsv, HeaderQuotingAndEmptyNaN) {
  std::vector<GroupSummary> groups = summarize_statuses({TrialStatus::falsified});
  groups[0].instance = R"(at1, "fast")";
  const std::string csv = to_csv(groups);
  const std::string header =
      "suite,instance,method,config,n,falsified,validated,falsified_rate,timeouts,node_caps,budgets,"
      "not_found,errors,time_mean_s,time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,"
      "nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high\r\n";
  ASSERT_EQ(csv.substr(0, header.size()), header);
  // One trial: std and CI are NaN, written as empty fields.
  EXPECT_EQ(csv.substr(header.size()),
            "arch,\"at1, \"\"fast\"\"\",rrt,\"{\"\"budget\"\":1000}\",1,1,0,1,0,0,0,0,0,"
            "1.25,1.25,,,,1000,1000,,,\r\n");
}

TEST(ToCsv, FullPrecisionNumbers) {
  std::vector<GroupSummary> groups = summarize_statuses(
      {TrialStatus::falsified, TrialStatus::not_found, TrialStatus::not_found});
  const std::string csv = to_csv(groups);
  EXPECT_NE(csv.find(",0.3333333333333333,"), std::string::npos) << csv;  // falsified_rate
}

}  // namespace
}  // namespace hyfal
