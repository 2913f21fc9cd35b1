#include "results/store.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <filesystem>
#include <string_view>
#include <system_error>

namespace hyfal {
namespace {

constexpr int kSchemaVersion = 1;
constexpr int kBusyTimeoutMs = 5000;

// IF NOT EXISTS everywhere: opening an existing database runs the same script harmlessly.
constexpr const char* kSchemaSql = R"sql(
CREATE TABLE IF NOT EXISTS meta (
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
);
INSERT OR IGNORE INTO meta (key, value) VALUES ('schema_version', '1');  -- kSchemaVersion
CREATE TABLE IF NOT EXISTS trials (
  id                INTEGER PRIMARY KEY,
  experiment        TEXT    NOT NULL,
  suite             TEXT    NOT NULL,
  instance          TEXT    NOT NULL,
  method            TEXT    NOT NULL,
  config            TEXT    NOT NULL,
  trial_index       INTEGER NOT NULL,
  seed              INTEGER NOT NULL,
  status            TEXT    NOT NULL
    CHECK (status IN ('falsified', 'not_found', 'timeout', 'node_cap', 'error')),
  validated         INTEGER NOT NULL CHECK (validated IN (0, 1)),
  wall_s            REAL    NOT NULL,
  cpu_s             REAL    NOT NULL,
  nodes             INTEGER NOT NULL,
  propagations      INTEGER NOT NULL,
  integration_steps INTEGER NOT NULL,
  witness           TEXT,
  error             TEXT,
  threads           INTEGER NOT NULL,
  host              TEXT    NOT NULL,
  git_commit        TEXT    NOT NULL,
  started_at        TEXT    NOT NULL,
  finished_at       TEXT    NOT NULL,
  metrics           TEXT    NOT NULL DEFAULT '{}',
  UNIQUE (experiment, suite, instance, method, config, trial_index)
);
CREATE TABLE IF NOT EXISTS series (
  trial_id INTEGER NOT NULL REFERENCES trials (id),
  name     TEXT    NOT NULL,
  x        REAL    NOT NULL,
  y        REAL    NOT NULL
);
CREATE INDEX IF NOT EXISTS series_by_trial ON series (trial_id, name);
)sql";

constexpr const char* kTrialColumns =
    "experiment, suite, instance, method, config, trial_index, seed, status, validated, "
    "wall_s, cpu_s, nodes, propagations, integration_steps, witness, error, threads, host, "
    "git_commit, started_at, finished_at, metrics";

[[noreturn]] void throw_sqlite_error(sqlite3* connection, std::string_view what) {
  throw StoreError(fmt::format("{}: {}", what, sqlite3_errmsg(connection)));
}

void execute(sqlite3* connection, const char* sql, std::string_view what) {
  if (sqlite3_exec(connection, sql, nullptr, nullptr, nullptr) != SQLITE_OK)
    throw_sqlite_error(connection, what);
}

// Resets a statement and drops its bindings when a use of it ends, however it ends, so a
// kept statement never holds a read transaction open between calls.
class StatementUse {
 public:
  explicit StatementUse(sqlite3_stmt* statement) : statement_(statement) {}
  StatementUse(const StatementUse&) = delete;
  StatementUse& operator=(const StatementUse&) = delete;
  ~StatementUse() {
    sqlite3_reset(statement_);
    sqlite3_clear_bindings(statement_);
  }

  void bind(int index, std::string_view text) {
    // A null data pointer would bind NULL, not an empty text.
    const char* chars = text.data() != nullptr ? text.data() : "";
    check(sqlite3_bind_text64(statement_, index, chars, text.size(), SQLITE_TRANSIENT,
                              SQLITE_UTF8));
  }
  // Empty text is stored as NULL: "no witness" / "no error".
  void bind_or_null(int index, std::string_view text) {
    if (text.empty())
      check(sqlite3_bind_null(statement_, index));
    else
      bind(index, text);
  }
  void bind(int index, std::int64_t value) {
    check(sqlite3_bind_int64(statement_, index, value));
  }
  void bind(int index, double value) { check(sqlite3_bind_double(statement_, index, value)); }

  // True while there is a row to read; false when done.
  bool step() {
    const int rc = sqlite3_step(statement_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    sqlite3* connection = sqlite3_db_handle(statement_);
    throw_sqlite_error(connection, fmt::format("query on results database '{}' failed",
                                               sqlite3_db_filename(connection, "main")));
  }

  std::string text(int column) const {
    const auto* chars = sqlite3_column_text(statement_, column);  // NULL reads as empty
    if (chars == nullptr) return {};
    return std::string(reinterpret_cast<const char*>(chars),
                       static_cast<std::size_t>(sqlite3_column_bytes(statement_, column)));
  }
  std::int64_t integer(int column) const { return sqlite3_column_int64(statement_, column); }
  double real(int column) const { return sqlite3_column_double(statement_, column); }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK)
      throw_sqlite_error(sqlite3_db_handle(statement_), "cannot bind results database parameter");
  }
  sqlite3_stmt* statement_;
};

// Binds experiment, suite, instance, method, config to parameters 1..5.
void bind_key_without_index(StatementUse& use, const TrialKey& key) {
  use.bind(1, key.experiment);
  use.bind(2, key.suite);
  use.bind(3, key.instance);
  use.bind(4, key.method);
  use.bind(5, key.config);
}

std::string describe(const TrialKey& key) {
  return fmt::format("experiment '{}', suite '{}', instance {}, method '{}', config {}, trial {}",
                     key.experiment, key.suite, key.instance, key.method, key.config,
                     key.trial_index);
}

// Ensures the directory the database goes into exists; SQLite creates files, not directories.
void create_parent_directories(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error)
    throw StoreError(fmt::format("cannot create directory '{}': {}", parent.string(),
                                 error.message()));
}

// Makes the connection ready for use; a file that is not a SQLite database fails here, on the
// first statement that reads it, not in sqlite3_open_v2. SQLite's own message ("file is not a
// database") is the clearest cause to report, so it is reported alone.
void configure(sqlite3* connection) {
  const auto run = [connection](const char* sql) {
    if (sqlite3_exec(connection, sql, nullptr, nullptr, nullptr) != SQLITE_OK)
      throw StoreError(sqlite3_errmsg(connection));
  };
  if (sqlite3_busy_timeout(connection, kBusyTimeoutMs) != SQLITE_OK)
    throw StoreError(sqlite3_errmsg(connection));
  // WAL: readers (a report run) do not block the writer. synchronous=NORMAL in WAL mode keeps
  // every committed trial across a crash of the process (kill -9); only a power loss may drop
  // the last commits, which is an acceptable trade for not syncing on each trial.
  run("PRAGMA journal_mode = WAL");
  run("PRAGMA synchronous = NORMAL");
  run("PRAGMA foreign_keys = ON");  // a series must belong to a stored trial
  // IMMEDIATE: two processes opening a new database at once create the schema one at a time.
  run("BEGIN IMMEDIATE");
  if (sqlite3_exec(connection, kSchemaSql, nullptr, nullptr, nullptr) != SQLITE_OK) {
    const std::string message = sqlite3_errmsg(connection);
    sqlite3_exec(connection, "ROLLBACK", nullptr, nullptr, nullptr);
    throw StoreError(fmt::format("cannot create schema: {}", message));
  }
  run("COMMIT");
}

void check_schema_version(sqlite3* connection) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(connection, "SELECT value FROM meta WHERE key = 'schema_version'", -1,
                         &raw, nullptr) != SQLITE_OK)
    throw_sqlite_error(connection, "cannot read schema version");
  std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> statement(raw, &sqlite3_finalize);
  StatementUse use(statement.get());
  const std::string version = use.step() ? use.text(0) : std::string();
  if (version != std::to_string(kSchemaVersion))
    throw StoreError(fmt::format("schema version is '{}', this build reads version {}", version,
                                 kSchemaVersion));
}

}  // namespace

void TrialStore::ConnectionCloser::operator()(sqlite3* connection) const noexcept {
  // close_v2 defers the close until the last statement is finalized, so destruction order
  // (e.g. in a move assignment) cannot leak the connection.
  sqlite3_close_v2(connection);
}

void TrialStore::StatementFinalizer::operator()(sqlite3_stmt* statement) const noexcept {
  sqlite3_finalize(statement);
}

TrialStore::TrialStore(std::string path, Connection connection)
    : path_(std::move(path)), connection_(std::move(connection)) {
  insert_trial_ = prepare(
      fmt::format("INSERT INTO trials ({}) VALUES "
                  "(?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, "
                  "?18, ?19, ?20, ?21, ?22)",
                  kTrialColumns)
          .c_str());
  insert_series_point_ =
      prepare("INSERT INTO series (trial_id, name, x, y) VALUES (?1, ?2, ?3, ?4)");
  select_trial_indices_ = prepare(
      "SELECT trial_index FROM trials "
      "WHERE experiment = ?1 AND suite = ?2 AND instance = ?3 AND method = ?4 AND config = ?5 "
      "AND status <> 'error'");
  delete_error_series_ = prepare(
      "DELETE FROM series WHERE trial_id IN (SELECT id FROM trials WHERE experiment = ?1 AND "
      "suite = ?2 AND instance = ?3 AND method = ?4 AND config = ?5 AND trial_index = ?6 AND "
      "status = 'error')");
  delete_error_trial_ = prepare(
      "DELETE FROM trials WHERE experiment = ?1 AND suite = ?2 AND instance = ?3 AND method = ?4 "
      "AND config = ?5 AND trial_index = ?6 AND status = 'error'");
  select_trials_ = prepare(
      fmt::format("SELECT {} FROM trials WHERE ?1 IS NULL OR experiment = ?1 "
                  "ORDER BY suite, instance, method, config, trial_index, experiment",
                  kTrialColumns)
          .c_str());
  select_series_ = prepare(
      "SELECT s.x, s.y FROM series s JOIN trials t ON s.trial_id = t.id WHERE t.experiment = ?1 AND "
      "t.suite = ?2 AND t.instance = ?3 AND t.method = ?4 AND t.config = ?5 AND t.trial_index = ?6 "
      "AND s.name = ?7 ORDER BY s.rowid");
  select_experiments_ = prepare("SELECT DISTINCT experiment FROM trials ORDER BY experiment");
}

TrialStore::TrialStore(TrialStore&&) noexcept = default;
TrialStore& TrialStore::operator=(TrialStore&&) noexcept = default;
TrialStore::~TrialStore() = default;

TrialStore TrialStore::open(const std::string& path) {
  try {
    create_parent_directories(path);
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE,
                                   nullptr);
    Connection connection(raw);  // sqlite3_open_v2 allocates a handle even when it fails
    if (rc != SQLITE_OK) {
      if (raw == nullptr) throw StoreError(sqlite3_errstr(rc));
      throw StoreError(sqlite3_errmsg(raw));
    }
    sqlite3_extended_result_codes(raw, 1);
    configure(raw);
    check_schema_version(raw);
    return TrialStore(path, std::move(connection));
  } catch (const StoreError& error) {
    throw StoreError(fmt::format("cannot open results database '{}': {}", path, error.what()));
  }
}

TrialStore::Statement TrialStore::prepare(const char* sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v3(connection_.get(), sql, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr) !=
      SQLITE_OK)
    throw_sqlite_error(connection_.get(), "cannot prepare statement");
  return Statement(raw);
}

std::int64_t TrialStore::insert(const TrialRecord& record) {
  // One transaction: an earlier attempt of the same trial that ended in error is replaced (so a
  // resumed run retries errors), and the row is stored with its series, whole or not at all.
  execute(connection_.get(), "BEGIN IMMEDIATE",
          fmt::format("cannot start transaction on results database '{}'", path_));
  try {
    for (sqlite3_stmt* statement : {delete_error_series_.get(), delete_error_trial_.get()}) {
      StatementUse use(statement);
      bind_key_without_index(use, record.key);
      use.bind(6, record.key.trial_index);
      if (sqlite3_step(statement) != SQLITE_DONE)
        throw_sqlite_error(connection_.get(), fmt::format("cannot replace an errored trial in '{}'", path_));
    }
    const std::int64_t id = insert_row(record);
    for (const auto& [name, points] : record.series) insert_points(id, name, points);
    execute(connection_.get(), "COMMIT",
            fmt::format("cannot commit trial to results database '{}'", path_));
    return id;
  } catch (...) {
    sqlite3_exec(connection_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::int64_t TrialStore::insert_row(const TrialRecord& record) {
  // A single INSERT in autocommit mode is its own transaction: committed when step returns.
  StatementUse use(insert_trial_.get());
  bind_key_without_index(use, record.key);
  use.bind(6, record.key.trial_index);
  use.bind(7, record.seed);
  use.bind(8, to_string(record.status));
  use.bind(9, std::int64_t{record.validated ? 1 : 0});
  use.bind(10, record.wall_s);
  use.bind(11, record.cpu_s);
  use.bind(12, record.nodes);
  use.bind(13, record.propagations);
  use.bind(14, record.integration_steps);
  use.bind_or_null(15, record.witness);
  use.bind_or_null(16, record.error);
  use.bind(17, std::int64_t{record.threads});
  use.bind(18, record.host);
  use.bind(19, record.git_commit);
  use.bind(20, record.started_at);
  use.bind(21, record.finished_at);
  use.bind(22, record.metrics);
  const int rc = sqlite3_step(insert_trial_.get());
  if (rc == SQLITE_CONSTRAINT_UNIQUE)
    throw StoreError(fmt::format("results database '{}' already holds the trial ({})", path_,
                                 describe(record.key)));
  if (rc != SQLITE_DONE)
    throw_sqlite_error(connection_.get(),
                       fmt::format("cannot store trial ({}) in results database '{}'",
                                   describe(record.key), path_));
  return sqlite3_last_insert_rowid(connection_.get());
}

void TrialStore::insert_series(std::int64_t trial_id, const std::string& name,
                               std::span<const std::pair<double, double>> points) {
  // One transaction for all points: a series is stored whole or not at all, and one commit is
  // much cheaper than one per point.
  execute(connection_.get(), "BEGIN IMMEDIATE",
          fmt::format("cannot start transaction on results database '{}'", path_));
  try {
    insert_points(trial_id, name, points);
    execute(connection_.get(), "COMMIT",
            fmt::format("cannot commit series '{}' of trial {} to results database '{}'", name,
                        trial_id, path_));
  } catch (...) {
    sqlite3_exec(connection_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void TrialStore::insert_points(std::int64_t trial_id, const std::string& name,
                               std::span<const std::pair<double, double>> points) {
  for (const auto& [x, y] : points) {
    StatementUse use(insert_series_point_.get());
    use.bind(1, trial_id);
    use.bind(2, name);
    use.bind(3, x);
    use.bind(4, y);
    if (sqlite3_step(insert_series_point_.get()) != SQLITE_DONE)
      throw_sqlite_error(connection_.get(),
                         fmt::format("cannot store series '{}' of trial {} in results database '{}'",
                                     name, trial_id, path_));
  }
}

std::set<std::int64_t> TrialStore::stored_trial_indices(const TrialKey& key_without_index) {
  StatementUse use(select_trial_indices_.get());
  bind_key_without_index(use, key_without_index);
  std::set<std::int64_t> indices;
  while (use.step()) indices.insert(use.integer(0));
  return indices;
}

std::vector<TrialRecord> TrialStore::load(std::optional<std::string> experiment) {
  StatementUse use(select_trials_.get());
  if (experiment) use.bind(1, *experiment);  // unbound ?1 is NULL: every experiment
  std::vector<TrialRecord> records;
  while (use.step()) {
    TrialRecord record;
    record.key.experiment = use.text(0);
    record.key.suite = use.text(1);
    record.key.instance = use.text(2);
    record.key.method = use.text(3);
    record.key.config = use.text(4);
    record.key.trial_index = use.integer(5);
    record.seed = use.integer(6);
    const std::string status = use.text(7);
    const auto parsed_status = parse_trial_status(status);
    if (!parsed_status)
      throw StoreError(fmt::format("results database '{}' holds unknown trial status '{}'", path_,
                                   status));
    record.status = *parsed_status;
    record.validated = use.integer(8) != 0;
    record.wall_s = use.real(9);
    record.cpu_s = use.real(10);
    record.nodes = use.integer(11);
    record.propagations = use.integer(12);
    record.integration_steps = use.integer(13);
    record.witness = use.text(14);
    record.error = use.text(15);
    record.threads = static_cast<int>(use.integer(16));
    record.host = use.text(17);
    record.git_commit = use.text(18);
    record.started_at = use.text(19);
    record.finished_at = use.text(20);
    record.metrics = use.text(21);
    records.push_back(std::move(record));
  }
  return records;
}

std::vector<std::pair<double, double>> TrialStore::series_of(const TrialKey& key, const std::string& name) {
  StatementUse use(select_series_.get());
  bind_key_without_index(use, key);
  use.bind(6, key.trial_index);
  use.bind(7, name);
  std::vector<std::pair<double, double>> points;
  while (use.step()) points.emplace_back(use.real(0), use.real(1));
  return points;
}

std::vector<std::string> TrialStore::experiments() {
  StatementUse use(select_experiments_.get());
  std::vector<std::string> names;
  while (use.step()) names.push_back(use.text(0));
  return names;
}

}  // namespace hyfal
