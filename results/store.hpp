// TrialStore: the SQLite database every trial result is written to as soon as it finishes.
// One row per trial, committed on insert, so an interrupted run (even kill -9) keeps every
// finished trial and a rerun resumes by skipping the trial indices already stored.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/trial_record.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace hyfal {

// Any failure of the results database; what() is one line naming the database and the cause.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Schema (snake_case, version 1, recorded in table meta as schema_version):
//   trials(id, experiment, suite, instance, method, config, trial_index, seed, status,
//          validated, wall_s, cpu_s, nodes, propagations, integration_steps, witness, error,
//          threads, host, git_commit, started_at, finished_at)
//     UNIQUE(experiment, suite, instance, method, config, trial_index);
//     witness and error are NULL when empty.
//   series(trial_id -> trials.id, name, x, y): per-trial progress curves, e.g. coverage vs nodes.
//
// Thread-safety: a TrialStore holds one SQLite connection and its prepared statements, so one
// TrialStore must be used from one thread at a time; the caller serializes access (e.g. one
// writer thread, or a mutex around every call). Several processes may open the same file:
// WAL mode plus a 5 s busy timeout lets them take turns.
class TrialStore {
 public:
  // Opens (creating it and its parent directories if missing) the database at path and creates
  // the schema if it is not there yet. Throws StoreError "cannot open results database '<path>':
  // <cause>" if the path cannot be created or opened, is not a SQLite database, or holds a
  // different schema version.
  static TrialStore open(const std::string& path);

  TrialStore(TrialStore&&) noexcept;
  TrialStore& operator=(TrialStore&&) noexcept;
  TrialStore(const TrialStore&) = delete;
  TrialStore& operator=(const TrialStore&) = delete;
  ~TrialStore();

  const std::string& path() const { return path_; }

  // Inserts one trial in its own transaction, committed when this returns; returns its row id.
  // Throws StoreError if a trial with the same key is already stored.
  std::int64_t insert(const TrialRecord& record);

  // Stores the points of the series called name of trial trial_id (a row id from insert), all
  // or none of them.
  // Inserts the record's row and its series (in the same transaction).
  void insert_series(std::int64_t trial_id, const std::string& name,
                     std::span<const std::pair<double, double>> points);

  // The trial indices already stored for (experiment, suite, instance, method, config) of
  // key_without_index; its trial_index is ignored.
  // Indices stored with a status other than error (errored trials are retried on resume).
  std::set<std::int64_t> stored_trial_indices(const TrialKey& key_without_index);

  // All trials, or those of one experiment, ordered by suite, instance, method, config,
  // trial_index (then experiment, so the order is total).
  std::vector<TrialRecord> load(std::optional<std::string> experiment = {});

  // The distinct experiment names stored, sorted.
  std::vector<std::string> experiments();

  // The points of series `name` of the stored trial with this key (index included), in order.
  std::vector<std::pair<double, double>> series_of(const TrialKey& key, const std::string& name);

 private:
  struct ConnectionCloser {
    void operator()(sqlite3* connection) const noexcept;
  };
  struct StatementFinalizer {
    void operator()(sqlite3_stmt* statement) const noexcept;
  };
  using Connection = std::unique_ptr<sqlite3, ConnectionCloser>;
  using Statement = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

  TrialStore(std::string path, Connection connection);
  Statement prepare(const char* sql);

  std::string path_;
  // The connection is declared before the statements so it is destroyed after them.
  Connection connection_;
  Statement insert_trial_;
  std::int64_t insert_row(const TrialRecord& record);
  void insert_points(std::int64_t trial_id, const std::string& name,
                     std::span<const std::pair<double, double>> points);
  Statement insert_series_point_;
  Statement delete_error_series_;
  Statement select_series_;
  Statement delete_error_trial_;
  Statement select_trial_indices_;
  Statement select_trials_;
  Statement select_experiments_;
};

}  // namespace hyfal
