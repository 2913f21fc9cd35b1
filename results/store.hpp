// TrialStore: the SQLite database every trial result is written to as soon as it finishes.
// One row per trial, committed on insert, so an interrupted run (even kill -9) keeps every
// finished trial and a rerun resumes by skipping the trial indices already stored.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/util/error.hpp"
#include "core/run/trial_record.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace hyfal {

// What a failure of the results database says about its cause, and so the exit code it gets.
enum class StoreErrorKind {
  // The user named something that is not a usable hyfal database: not a hyfal database, an
  // unsupported schema version, a directory, an empty path. Nothing was written (exit 2).
  bad_input,
  // The machine failed a database that was fine: disk full, I/O error, locked past the busy
  // timeout, permission lost, the file vanished (exit 3).
  environment,
};

// Any failure of the results database: the mixin of StoreInputError and StoreEnvironmentError
// (core/util/error.hpp), so that `catch (const StoreError&)` sees both. what() is one line naming the
// database and the cause. Thrown by throw_store_error, which picks the class by the kind.
class StoreError {
 public:
  virtual ~StoreError() = default;
  virtual const char* what() const noexcept = 0;
  virtual StoreErrorKind kind() const noexcept = 0;
  // SQLite's (extended) result code behind the failure, 0 when it did not come from SQLite.
  int sqlite_code() const noexcept { return sqlite_code_; }

 protected:
  explicit StoreError(int sqlite_code) : sqlite_code_(sqlite_code) {}

 private:
  int sqlite_code_;
};

// StoreErrorKind::bad_input: the user named something that is not a usable hyfal database.
class StoreInputError : public InputError, public StoreError {
 public:
  StoreInputError(const std::string& what, int sqlite_code = 0) : InputError(what), StoreError(sqlite_code) {}
  const char* what() const noexcept override { return InputError::what(); }
  StoreErrorKind kind() const noexcept override { return StoreErrorKind::bad_input; }
  const char* name() const noexcept override { return "StoreInputError"; }
};

// StoreErrorKind::environment: the machine failed a database that was fine.
class StoreEnvironmentError : public EnvironmentError, public StoreError {
 public:
  StoreEnvironmentError(const std::string& what, int sqlite_code = 0) : EnvironmentError(what), StoreError(sqlite_code) {}
  const char* what() const noexcept override { return EnvironmentError::what(); }
  StoreErrorKind kind() const noexcept override { return StoreErrorKind::environment; }
  const char* name() const noexcept override { return "StoreEnvironmentError"; }
};

// Throws the StoreError of that kind.
[[noreturn]] inline void throw_store_error(StoreErrorKind kind, const std::string& what, int sqlite_code = 0) {
  if (kind == StoreErrorKind::bad_input) throw StoreInputError(what, sqlite_code);
  throw StoreEnvironmentError(what, sqlite_code);
}

// Who runs a claimed trial: one process, told apart from a later process that reuses its pid by
// the start time the kernel records for it.
struct ClaimOwner {
  std::string host;                 // host name and pid namespace: where `pid` means this process
  std::int64_t pid = 0;
  std::int64_t process_start = 0;   // /proc/<pid>/stat field 22 (clock ticks after boot), 0 if unknown
  std::string token;                // random per process: the owner's identity in the database

  // The calling process (the same value on every call).
  static const ClaimOwner& this_process();
};

// Claims are refreshed every kClaimHeartbeatInterval by ClaimHeartbeat; a claim whose heartbeat
// is older than kClaimStaleAfter belongs to an owner that is gone (or hung, or on a host whose
// clock is that far off: hosts sharing a database must keep their clocks within a few seconds).
// A claim of an owner on this host whose process has ended is stale at once.
inline constexpr double kClaimHeartbeatInterval = 5.0;  // seconds
inline constexpr double kClaimStaleAfter = 60.0;        // seconds

// Where one trial of a cooperative run stands.
enum class TrialProgress {
  stored,            // stored with a status other than error: done
  stored_error,      // stored as error and not claimed: done in this run (it ended in error)
  claimed_by_other,  // a live owner other than the asking process runs it: wait for it
  needs_runner,      // neither stored nor claimed by a live owner: run it
};

// Schema (snake_case, version 1, recorded in table meta as schema_version):
//   trials(id, experiment, suite, instance, method, config, trial_index, seed, status,
//          validated, wall_s, cpu_s, nodes, propagations, integration_steps, witness, error,
//          threads, host, git_commit, started_at, finished_at, metrics)
//     UNIQUE(experiment, suite, instance, method, config, trial_index);
//     witness and error are NULL when empty.
//   series(trial_id -> trials.id, name, x, y): per-trial progress curves, e.g. coverage vs nodes.
//   claims(experiment, suite, instance, method, config, trial_index, host, pid, process_start,
//          token, heartbeat): the trials a process is running now, so that several processes on
//          one experiment run each trial once. Created by writers when missing (IF NOT EXISTS),
//          so databases written before it existed still open; readers do not need it.
//
// Thread-safety: a TrialStore holds one SQLite connection and its prepared statements, so one
// TrialStore must be used from one thread at a time; the caller serializes access (e.g. one
// writer thread, or a mutex around every call). Several processes may open the same file:
// WAL mode plus a 5 s busy timeout lets them take turns.
class TrialStore {
 public:
  // Opens the database at path for writing. A missing path is created with its parent
  // directories as a complete database in one step (built unnamed, then linked into place), so a
  // process killed at any instant leaves no database or a whole one. An empty file (or a SQLite
  // database without any table) gets the schema in place. A hot journal that a killed writer
  // left is rolled back first (as SQLite would on any read-write open: the file returns to its
  // last commit). Any other file is first opened read-only and checked to be a hyfal results
  // database of schema version 1 or 2 (tables meta, trials and series with hyfal's columns);
  // only then is it opened for writing, so a file that is not one is never changed. A schema-1
  // file is then migrated to schema 2 (store.cpp: migrate_from_schema_1). Throws StoreError: bad_input for a file
  // that is not a hyfal database, an unsupported schema version, a directory or an empty path;
  // environment when a usable path cannot be opened (I/O, disk full, locked, permissions).
  static TrialStore open(const std::string& path);
 private:
  static TrialStore open_once(const std::string& path);

 public:

  // Opens an existing hyfal database for reading only (URI mode=ro: works on a read-only file
  // or folder, never takes a write lock, never waits for a writer: WAL readers see the last
  // commit). Where WAL would need a -shm file that cannot be created (read-only folder), or the
  // file is read-only and no writer has it open, it is read as immutable. -wal/-shm files that
  // opening created are removed when the store closes, unless another connection uses them by
  // then (SQLite removes them at that connection's close). A hot journal is rolled back first
  // where this process may write the file (else a StoreError names it: read as immutable, the
  // half-written file would be read). The write methods (insert, claim, ...)
  // must not be called on it (std::logic_error). Throws StoreError like open().
  static TrialStore open_read_only(const std::string& path);

  TrialStore(TrialStore&&) noexcept;
  TrialStore& operator=(TrialStore&&) noexcept;
  TrialStore(const TrialStore&) = delete;
  TrialStore& operator=(const TrialStore&) = delete;
  ~TrialStore();

  const std::string& path() const { return path_; }

  // Inserts one trial in its own transaction, committed when this returns; returns its row id.
  // A claim on the trial is deleted in the same transaction. Throws StoreError (bad_input) if a
  // trial with the same key is already stored with a status other than error.
  std::int64_t insert(const TrialRecord& record);

  // Whether a trial with this key is stored with a status other than error.
  bool is_stored(const TrialKey& key);

  // Claims the trial for owner in one write transaction, right before running it. False if it is
  // stored with a status other than error, or claimed by a live owner other than this one; a
  // stale claim (see kClaimStaleAfter) is taken over.
  bool claim(const TrialKey& key, const ClaimOwner& owner);

  // Where each trial stands for the process `self` (one read transaction for all keys).
  std::vector<TrialProgress> progress(const std::vector<TrialKey>& keys, const ClaimOwner& self);

  // Sets the heartbeat of every claim of owner to now; returns how many there are.
  std::int64_t refresh_claims(const ClaimOwner& owner);

  // Drops every claim of owner (a run that stops hands its trials over at once).
  void release_claims(const ClaimOwner& owner);

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

  // Every trial (ordered as load() orders them) with all its series, read in one transaction so
  // that rows and series come from one snapshot (merge reads its inputs this way).
  std::vector<TrialRecord> load_with_series();

  // Stores many trials with their series in ONE transaction (merge writes this way): all or none
  // of them are stored. Like insert(), a stored row of the same key with status error is replaced
  // (with its series) and a claim on the key ends. Throws StoreError (bad_input) if a trial with
  // the same key is stored with a status other than error; nothing is then stored.
  void insert_all(const std::vector<TrialRecord>& records);

  // The distinct experiment names stored, sorted.
  std::vector<std::string> experiments();

  // The points of series `name` of the stored trial with this key (index included), in order.
  std::vector<std::pair<double, double>> series_of(const TrialKey& key, const std::string& name);

 private:
  struct ConnectionCloser {
    // A read-only connection that created the -wal/-shm files of its database names it here:
    // they are removed after it closes, unless another connection uses them by then.
    std::string remove_wal_files_of;
    void operator()(sqlite3* connection) const noexcept;
  };
  struct StatementFinalizer {
    void operator()(sqlite3_stmt* statement) const noexcept;
  };
  using Connection = std::unique_ptr<sqlite3, ConnectionCloser>;
  using Statement = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

  TrialStore(std::string path, Connection connection, bool writable);
  Statement prepare(const char* sql);
  void require_writable(const char* what) const;

  std::string path_;
  bool writable_ = false;
  // Marks the file open in this process (see OpenDatabaseFiles in store.cpp) until after the
  // connection has closed: declared before it, so destroyed after it.
  std::shared_ptr<const void> open_file_;
  // The connection is declared before the statements so it is destroyed after them.
  Connection connection_;
  Statement insert_trial_;
  std::int64_t insert_row(const TrialRecord& record);
  // The one step of insert and insert_all, inside their transaction: the row of record (replacing
  // an errored attempt of the same trial), its series, and the end of its claim.
  std::int64_t store_in_transaction(const TrialRecord& record);
  void insert_points(std::int64_t trial_id, const std::string& name,
                     std::span<const std::pair<double, double>> points);
  Statement insert_series_point_;
  Statement delete_error_series_;
  Statement select_series_;
  Statement delete_error_trial_;
  Statement select_trial_indices_;
  Statement select_trials_;
  Statement select_experiments_;
  Statement select_status_;
  Statement select_claim_;
  Statement upsert_claim_;
  Statement delete_claim_;
  Statement refresh_claims_;
  Statement delete_claims_of_owner_;
};

// Keeps the claims of one owner fresh while a run goes on: a thread with its own connection to
// the database refreshes them every kClaimHeartbeatInterval. Destroying it stops the thread and
// releases the owner's remaining claims (those of trials a failed run did not finish), so other
// processes take them over at once. A failed refresh is retried at the next beat.
class ClaimHeartbeat {
 public:
  ClaimHeartbeat(const std::string& database_path, ClaimOwner owner);
  ClaimHeartbeat(const ClaimHeartbeat&) = delete;
  ClaimHeartbeat& operator=(const ClaimHeartbeat&) = delete;
  ~ClaimHeartbeat();

 private:
  TrialStore store_;
  ClaimOwner owner_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::jthread thread_;  // last: started after, and stopped before, everything it uses
};

}  // namespace hyfal
