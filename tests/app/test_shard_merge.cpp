// End-to-end tests of `--shard i/K`, `hyfal merge` and `--plan`: the built binary (HYFAL_BIN) runs
// as a child process in a fresh temporary directory per test (as in test_cli.cpp), and its exit
// status, output, databases (read with the sqlite3 command-line tool) and witness files are checked.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

#ifndef HYFAL_BIN
#error "HYFAL_BIN (the path of the built hyfal binary) must be defined"
#endif

namespace {

namespace fs = std::filesystem;

// Helpers: tests/cli_support.hpp
using namespace hyfal_cli_test;

// A trial as it must be equal across shards and the single-process run: its key and result.
const char* kTrialResult =
    "SELECT experiment, suite, instance, method, config, trial_index, seed, status, nodes, propagations, "
    "integration_steps FROM trials ORDER BY experiment, suite, instance, method, config, trial_index";
// Everything stored, but the row ids: what a second merge must leave unchanged.
const char* kEverything =
    "SELECT experiment, suite, instance, method, config, trial_index, seed, status, validated, wall_s, cpu_s, nodes, "
    "propagations, integration_steps, witness, error, threads, host, git_commit, started_at, finished_at, metrics "
    "FROM trials ORDER BY experiment, suite, instance, method, config, trial_index; "
    "SELECT t.trial_index, s.name, s.x, s.y FROM series s JOIN trials t ON s.trial_id = t.id "
    "ORDER BY t.experiment, t.suite, t.instance, t.method, t.config, t.trial_index, s.rowid;";

// trial_index -> witness path as stored ("" for none).
std::map<std::string, std::string> witnesses_of(const fs::path& db) {
  std::map<std::string, std::string> m;
  for (const auto& l : lines(sql(db, "SELECT trial_index, ifnull(witness, '') FROM trials").text)) {
    const auto bar = l.find('|');
    m[l.substr(0, bar)] = l.substr(bar + 1);
  }
  return m;
}

class ShardMergeTest : public HyfalBinaryTest {
 protected:
  ShardMergeTest() : HyfalBinaryTest("shard") {}

  // run --suite thermostat --trials 12 into db with witnesses under wit, as shard (or all).
  Result thermostat(const std::string& db, const std::string& wit, const std::string& shard = "") {
    Args a = {"run", "--suite", "thermostat", "--trials", "12", "--threads", "1", "--db", db, "--witness-dir", wit,
              "--quiet"};
    if (!shard.empty()) a.insert(a.end(), {"--shard", shard});
    return hyfal(a);
  }

  // The single-process run (single.sqlite, wsingle/) and shards 0/3..2/3 (sK.sqlite, wK/).
  void run_single_and_shards() {
    const Result single = thermostat("single.sqlite", "wsingle");
    ASSERT_EQ(single.code, 0) << single;
    for (int k = 0; k < 3; ++k) {
      const std::string i = std::to_string(k);
      const Result r = thermostat("s" + i + ".sqlite", "w" + i, i + "/3");
      ASSERT_EQ(r.code, 0) << r;
    }
  }
};

// ---------------------------------------------------------------------------------------------

TEST_F(ShardMergeTest, ShardsAreDisjointAndTheirUnionIsTheSingleProcessRun) {
  ASSERT_NO_FATAL_FAILURE(run_single_and_shards());
  for (int k = 0; k < 3; ++k) {
    // Shard k holds exactly the trial indices t with t % 3 == k.
    std::string expected;
    for (int t = k; t < 12; t += 3) expected += std::to_string(t) + "\n";
    EXPECT_EQ(sql(work() / ("s" + std::to_string(k) + ".sqlite"), "SELECT trial_index FROM trials ORDER BY 1").text,
              expected);
  }
  const Result merged = hyfal({"merge", "merged.sqlite", "s0.sqlite", "s1.sqlite", "s2.sqlite"});
  ASSERT_EQ(merged.code, 0) << merged;
  EXPECT_TRUE(contains(merged.out, "merged 12 trials")) << merged;
  const auto single_rows = sql(work() / "single.sqlite", kTrialResult);
  ASSERT_TRUE(single_rows.ok) << single_rows.text;
  EXPECT_EQ(lines(single_rows.text).size(), 12u);
  EXPECT_EQ(sql(work() / "merged.sqlite", kTrialResult).text, single_rows.text);
  // The series came along: as many points per trial as in the single-process run.
  const char* points = "SELECT t.trial_index, s.name, count(*) FROM series s JOIN trials t ON s.trial_id = t.id "
                       "GROUP BY t.trial_index, s.name ORDER BY 1, 2";
  EXPECT_EQ(sql(work() / "merged.sqlite", points).text, sql(work() / "single.sqlite", points).text);

  // Witness paths stay as stored (valid from this folder) and hold the single run's bytes.
  const auto merged_witnesses = witnesses_of(work() / "merged.sqlite");
  const auto single_witnesses = witnesses_of(work() / "single.sqlite");
  ASSERT_EQ(merged_witnesses.size(), 12u);
  std::size_t compared = 0;
  for (const auto& [index, path] : merged_witnesses) {
    ASSERT_EQ(path.empty(), single_witnesses.at(index).empty()) << "trial " << index;
    if (path.empty()) continue;
    ASSERT_TRUE(fs::is_regular_file(work() / path)) << path;
    EXPECT_EQ(read_text(work() / path), read_text(work() / single_witnesses.at(index))) << "trial " << index;
    ++compared;
  }
  EXPECT_GT(compared, 0u) << "thermostat trials falsify: there are witnesses to compare";

  // Merging the same inputs again changes nothing.
  const std::string before = sql(work() / "merged.sqlite", kEverything).text;
  const Result again = hyfal({"merge", "merged.sqlite", "s2.sqlite", "s0.sqlite", "s1.sqlite"});
  ASSERT_EQ(again.code, 0) << again;
  EXPECT_TRUE(contains(again.out, "merged 0 trials")) << again;
  EXPECT_TRUE(contains(again.out, "12 skipped")) << again;
  EXPECT_EQ(sql(work() / "merged.sqlite", kEverything).text, before);
  EXPECT_EQ(sql(work() / "merged.sqlite", "SELECT count(*) FROM trials").text, "12\n");

  // Merging the single-process run into it: the same trials (other times and paths): skipped.
  const Result same = hyfal({"merge", "merged.sqlite", "single.sqlite"});
  ASSERT_EQ(same.code, 0) << same;
  EXPECT_EQ(sql(work() / "merged.sqlite", kEverything).text, before);
}

TEST_F(ShardMergeTest, AConflictingRowIsRefusedInOneLineAndLeavesOutUnchanged) {
  ASSERT_NO_FATAL_FAILURE(run_single_and_shards());
  ASSERT_EQ(hyfal({"merge", "merged.sqlite", "s0.sqlite", "s1.sqlite", "s2.sqlite"}).code, 0);
  fs::copy_file(work() / "s0.sqlite", work() / "altered.sqlite");
  ASSERT_TRUE(sql(work() / "altered.sqlite", "UPDATE trials SET nodes = nodes + 1 WHERE trial_index = 3").ok);
  const std::string bytes = read_text(work() / "merged.sqlite");
  const std::string inputs_bytes = read_text(work() / "altered.sqlite");

  const Result r = hyfal({"merge", "merged.sqlite", "altered.sqlite"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "altered.sqlite")) << r;
  EXPECT_TRUE(contains(r.err, "trial 3")) << r;
  EXPECT_TRUE(contains(r.err, "nodes")) << r;
  EXPECT_TRUE(contains(r.err, "thermostat")) << r;
  EXPECT_TRUE(r.out.empty()) << r;
  EXPECT_EQ(read_text(work() / "merged.sqlite"), bytes) << "OUT unchanged";
  EXPECT_EQ(read_text(work() / "altered.sqlite"), inputs_bytes) << "an input is never changed";

  // Between two inputs, into a new OUT: refused before OUT is created.
  const Result fresh = hyfal({"merge", "fresh.sqlite", "s0.sqlite", "altered.sqlite"});
  EXPECT_EQ(fresh.code, 2) << fresh;
  EXPECT_EQ(lines(fresh.err).size(), 1u) << fresh;
  EXPECT_FALSE(fs::exists(work() / "fresh.sqlite"));

  // OUT as an input, a missing input, a file that is no database: exit 2, one line, OUT unchanged.
  fs::path text = work() / "notes.sqlite";
  std::ofstream(text) << "not a database\n";
  for (const Args& bad : {Args{"merge", "merged.sqlite", "merged.sqlite"}, Args{"merge", "merged.sqlite", "./merged.sqlite"},
                          Args{"merge", "merged.sqlite", "missing.sqlite"}, Args{"merge", "merged.sqlite", "notes.sqlite"},
                          Args{"merge", "merged.sqlite"}}) {
    const Result b = hyfal(bad);
    EXPECT_EQ(b.code, 2) << b;
    EXPECT_EQ(lines(b.err).size(), 1u) << b;
    EXPECT_EQ(read_text(work() / "merged.sqlite"), bytes) << b;
  }
}

TEST_F(ShardMergeTest, AnErrorRowIsReplacedByTheResultOfTheSameTrial) {
  ASSERT_NO_FATAL_FAILURE(run_single_and_shards());
  fs::copy_file(work() / "s1.sqlite", work() / "errored.sqlite");
  ASSERT_TRUE(sql(work() / "errored.sqlite",
                  "DELETE FROM series WHERE trial_id IN (SELECT id FROM trials WHERE trial_index = 4); "
                  "UPDATE trials SET status = 'error', validated = 0, nodes = 0, witness = NULL, error = 'boom' "
                  "WHERE trial_index = 4")
                  .ok);
  ASSERT_EQ(hyfal({"merge", "merged.sqlite", "errored.sqlite"}).code, 0);
  const Result r = hyfal({"merge", "merged.sqlite", "s1.sqlite"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "1 replacing error rows")) << r;
  EXPECT_EQ(sql(work() / "merged.sqlite", kTrialResult).text, sql(work() / "s1.sqlite", kTrialResult).text);
  const char* points = "SELECT t.trial_index, count(*) FROM series s JOIN trials t ON s.trial_id = t.id GROUP BY 1";
  EXPECT_EQ(sql(work() / "merged.sqlite", points).text, sql(work() / "s1.sqlite", points).text);
  // The other way round: an error row of a stored result is skipped.
  const Result back = hyfal({"merge", "merged.sqlite", "errored.sqlite"});
  ASSERT_EQ(back.code, 0) << back;
  EXPECT_EQ(sql(work() / "merged.sqlite", kTrialResult).text, sql(work() / "s1.sqlite", kTrialResult).text);
}

TEST_F(ShardMergeTest, WitnessDirCopiesEveryWitnessAndTheCopiesValidate) {
  ASSERT_NO_FATAL_FAILURE(run_single_and_shards());
  // Run from another folder, so that the stored relative paths are found beside the databases.
  fs::create_directories(work() / "elsewhere");
  const Result r = run_hyfal(work() / "elsewhere", io(),
                             {"merge", "../merged.sqlite", "../s0.sqlite", "../s1.sqlite", "../s2.sqlite",
                              "--witness-dir", "../merged-witnesses"});
  ASSERT_EQ(r.code, 0) << r;
  const auto witnesses = witnesses_of(work() / "merged.sqlite");
  const auto single = witnesses_of(work() / "single.sqlite");
  std::size_t stored = 0;
  for (const auto& [index, path] : witnesses) {
    if (path.empty()) continue;
    ++stored;
    EXPECT_EQ(path.rfind("../merged-witnesses/", 0), 0u) << path;
    const fs::path file = work() / "elsewhere" / path;
    ASSERT_TRUE(fs::is_regular_file(file)) << path;
    EXPECT_EQ(read_text(file), read_text(work() / single.at(index))) << path;
    const Result v = hyfal({"validate", fs::relative(file, work()).string()});
    EXPECT_EQ(v.code, 0) << v;
    EXPECT_TRUE(contains(v.out, "VALID")) << v;
  }
  EXPECT_GT(stored, 0u);
  EXPECT_EQ(files_under(work() / "merged-witnesses").size(), stored) << "one copy per witness, no temporary left";
  EXPECT_TRUE(contains(r.out, std::to_string(stored) + " witnesses copied")) << r;

  // A witness that cannot be found: exit 2 before anything is written (no database, no copy).
  const auto s2 = witnesses_of(work() / "s2.sqlite");
  for (const auto& [index, path] : s2)
    if (!path.empty()) fs::remove(work() / path);
  const Result missing = hyfal({"merge", "other.sqlite", "s0.sqlite", "s2.sqlite", "--witness-dir", "other-wit"});
  EXPECT_EQ(missing.code, 2) << missing;
  EXPECT_EQ(lines(missing.err).size(), 1u) << missing;
  EXPECT_FALSE(fs::exists(work() / "other.sqlite"));
  EXPECT_FALSE(fs::exists(work() / "other-wit"));
  // Without --witness-dir the paths are kept, with one warning line counting the missing files.
  const Result kept = hyfal({"merge", "kept.sqlite", "s2.sqlite"});
  EXPECT_EQ(kept.code, 0) << kept;
  EXPECT_EQ(lines(kept.err).size(), 1u) << kept;
  EXPECT_TRUE(contains(kept.err, "warning: " + std::to_string(s2.size() - std::count_if(s2.begin(), s2.end(), [](const auto& kv) {
                                    return kv.second.empty();
                                  })) + " witness files"))
      << kept;
}

TEST_F(ShardMergeTest, AFailedWitnessCopyRemovesTheCopiesAndWritesNoDatabase) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  ASSERT_NO_FATAL_FAILURE(run_single_and_shards());
  // The copies are made in key order: trial 11's is the last. Its temporary file is made to fail
  // as on a full disk, after the copies of trials 0..10 were written.
  const std::string last = witnesses_of(work() / "single.sqlite").at("11");
  ASSERT_FALSE(last.empty());
  const fs::path target = work() / "copies" / fs::relative(last, "wsingle");
  fs::create_directories(target.parent_path());
  fs::create_symlink("/dev/full", target.string() + ".tmp");
  const Result r = hyfal({"merge", "merged.sqlite", "s0.sqlite", "s1.sqlite", "s2.sqlite", "--witness-dir", "copies"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "No space left on device")) << r;
  EXPECT_TRUE(files_under(work() / "copies").empty()) << "the copies made are removed again";
  EXPECT_FALSE(fs::exists(work() / "merged.sqlite"));
  const Result again = hyfal({"merge", "merged.sqlite", "s0.sqlite", "s1.sqlite", "s2.sqlite", "--witness-dir", "copies"});
  ASSERT_EQ(again.code, 0) << again;
  EXPECT_TRUE(contains(again.out, "merged 12 trials")) << again;
}

TEST_F(ShardMergeTest, BadShardValuesExitTwoAndCreateNothing) {
  for (const std::string v : {"3/3", "a/b", "1/0", "-1/2", "1", "", "0/100001", "0/2/3", " 0/2"}) {
    const Result run = hyfal({"run", "--suite", "thermostat", "--trials", "2", "--threads", "1", "--db", "out/db.sqlite",
                              "--witness-dir", "out/wit", "--shard", v});
    EXPECT_EQ(run.code, 2) << run;
    EXPECT_EQ(lines(run.err).size(), 1u) << run;
    EXPECT_TRUE(contains(run.err, "--shard")) << run;
    const Result table = hyfal({"reproduce", "kim-table1", "--profile", "smoke", "--db", "out/db.sqlite",
                                "--witness-dir", "out/wit", "--out-dir", "out/tables", "--shard=" + v});
    EXPECT_EQ(table.code, 2) << table;
    EXPECT_EQ(lines(table.err).size(), 1u) << table;
    EXPECT_TRUE(contains(table.err, "--shard")) << table;
  }
  EXPECT_TRUE(fs::is_empty(work())) << "nothing created";
}

TEST_F(ShardMergeTest, PlanCountsWithoutCreatingAnythingAndShowsWhatRemains) {
  const Args plan = {"reproduce", "kim-table1", "--profile", "smoke", "--db", "db.sqlite", "--witness-dir", "wit",
                     "--out-dir", "tables", "--plan"};
  const Result r = hyfal(plan);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "3 trial group(s), 9 trials")) << r;
  EXPECT_TRUE(contains(r.out, "10 s wall clock")) << r;
  EXPECT_TRUE(contains(r.out, "CPU-hours: at most 0.03")) << r;
  EXPECT_TRUE(contains(r.out, "batch 1")) << r;
  EXPECT_TRUE(fs::is_empty(work())) << "a plan creates no file";

  // Shard 1/3 of the table's 9 trials (positions 1, 4, 7), then plans of what remains.
  Args shard1 = {"reproduce", "kim-table1", "--profile", "smoke", "--threads", "1", "--db", "db.sqlite",
                 "--witness-dir", "wit", "--out-dir", "tables", "--shard", "1/3"};
  const Result part = hyfal(shard1);
  ASSERT_EQ(part.code, 0) << part;
  EXPECT_TRUE(contains(part.err, "3 trials (3 run now)")) << part;
  EXPECT_TRUE(contains(part.err, "--shard 1/3")) << part;
  EXPECT_TRUE(contains(part.err, "merge")) << part;
  EXPECT_EQ(sql(work() / "db.sqlite", "SELECT count(*) FROM trials").text, "3\n");
  const std::string db_bytes = read_text(work() / "db.sqlite");
  const auto files_before = files_under(work());

  const Result after = hyfal(plan);
  ASSERT_EQ(after.code, 0) << after;
  EXPECT_TRUE(contains(after.out, "stored:    3 of these 9 trials in db.sqlite; 6 remain, at most 0.02 CPU-hours"))
      << after;
  Args plan1 = plan;
  plan1.insert(plan1.end(), {"--shard", "1/3"});
  const Result after1 = hyfal(plan1);
  ASSERT_EQ(after1.code, 0) << after1;
  EXPECT_TRUE(contains(after1.out, "shard 1/3: 3 of them")) << after1;
  EXPECT_TRUE(contains(after1.out, "3 of these 3 trials in db.sqlite; 0 remain")) << after1;
  EXPECT_EQ(read_text(work() / "db.sqlite"), db_bytes) << "a plan changes no file";
  EXPECT_EQ(files_under(work()), files_before) << "a plan creates no file";

  // The other two shards complete the table: the full run then runs nothing.
  for (const char* s : {"0/3", "2/3"}) {
    Args other = shard1;
    other.back() = s;
    ASSERT_EQ(hyfal(other).code, 0);
  }
  Args full = shard1;
  full.resize(full.size() - 2);
  const Result complete = hyfal(full);
  ASSERT_EQ(complete.code, 0) << complete;
  EXPECT_TRUE(contains(complete.err, "9 trials (0 run now)")) << complete;

  // run --plan: one cell, --trials of it, the shard's share.
  const Result run_plan = hyfal({"run", "--suite", "thermostat", "--trials", "10", "--timeout", "36", "--db",
                                 "none.sqlite", "--plan", "--shard", "0/4", "--set", "batch=4"});
  ASSERT_EQ(run_plan.code, 0) << run_plan;
  EXPECT_TRUE(contains(run_plan.out, "1 trial group(s), 10 trials; shard 0/4: 3 of them")) << run_plan;
  EXPECT_TRUE(contains(run_plan.out, "at most 0.03")) << run_plan;  // 3 x 36 s
  EXPECT_TRUE(contains(run_plan.out, "batch up to 4")) << run_plan;
  EXPECT_FALSE(fs::exists(work() / "none.sqlite"));
}

TEST_F(ShardMergeTest, MergedShardDatabasesGiveTheFullTableWithoutRunning) {
  for (const char* s : {"0/2", "1/2"}) {
    const std::string i(1, s[0]);
    const Result r = hyfal({"reproduce", "kim-table1", "--profile", "smoke", "--threads", "1", "--db",
                            "k" + i + ".sqlite", "--witness-dir", "wit", "--out-dir", "t" + i, "--shard", s});
    ASSERT_EQ(r.code, 0) << r;
  }
  const Result m = hyfal({"merge", "merged.sqlite", "k0.sqlite", "k1.sqlite"});
  ASSERT_EQ(m.code, 0) << m;
  EXPECT_TRUE(contains(m.out, "merged 9 trials")) << m;
  const Result full = hyfal({"reproduce", "kim-table1", "--profile", "smoke", "--threads", "1", "--db", "merged.sqlite",
                             "--witness-dir", "wit", "--out-dir", "tables"});
  ASSERT_EQ(full.code, 0) << full;
  EXPECT_TRUE(contains(full.err, "9 trials (0 run now)")) << full;
  EXPECT_TRUE(fs::is_regular_file(work() / "tables" / "kim-table1.md"));
}

TEST_F(ShardMergeTest, HelpExplainsTheNewOptions) {
  const Result run = hyfal({"run", "--help"});
  ASSERT_EQ(run.code, 0) << run;
  EXPECT_TRUE(contains(run.out, "--shard")) << run;
  EXPECT_TRUE(contains(run.out, "--plan")) << run;
  const Result reproduce = hyfal({"reproduce", "--help"});
  EXPECT_TRUE(contains(reproduce.out, "--shard")) << reproduce;
  EXPECT_TRUE(contains(reproduce.out, "--plan")) << reproduce;
  const Result merge = hyfal({"merge", "--help"});
  ASSERT_EQ(merge.code, 0) << merge;
  EXPECT_TRUE(contains(merge.out, "--witness-dir")) << merge;
  EXPECT_TRUE(contains(merge.out, "conflicting")) << merge;
  const Result top = hyfal({"--help"});
  EXPECT_TRUE(contains(top.out, "merge")) << top;
  EXPECT_TRUE(fs::is_empty(work())) << "help writes nothing";
}

}  // namespace
