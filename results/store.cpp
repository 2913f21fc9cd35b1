#include "results/store.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <string_view>
#include <system_error>

namespace hyfal {
namespace {

// Schema 2 (2026-12-07) adds the status 'budget' (a trial that spent its method's budget), which
// schema 1 called 'node_cap' like the node cap. A schema-1 database is read with those rows mapped
// (budget_stop_in_schema_1) and migrated, the same mapping written, when opened for writing
// (migrate_from_schema_1): its trials table is rebuilt with the new CHECK, one transaction.
constexpr int kSchemaVersion = 2;
constexpr int kBusyTimeoutMs = 5000;

// The trials table, named `name` (the migration builds it beside the old one first).
std::string trials_table_sql(std::string_view name) {
  return fmt::format(R"sql(
CREATE TABLE IF NOT EXISTS {} (
  id                INTEGER PRIMARY KEY,
  experiment        TEXT    NOT NULL,
  suite             TEXT    NOT NULL,
  instance          TEXT    NOT NULL,
  method            TEXT    NOT NULL,
  config            TEXT    NOT NULL,
  trial_index       INTEGER NOT NULL,
  seed              INTEGER NOT NULL,
  status            TEXT    NOT NULL
    CHECK (status IN ('falsified', 'not_found', 'timeout', 'node_cap', 'budget', 'error')),
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
  metrics           TEXT    NOT NULL DEFAULT '{{}}',
  UNIQUE (experiment, suite, instance, method, config, trial_index)
);
)sql",
                     name);
}

// IF NOT EXISTS everywhere: opening an existing database runs the same script harmlessly (an
// existing schema_version stays: a schema-1 database is migrated apart).
std::string schema_sql() {
  return fmt::format(R"sql(
CREATE TABLE IF NOT EXISTS meta (
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
);
INSERT OR IGNORE INTO meta (key, value) VALUES ('schema_version', '{}');
{}
CREATE TABLE IF NOT EXISTS series (
  trial_id INTEGER NOT NULL REFERENCES trials (id),
  name     TEXT    NOT NULL,
  x        REAL    NOT NULL,
  y        REAL    NOT NULL
);
CREATE INDEX IF NOT EXISTS series_by_trial ON series (trial_id, name);
CREATE TABLE IF NOT EXISTS claims (
  experiment    TEXT    NOT NULL,
  suite         TEXT    NOT NULL,
  instance      TEXT    NOT NULL,
  method        TEXT    NOT NULL,
  config        TEXT    NOT NULL,
  trial_index   INTEGER NOT NULL,
  host          TEXT    NOT NULL,
  pid           INTEGER NOT NULL,
  process_start INTEGER NOT NULL,
  token         TEXT    NOT NULL,
  heartbeat     REAL    NOT NULL,  -- Unix time, seconds
  PRIMARY KEY (experiment, suite, instance, method, config, trial_index)
);
CREATE INDEX IF NOT EXISTS claims_by_token ON claims (token);
)sql",
                     kSchemaVersion, trials_table_sql("trials"));
}

// The columns each table of a hyfal database has (the check before anything is written).
const std::map<std::string, std::set<std::string>>& expected_columns() {
  static const std::map<std::string, std::set<std::string>> columns{
      {"meta", {"key", "value"}},
      {"trials",
       {"id", "experiment", "suite", "instance", "method", "config", "trial_index", "seed", "status",
        "validated", "wall_s", "cpu_s", "nodes", "propagations", "integration_steps", "witness", "error",
        "threads", "host", "git_commit", "started_at", "finished_at", "metrics"}},
      {"series", {"trial_id", "name", "x", "y"}},
      {"claims",
       {"experiment", "suite", "instance", "method", "config", "trial_index", "host", "pid",
        "process_start", "token", "heartbeat"}},
  };
  return columns;
}

// Whether a schema-1 row was stopped by its method's budget (which schema 1 called node_cap):
// status node_cap, its config's method options set a budget > 0, and it holds fewer nodes than
// its node cap, which therefore cannot have stopped it. A node cap below the budget is still a
// node cap. One case it misreads: an RRFT run with a budget whose last planting the node cap
// refused (that leaves fewer nodes than the cap): read as budget. A SQL expression, so that a
// reader of a schema-1 file and the migration apply the very same rule.
constexpr const char* kSchema1BudgetStop =
    "(status = 'node_cap' AND json_valid(config) AND json_type(config, '$.options.budget') IN ('integer', 'real') "
    "AND json_extract(config, '$.options.budget') > 0 AND json_type(config, '$.max_nodes') IN ('integer', 'real') "
    "AND nodes < json_extract(config, '$.max_nodes'))";

constexpr const char* kTrialColumns =
    "experiment, suite, instance, method, config, trial_index, seed, status, validated, "
    "wall_s, cpu_s, nodes, propagations, integration_steps, witness, error, threads, host, "
    "git_commit, started_at, finished_at, metrics";

// What a SQLite result code says about its cause. The file's content is the user's (bad input)
// when SQLite finds it is not a database, or a constraint refuses a row; everything else that
// fails on a database that passed the checks is the machine's: SQLITE_FULL, SQLITE_IOERR_*,
// SQLITE_BUSY/LOCKED after the busy timeout, SQLITE_READONLY_*, SQLITE_CANTOPEN, SQLITE_NOMEM...
StoreErrorKind kind_of(int rc) {
  switch (rc & 0xff) {
    case SQLITE_NOTADB:
    case SQLITE_CORRUPT:
    case SQLITE_CONSTRAINT:
    case SQLITE_MISMATCH:
    case SQLITE_FORMAT:
      return StoreErrorKind::bad_input;
    default:
      return StoreErrorKind::environment;
  }
}

[[noreturn]] void throw_sqlite_error(sqlite3* connection, std::string_view what) {
  const int rc = sqlite3_extended_errcode(connection);
  throw_store_error(kind_of(rc), fmt::format("{}: {}", what, sqlite3_errmsg(connection)), rc);
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
// A parent that cannot be made (a regular file in the way, a forbidden place) is a bad path;
// a full or failing disk is the machine's.
void create_parent_directories(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error) {
    const int code = error.value();
    const bool machine = code == ENOSPC || code == EIO || code == EDQUOT || code == ENOMEM;
    throw_store_error(machine ? StoreErrorKind::environment : StoreErrorKind::bad_input,
                     fmt::format("cannot create directory '{}' for results database '{}': {}",
                                 parent.string(), path, error.message()));
  }
}

[[noreturn]] void throw_not_hyfal(const std::string& path, std::string_view why) {
  throw_store_error(StoreErrorKind::bad_input,
                   fmt::format("'{}' is not a hyfal results database: {}", path, why));
}

// A SQLite URI for path (file: scheme, percent-encoded) with the given query.
std::string sqlite_uri(const std::string& path, std::string_view query) {
  std::error_code ignored;
  const std::string absolute = std::filesystem::absolute(path, ignored).string();
  std::string uri = "file:";
  for (const unsigned char c : absolute.empty() ? path : absolute) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~')
      uri += static_cast<char>(c);
    else
      uri += fmt::format("%{:02X}", c);
  }
  uri += '?';
  uri += query;
  return uri;
}

// Opens a connection; on failure throws StoreError with the cause (classified by SQLite's code).
using RawConnection = std::unique_ptr<sqlite3, decltype(&sqlite3_close_v2)>;
RawConnection open_connection(const std::string& path, const std::string& name, int flags) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(name.c_str(), &raw, flags, nullptr);
  RawConnection connection(raw, &sqlite3_close_v2);  // a handle is allocated even on failure
  if (rc != SQLITE_OK)
    throw_store_error(kind_of(rc), fmt::format("cannot open results database '{}': {}", path,
                                              raw == nullptr ? sqlite3_errstr(rc) : sqlite3_errmsg(raw)), rc);
  sqlite3_extended_result_codes(raw, 1);
  if (sqlite3_busy_timeout(raw, kBusyTimeoutMs) != SQLITE_OK)
    throw_sqlite_error(raw, fmt::format("cannot open results database '{}'", path));
  return connection;
}

// Runs sql, handing each row's first column (as text) to on_row. Throws StoreError naming path.
template <class OnRow>
void for_each_row(sqlite3* connection, const std::string& path, const std::string& sql, OnRow on_row) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(connection, sql.c_str(), -1, &raw, nullptr) != SQLITE_OK)
    throw_sqlite_error(connection, fmt::format("cannot read results database '{}'", path));
  std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> statement(raw, &sqlite3_finalize);
  for (;;) {
    const int rc = sqlite3_step(raw);
    if (rc == SQLITE_DONE) return;
    if (rc != SQLITE_ROW) throw_sqlite_error(connection, fmt::format("cannot read results database '{}'", path));
    const auto* chars = sqlite3_column_text(raw, 0);
    on_row(chars == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(chars)));
  }
}

// Whether the database holds hyfal's schema, read without writing anything. Returns false for a
// SQLite database without any table (a new database another process is creating now looks like
// this until its schema commits), true for a hyfal database; throws StoreError (bad_input)
// naming what is wrong for anything else.
bool check_hyfal_schema(sqlite3* connection, const std::string& path) {
  std::set<std::string> tables;
  try {
    for_each_row(connection, path, "SELECT name FROM sqlite_master WHERE type = 'table'",
                 [&](std::string name) { tables.insert(std::move(name)); });
  } catch (const StoreError& error) {
    const int rc = sqlite3_extended_errcode(connection);
    if ((rc & 0xff) == SQLITE_NOTADB || (rc & 0xff) == SQLITE_CORRUPT)
      throw_not_hyfal(path, sqlite3_errmsg(connection));
    throw;
  }
  if (tables.empty()) return false;
  if (!tables.count("meta")) throw_not_hyfal(path, "it has no table 'meta'");
  std::vector<std::string> versions;
  try {
    for_each_row(connection, path, "SELECT value FROM meta WHERE key = 'schema_version'",
                 [&](std::string value) { versions.push_back(std::move(value)); });
  } catch (const StoreError& error) {
    if (error.kind() == StoreErrorKind::environment &&
        (sqlite3_extended_errcode(connection) & 0xff) != SQLITE_ERROR)
      throw;
    throw_not_hyfal(path, "its table 'meta' is not hyfal's (no key and value columns)");
  }
  if (versions.empty()) throw_not_hyfal(path, "its table 'meta' holds no schema_version");
  if (versions.front() != std::to_string(kSchemaVersion) && versions.front() != "1")
    throw_store_error(StoreErrorKind::bad_input,
                     fmt::format("results database '{}': schema version {} is not supported by this build "
                                 "(reads 1 and {})",
                                 path, versions.front(), kSchemaVersion));
  for (const auto& [table, columns] : expected_columns()) {
    if (!tables.count(table)) {
      if (table == "claims") continue;  // added by writers; older databases lack it
      throw_not_hyfal(path, fmt::format("it has no table '{}'", table));
    }
    std::set<std::string> found;
    for_each_row(connection, path, fmt::format("SELECT name FROM pragma_table_info('{}')", table),
                 [&](std::string name) { found.insert(std::move(name)); });
    for (const std::string& column : columns)
      if (!found.count(column)) throw_not_hyfal(path, fmt::format("its table '{}' has no column '{}'", table, column));
    for (const std::string& column : found)
      if (!columns.count(column))
        throw_not_hyfal(path, fmt::format("its table '{}' has a column '{}' that hyfal's has not", table, column));
  }
  return true;
}

// The database's schema_version (one check_hyfal_schema accepted: 1 or kSchemaVersion).
int schema_version_of(sqlite3* connection, const std::string& path) {
  int version = kSchemaVersion;
  for_each_row(connection, path, "SELECT value FROM meta WHERE key = 'schema_version'",
               [&](const std::string& value) { version = value == "1" ? 1 : kSchemaVersion; });
  return version;
}

// Rebuilds a schema-1 database's trials table with schema 2's CHECK (SQLite cannot alter a
// CHECK: sqlite.org/lang_altertable.html, "Making Other Kinds Of Table Schema Changes": new
// table, copy, drop, rename, in one transaction with foreign keys off), relabels its budget stops
// (kSchema1BudgetStop) and sets schema_version 2. Rows keep their ids, so series stay attached.
// Another process may have migrated it first: then nothing is done.
void migrate_from_schema_1(sqlite3* connection, const std::string& path) {
  const std::string what = fmt::format("cannot migrate results database '{}' to schema {}", path, kSchemaVersion);
  execute(connection, "PRAGMA foreign_keys = OFF", what);  // a no-op inside a transaction: set before
  execute(connection, "BEGIN IMMEDIATE", what);
  try {
    if (schema_version_of(connection, path) == 1) {
      execute(connection, trials_table_sql("trials_schema_2").c_str(), what);
      execute(connection,
              fmt::format("INSERT INTO trials_schema_2 (id, {0}) SELECT id, {0} FROM trials", kTrialColumns).c_str(), what);
      execute(connection, "DROP TABLE trials", what);
      execute(connection, "ALTER TABLE trials_schema_2 RENAME TO trials", what);
      execute(connection, fmt::format("UPDATE trials SET status = 'budget' WHERE {}", kSchema1BudgetStop).c_str(), what);
      execute(connection, fmt::format("UPDATE meta SET value = '{}' WHERE key = 'schema_version'", kSchemaVersion).c_str(),
              what);
    }
    execute(connection, "COMMIT", what);
  } catch (...) {
    sqlite3_exec(connection, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_exec(connection, "PRAGMA foreign_keys = ON", nullptr, nullptr, nullptr);
    throw;
  }
  execute(connection, "PRAGMA foreign_keys = ON", what);
}

// The database files this process has open through a TrialStore, by (device, inode), counted.
// POSIX record locks belong to a process and a file, not to a descriptor: closing ANY descriptor
// of the database file drops every lock SQLite holds on it through its own. A header read of
// ours while a connection of this process is open would thus unlock the database under it: a
// reader in another process would then take itself for the last connection, checkpoint and reset
// the WAL under the writer, and see none of its later commits. So a file open here is not read
// outside SQLite again (it was checked when it was first opened).
class OpenDatabaseFiles {
 public:
  using Id = std::pair<dev_t, ino_t>;
  static OpenDatabaseFiles& instance() {
    static OpenDatabaseFiles files;
    return files;
  }
  static std::optional<Id> id_of(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return std::nullopt;
    return Id{st.st_dev, st.st_ino};
  }
  bool contains(const Id& id) {
    std::lock_guard lock(mutex_);
    return counts_.count(id) != 0;
  }
  // Registers the file for as long as the returned token lives.
  std::shared_ptr<const void> hold(const std::string& path) {
    const auto id = id_of(path);
    if (!id) return nullptr;
    {
      std::lock_guard lock(mutex_);
      ++counts_[*id];
    }
    return std::shared_ptr<const void>(nullptr, [this, id = *id](const void*) {
      std::lock_guard lock(mutex_);
      if (--counts_[id] == 0) counts_.erase(id);
    });
  }

 private:
  std::mutex mutex_;
  std::map<Id, int> counts_;
};

// Whether the file at path starts like a SQLite database (its 16-byte magic header). Reading it
// ourselves first means a file that is not one is never handed to SQLite at all.
bool has_sqlite_header(const std::string& path) {
  if (const auto id = OpenDatabaseFiles::id_of(path); id && OpenDatabaseFiles::instance().contains(*id)) return true;
  std::ifstream in(path, std::ios::binary);
  char header[16] = {};
  in.read(header, sizeof header);
  return in.gcount() == sizeof header && std::memcmp(header, "SQLite format 3", 16) == 0;
}

bool path_exists(const std::string& path) {
  std::error_code ignored;
  return std::filesystem::exists(path, ignored);
}

// Whether a rollback journal that may be hot lies beside the database: one that starts with
// SQLite's journal magic (sqlite.org/fileformat.html, "The Rollback Journal"; a committed journal
// in PERSIST mode has its header zeroed). A process killed inside a write transaction in
// rollback-journal mode leaves one: the switch of a new database to WAL is such a transaction.
bool may_have_hot_journal(const std::string& path) {
  static constexpr unsigned char kMagic[8] = {0xd9, 0xd5, 0x05, 0xf9, 0x20, 0xa1, 0x63, 0xd7};
  std::ifstream in(path + "-journal", std::ios::binary);
  unsigned char magic[8] = {};
  in.read(reinterpret_cast<char*>(magic), sizeof magic);
  return in.gcount() == sizeof magic && std::memcmp(magic, kMagic, sizeof magic) == 0;
}

// Whether this process may write the file at path and create files beside it (a journal).
bool may_write_file_and_folder(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::absolute(std::filesystem::path(path)).parent_path();
  return ::access(path.c_str(), W_OK) == 0 && ::access(parent.c_str(), W_OK | X_OK) == 0;
}

[[noreturn]] void throw_unfinished_transaction(const std::string& path) {
  throw_store_error(StoreErrorKind::environment,
                   fmt::format("cannot open results database '{}': a process killed while writing it left an "
                               "unfinished transaction ('{}-journal'), which only a user who may write the file "
                               "and its folder can roll back (any hyfal run or table does)",
                               path, path),
                   SQLITE_READONLY_ROLLBACK);
}

// Rolls back a hot journal of the database at path before anything reads it: SQLite does so on
// the first read of a connection that may write the file, while a read-only connection (the
// schema check, a reader) fails on it with SQLITE_READONLY_ROLLBACK ("attempt to write a
// readonly database") for as long as the journal stays. The rollback undoes a transaction that
// never committed, so the file returns to its last committed state: it restores what the
// database holds and changes nothing of it, whatever the file is. A journal that is not hot
// (its writer is alive and holds its lock) is left to its writer. Where this process may not
// write the file, throws StoreError naming the journal.
void roll_back_hot_journal(const std::string& path) {
  if (!may_have_hot_journal(path)) return;
  if (!may_write_file_and_folder(path)) throw_unfinished_transaction(path);
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(sqlite_uri(path, "mode=rw").c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_URI, nullptr) ==
      SQLITE_OK) {
    sqlite3_busy_timeout(raw, kBusyTimeoutMs);
    // The read's own failure (not a database after all, locked) is reported by the checks after it.
    sqlite3_exec(raw, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  }
  sqlite3_close_v2(raw);
}

// Writes a complete, empty hyfal database (the schema, schema_version, WAL mode) to the missing
// path in one step, so that a process killed at any instant leaves no file there or a whole
// one, never a half-created database. The schema is built in memory and serialized; WAL mode is
// the file-format version bytes 18 and 19 set to 2 (sqlite.org/fileformat.html, "File format
// version numbers": what `PRAGMA journal_mode = WAL` writes); the image goes to an unnamed file
// in path's folder (O_TMPFILE), is synced, and is linked into place. link never replaces a file: if another
// process created the database first, its database stays and is used. Returns true when a
// database is at path now; false where the file system cannot do this (no O_TMPFILE, no hard
// links), and the caller then creates the database in place.
bool create_database_file(const std::string& path) {
  sqlite3* memory = nullptr;
  if (sqlite3_open_v2(":memory:", &memory, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    sqlite3_close_v2(memory);
    return false;
  }
  RawConnection built(memory, &sqlite3_close_v2);
  const std::string what = fmt::format("cannot create the schema of results database '{}'", path);
  execute(memory, schema_sql().c_str(), what);
  sqlite3_int64 size = 0;
  std::unique_ptr<unsigned char, decltype(&sqlite3_free)> image(sqlite3_serialize(memory, "main", &size, 0),
                                                                &sqlite3_free);
  if (!image || size < 100) return false;
  image.get()[18] = 2;  // file format write version: WAL
  image.get()[19] = 2;  // file format read version: WAL

  std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) folder = ".";
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  if (fd < 0) return false;  // EOPNOTSUPP, EISDIR (no O_TMPFILE), ...
  const auto close_fd = [&] { ::close(fd); };
  std::size_t written = 0;
  while (written < static_cast<std::size_t>(size)) {
    const ssize_t n = ::write(fd, image.get() + written, static_cast<std::size_t>(size) - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = errno;
      close_fd();
      const bool machine = n < 0 && (error == ENOSPC || error == EIO || error == EDQUOT);
      if (machine)
        throw_store_error(StoreErrorKind::environment,
                         fmt::format("cannot create results database '{}': {}", path, std::strerror(error)));
      return false;
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    close_fd();
    throw_store_error(StoreErrorKind::environment,
                     fmt::format("cannot create results database '{}': {}", path, std::strerror(error)));
  }
  const std::string self = fmt::format("/proc/self/fd/{}", fd);
  int linked = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path.c_str(), AT_SYMLINK_FOLLOW);
  if (linked != 0 && errno != EEXIST) linked = ::linkat(fd, "", AT_FDCWD, path.c_str(), AT_EMPTY_PATH);
  const int error = errno;
  close_fd();
  if (linked != 0 && error != EEXIST) return false;  // no /proc, no hard links here
  if (linked == 0) {
    const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
      ::fsync(dir);  // the new name survives a power loss as the file's content does
      ::close(dir);
    }
  }
  return true;
}

// A regular, non-empty file, checked before SQLite sees it; false for a missing or empty file.
// Throws StoreError (bad_input) for a directory or something else that is no file.
bool existing_database_file(const std::string& path) {
  if (path.empty()) throw_store_error(StoreErrorKind::bad_input, "the results database path is empty");
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) return false;
  if (std::filesystem::is_directory(status))
    throw_store_error(StoreErrorKind::bad_input,
                     fmt::format("'{}' is a directory, not a results database", path));
  if (!std::filesystem::is_regular_file(status))
    throw_store_error(StoreErrorKind::bad_input, fmt::format("'{}' is not a regular file", path));
  // Before the header is read and before any read-only connection, which fails on a hot journal
  // (read as immutable, it would read the half-written file).
  roll_back_hot_journal(path);
  const auto size = std::filesystem::file_size(path, error);
  if (error)
    throw_store_error(StoreErrorKind::environment,
                     fmt::format("cannot open results database '{}': {}", path, error.message()));
  if (size == 0) return false;
  if (!has_sqlite_header(path)) throw_not_hyfal(path, "it is not a SQLite database");
  return true;
}

void remove_unused_wal_files(const std::string& path) noexcept;

// Removes the -wal and -shm files of a database (remove_unused_wal_files) when destroyed, unless
// disarmed. Declared before the connection it guards, it runs after that connection has closed,
// also when the constructor holding both throws half-way (a database that fails its first read).
class WalFilesCleanup {
 public:
  WalFilesCleanup() = default;
  WalFilesCleanup(const WalFilesCleanup&) = delete;
  WalFilesCleanup& operator=(const WalFilesCleanup&) = delete;
  ~WalFilesCleanup() {
    if (!path_.empty()) remove_unused_wal_files(path_);
  }
  void arm(const std::string& path) { path_ = path; }
  // The path whose files are no longer removed here (empty when disarmed already).
  std::string disarm() { return std::exchange(path_, std::string()); }

 private:
  std::string path_;
};

// A read-only connection to an existing database file. A read-only connection in WAL mode
// creates the -wal (empty) and -shm files when they are missing, and cannot delete them when it
// closes (SQLite's last writer does): once it has closed, they are removed (see
// remove_unused_wal_files), whether the database was read or failed to be.
class ReadOnlyConnection {
 public:
  explicit ReadOnlyConnection(const std::string& path);
  ReadOnlyConnection(const ReadOnlyConnection&) = delete;
  ReadOnlyConnection& operator=(const ReadOnlyConnection&) = delete;

  sqlite3* get() const { return connection_.get(); }
  // Hands the connection over; whoever closes it must then remove the -wal/-shm files of the
  // returned path, unless it is empty.
  std::pair<sqlite3*, std::string> release() {
    std::string cleanup = wal_files_.disarm();
    return {connection_.release(), std::move(cleanup)};
  }

 private:
  std::string path_;
  WalFilesCleanup wal_files_;  // not armed when read as immutable (no -wal/-shm at all)
  RawConnection connection_{nullptr, &sqlite3_close_v2};
};

ReadOnlyConnection::ReadOnlyConnection(const std::string& path) : path_(path) {
  const std::string wal = path + "-wal";
  const bool writable = may_write_file_and_folder(path);
  // Without a -wal file no connection has the database open, and one that cannot write it
  // cannot become a writer: reading it as immutable (no locks, no -shm) is then exact.
  const bool immutable = !path_exists(wal) && !writable;
  const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI;
  connection_ = open_connection(path, sqlite_uri(path, immutable ? "mode=ro&immutable=1" : "mode=ro"), flags);
  if (immutable) return;
  wal_files_.arm(path);
  // The first read opens the WAL index (-shm); where it cannot be created (a read-only folder)
  // SQLite fails with SQLITE_CANTOPEN, and the file is read as immutable instead.
  const int rc = sqlite3_exec(connection_.get(), "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  if ((rc & 0xff) == SQLITE_CANTOPEN || rc == SQLITE_READONLY_CANTINIT || rc == SQLITE_READONLY_RECOVERY ||
      rc == SQLITE_READONLY_DIRECTORY) {
    connection_ = open_connection(path, sqlite_uri(path, "mode=ro&immutable=1"), flags);
    wal_files_.disarm();
  } else if ((rc & 0xff) == SQLITE_NOTADB) {
    throw_not_hyfal(path, sqlite3_errmsg(connection_.get()));
  } else if (rc == SQLITE_READONLY_ROLLBACK) {
    throw_unfinished_transaction(path);  // a writer killed just now: its journal came after the roll-back
  } else if ((rc & 0xff) == SQLITE_READONLY) {
    // Never "attempt to write a readonly database" for a reader: say what SQLite wanted to write.
    throw_store_error(StoreErrorKind::environment,
                     fmt::format("cannot read results database '{}': SQLite must write beside it to read it "
                                 "(its -wal/-shm files) and may not ({})",
                                 path, sqlite3_errmsg(connection_.get())),
                     rc);
  } else if (rc != SQLITE_OK) {
    throw_sqlite_error(connection_.get(), fmt::format("cannot open results database '{}'", path));
  }
}

// Removes the -wal and -shm files of path if they hold nothing and no connection uses them: a
// read-write connection that reads one page and closes does exactly that (SQLite checkpoints
// the empty WAL, which writes nothing to the database, and deletes both files when it closes
// as the last connection). It takes no lock that a writer would wait on: if another connection
// has the database open, it leaves the files to it. A -wal with content (a crashed writer's) is
// left for the next writer to recover: a reader does not write.
void remove_unused_wal_files(const std::string& path) noexcept {
  std::error_code error;
  const std::string wal = path + "-wal";
  const bool wal_exists = std::filesystem::exists(wal, error);
  if (wal_exists && std::filesystem::file_size(wal, error) != 0) return;
  if (error || (!wal_exists && !path_exists(path + "-shm"))) return;
  if (::access(path.c_str(), W_OK) != 0) return;
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(sqlite_uri(path, "mode=rw").c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_URI,
                      nullptr) == SQLITE_OK)
    sqlite3_exec(raw, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  sqlite3_close_v2(raw);
}

// Makes a read-write connection ready for use and creates the schema where it is missing.
// Runs `body` in one transaction (`begin`: "BEGIN" for a consistent read, "BEGIN IMMEDIATE" for
// a write): committed when it returns (its value is returned), rolled back when it throws.
template <class Body>
auto in_transaction(sqlite3* connection, const char* begin, std::string_view begin_error,
                    std::string_view commit_error, Body&& body) {
  execute(connection, begin, begin_error);
  try {
    if constexpr (std::is_void_v<decltype(body())>) {
      body();
      execute(connection, "COMMIT", commit_error);
    } else {
      auto result = body();
      execute(connection, "COMMIT", commit_error);
      return result;
    }
  } catch (...) {
    sqlite3_exec(connection, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void configure(sqlite3* connection, const std::string& path) {
  const auto run = [&](const char* sql) {
    if (sqlite3_exec(connection, sql, nullptr, nullptr, nullptr) != SQLITE_OK)
      throw_sqlite_error(connection, fmt::format("cannot open results database '{}'", path));
  };
  // WAL: readers (a report run) do not block the writer. synchronous=NORMAL in WAL mode keeps
  // every committed trial across a crash of the process (kill -9); only a power loss may drop
  // the last commits, which is an acceptable trade for not syncing on each trial.
  run("PRAGMA journal_mode = WAL");
  run("PRAGMA synchronous = NORMAL");
  run("PRAGMA foreign_keys = ON");  // a series must belong to a stored trial
  // IMMEDIATE: two processes opening a new database at once create the schema one at a time.
  run("BEGIN IMMEDIATE");
  if (sqlite3_exec(connection, schema_sql().c_str(), nullptr, nullptr, nullptr) != SQLITE_OK) {
    const int rc = sqlite3_extended_errcode(connection);
    const std::string message = sqlite3_errmsg(connection);
    sqlite3_exec(connection, "ROLLBACK", nullptr, nullptr, nullptr);
    throw_store_error(kind_of(rc), fmt::format("cannot create the schema of results database '{}': {}", path, message), rc);
  }
  run("COMMIT");
}

double unix_time_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// Fields of /proc/<pid>/stat after the command name: [0] is the state, [19] the start time.
std::vector<std::string> proc_stat_fields(std::int64_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text;
  std::getline(in, text);
  const auto close = text.rfind(')');  // the command name may hold spaces and parentheses
  std::vector<std::string> fields;
  if (close == std::string::npos) return fields;
  std::istringstream rest(text.substr(close + 1));
  for (std::string field; rest >> field;) fields.push_back(field);
  return fields;
}

// Whether the process that made a claim on this host still runs: the pid exists, is no zombie,
// and started when the claimant did (a reused pid belongs to another process).
bool claimant_process_alive(std::int64_t pid, std::int64_t process_start) {
  if (pid <= 0) return false;
  if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return false;
  const auto fields = proc_stat_fields(pid);
  if (fields.size() < 20) return true;  // no /proc: trust kill()
  if (fields[0] == "Z" || fields[0] == "X") return false;
  return process_start == 0 || fields[19] == std::to_string(process_start);
}

struct ClaimRow {
  std::string host, token;
  std::int64_t pid = 0, process_start = 0;
  double heartbeat = 0.0;
};

bool claim_is_live(const ClaimRow& claim, const ClaimOwner& self, double now) {
  if (now - claim.heartbeat > kClaimStaleAfter) return false;
  if (claim.host == self.host) return claimant_process_alive(claim.pid, claim.process_start);
  return true;
}

}  // namespace

void TrialStore::ConnectionCloser::operator()(sqlite3* connection) const noexcept {
  // close_v2 defers the close until the last statement is finalized, so destruction order
  // (e.g. in a move assignment) cannot leak the connection.
  sqlite3_close_v2(connection);
  if (!remove_wal_files_of.empty()) remove_unused_wal_files(remove_wal_files_of);
}

void TrialStore::StatementFinalizer::operator()(sqlite3_stmt* statement) const noexcept {
  sqlite3_finalize(statement);
}

TrialStore::TrialStore(std::string path, Connection connection, bool writable)
    : path_(std::move(path)),
      writable_(writable),
      open_file_(OpenDatabaseFiles::instance().hold(path_)),
      connection_(std::move(connection)) {
  const char* key6 =
      "experiment = ?1 AND suite = ?2 AND instance = ?3 AND method = ?4 AND config = ?5 AND trial_index = ?6";
  select_trial_indices_ = prepare(
      "SELECT trial_index FROM trials "
      "WHERE experiment = ?1 AND suite = ?2 AND instance = ?3 AND method = ?4 AND config = ?5 "
      "AND status <> 'error'");
  // A schema-1 file (read-only: a writer migrated it) has its budget stops mapped as it is read.
  std::string columns = kTrialColumns;
  if (schema_version_of(connection_.get(), path_) == 1)
    columns.replace(columns.find(" status,"), 8,
                    fmt::format(" CASE WHEN {} THEN 'budget' ELSE status END,", kSchema1BudgetStop));
  select_trials_ = prepare(
      fmt::format("SELECT {} FROM trials WHERE ?1 IS NULL OR experiment = ?1 "
                  "ORDER BY suite, instance, method, config, trial_index, experiment",
                  columns)
          .c_str());
  select_series_ = prepare(
      "SELECT s.x, s.y FROM series s JOIN trials t ON s.trial_id = t.id WHERE t.experiment = ?1 AND "
      "t.suite = ?2 AND t.instance = ?3 AND t.method = ?4 AND t.config = ?5 AND t.trial_index = ?6 "
      "AND s.name = ?7 ORDER BY s.rowid");
  select_experiments_ = prepare("SELECT DISTINCT experiment FROM trials ORDER BY experiment");
  select_status_ = prepare(fmt::format("SELECT status FROM trials WHERE {}", key6).c_str());
  if (!writable_) return;  // a reader needs no claims table, and prepares no writes
  insert_trial_ = prepare(
      fmt::format("INSERT INTO trials ({}) VALUES "
                  "(?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, "
                  "?18, ?19, ?20, ?21, ?22)",
                  kTrialColumns)
          .c_str());
  insert_series_point_ =
      prepare("INSERT INTO series (trial_id, name, x, y) VALUES (?1, ?2, ?3, ?4)");
  delete_error_series_ = prepare(
      "DELETE FROM series WHERE trial_id IN (SELECT id FROM trials WHERE experiment = ?1 AND "
      "suite = ?2 AND instance = ?3 AND method = ?4 AND config = ?5 AND trial_index = ?6 AND "
      "status = 'error')");
  delete_error_trial_ = prepare(
      fmt::format("DELETE FROM trials WHERE {} AND status = 'error'", key6).c_str());
  select_claim_ = prepare(
      fmt::format("SELECT host, pid, process_start, token, heartbeat FROM claims WHERE {}", key6).c_str());
  upsert_claim_ = prepare(
      "INSERT OR REPLACE INTO claims (experiment, suite, instance, method, config, trial_index, host, pid, "
      "process_start, token, heartbeat) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  delete_claim_ = prepare(fmt::format("DELETE FROM claims WHERE {}", key6).c_str());
  refresh_claims_ = prepare("UPDATE claims SET heartbeat = ?1 WHERE token = ?2");
  delete_claims_of_owner_ = prepare("DELETE FROM claims WHERE token = ?1");
}

TrialStore::TrialStore(TrialStore&&) noexcept = default;
TrialStore& TrialStore::operator=(TrialStore&& other) noexcept {
  // Not member-wise: this store's statements must be finalized before its connection closes,
  // so that the connection really closes (and cleans up its -wal/-shm files) here and now.
  if (this != &other) {
    std::destroy_at(this);
    std::construct_at(this, std::move(other));
  }
  return *this;
}
TrialStore::~TrialStore() = default;

void TrialStore::require_writable(const char* what) const {
  if (!writable_)
    throw std::logic_error(fmt::format("{} on results database '{}' opened read-only", what, path_));
}

TrialStore TrialStore::open(const std::string& path) {
  // Two processes opening one database at the same moment (cooperative runs) can meet SQLite
  // states in which it answers SQLITE_BUSY without calling the busy handler (a journal-mode
  // change or WAL recovery under way in the other process): the whole open is retried then,
  // within the same busy timeout as every other statement.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(kBusyTimeoutMs);
  for (;;) {
    try {
      return open_once(path);
    } catch (const StoreError& e) {
      const int primary = e.sqlite_code() & 0xff;
      if ((primary != SQLITE_BUSY && primary != SQLITE_LOCKED) || std::chrono::steady_clock::now() >= give_up) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}

TrialStore TrialStore::open_once(const std::string& path) {
  // A missing database is created whole before anything opens it (a kill at any instant leaves
  // none or a complete one); an empty file, or a file system without O_TMPFILE or hard links,
  // gets its schema in place below, where a kill can leave a hot journal, rolled back at the
  // next open (ReadOnlyConnection).
  bool existing = existing_database_file(path);
  if (!existing && !path_exists(path)) {
    create_parent_directories(path);
    // Re-read: what is at path now is ours or another process's (a dangling link stays missing).
    if (create_database_file(path)) existing = existing_database_file(path);
  }
  if (existing) {
    // Check first, reading only: a file that is not a hyfal database is never written to (a hot
    // journal's roll-back restores it, see roll_back_hot_journal).
    const ReadOnlyConnection check(path);  // closed (and its -wal/-shm removed) at the end of this block
    check_hyfal_schema(check.get(), path);
  }
  RawConnection raw =
      open_connection(path, sqlite_uri(path, "mode=rwc"), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_URI);
  // SQLite opens a file it may not write read-only, without a word; its first read would then
  // create -wal and -shm files that no read-only connection can remove. Refused before that read.
  if (sqlite3_db_readonly(raw.get(), "main") == 1)
    throw_store_error(StoreErrorKind::environment,
                     fmt::format("cannot open results database '{}' for writing: {}", path,
                                 sqlite3_errstr(SQLITE_READONLY)),
                     SQLITE_READONLY);
  Connection connection(raw.release());
  configure(connection.get(), path);
  // Another process may have filled an empty file in between: check what we now write to.
  if (!check_hyfal_schema(connection.get(), path))
    throw_store_error(StoreErrorKind::environment,
                     fmt::format("results database '{}' lost its schema while opening", path));
  if (schema_version_of(connection.get(), path) == 1) migrate_from_schema_1(connection.get(), path);
  return TrialStore(path, std::move(connection), true);
}

TrialStore TrialStore::open_read_only(const std::string& path) {
  if (!existing_database_file(path)) {
    if (!path_exists(path))
      throw_store_error(StoreErrorKind::bad_input, fmt::format("no results database at '{}'", path));
    throw_not_hyfal(path, "it is empty");
  }
  auto [raw, cleanup_path] = ReadOnlyConnection(path).release();
  Connection connection(raw, ConnectionCloser{std::move(cleanup_path)});
  if (!check_hyfal_schema(connection.get(), path)) throw_not_hyfal(path, "it has no tables");
  return TrialStore(path, std::move(connection), false);
}

TrialStore::Statement TrialStore::prepare(const char* sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v3(connection_.get(), sql, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr) !=
      SQLITE_OK)
    throw_sqlite_error(connection_.get(), "cannot prepare statement");
  return Statement(raw);
}

std::int64_t TrialStore::insert(const TrialRecord& record) {
  require_writable("insert");
  return in_transaction(connection_.get(), "BEGIN IMMEDIATE", fmt::format("cannot start transaction on results database '{}'", path_),
                        fmt::format("cannot commit trial to results database '{}'", path_), [&] {
    const std::int64_t id = store_in_transaction(record);
    return id;
  });
}

void TrialStore::insert_all(const std::vector<TrialRecord>& records) {
  require_writable("insert_all");
  in_transaction(connection_.get(), "BEGIN IMMEDIATE", fmt::format("cannot start transaction on results database '{}'", path_),
                        fmt::format("cannot commit {} trials to results database '{}'", records.size(), path_), [&] {
    for (const TrialRecord& record : records) store_in_transaction(record);
  });
}

std::int64_t TrialStore::store_in_transaction(const TrialRecord& record) {
  // An earlier attempt of the same trial that ended in error is replaced (so a resumed run
  // retries errors), the row is stored with its series, and the trial's claim ends with it.
  for (sqlite3_stmt* statement : {delete_error_series_.get(), delete_error_trial_.get(), delete_claim_.get()}) {
    StatementUse use(statement);
    bind_key_without_index(use, record.key);
    use.bind(6, record.key.trial_index);
    if (sqlite3_step(statement) != SQLITE_DONE)
      throw_sqlite_error(connection_.get(), fmt::format("cannot replace an errored trial in '{}'", path_));
  }
  const std::int64_t id = insert_row(record);
  for (const auto& [name, points] : record.series) insert_points(id, name, points);
  return id;
}

std::vector<TrialRecord> TrialStore::load_with_series() {
  // A read transaction on this connection: a writer committing meanwhile is not seen half-way.
  return in_transaction(connection_.get(), "BEGIN", fmt::format("cannot read results database '{}'", path_),
                        fmt::format("cannot read results database '{}'", path_), [&] {
    std::vector<TrialRecord> records = load();
    std::map<std::int64_t, std::size_t> position_of_id;
    {
      // load()'s order, which is total (the key is UNIQUE): row i of both queries is one trial.
      Statement ids = prepare("SELECT id FROM trials ORDER BY suite, instance, method, config, trial_index, experiment");
      StatementUse use(ids.get());
      for (std::size_t i = 0; use.step(); ++i) {
        if (i >= records.size())
          throw_store_error(StoreErrorKind::environment, fmt::format("results database '{}' changed while read", path_));
        position_of_id[use.integer(0)] = i;
      }
    }
    Statement points = prepare("SELECT trial_id, name, x, y FROM series ORDER BY rowid");
    StatementUse use(points.get());
    while (use.step()) {
      const auto at = position_of_id.find(use.integer(0));
      if (at == position_of_id.end()) continue;  // a point of no stored trial: nothing to carry
      auto& series = records[at->second].series;
      const std::string name = use.text(1);
      auto it = std::find_if(series.begin(), series.end(), [&](const auto& s) { return s.first == name; });
      if (it == series.end()) it = series.insert(series.end(), {name, {}});
      it->second.emplace_back(use.real(2), use.real(3));
    }
    return records;
  });
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
    throw_store_error(StoreErrorKind::bad_input, fmt::format("results database '{}' already holds the trial ({})", path_,
                                 describe(record.key)));
  if (rc != SQLITE_DONE)
    throw_sqlite_error(connection_.get(),
                       fmt::format("cannot store trial ({}) in results database '{}'",
                                   describe(record.key), path_));
  return sqlite3_last_insert_rowid(connection_.get());
}

void TrialStore::insert_series(std::int64_t trial_id, const std::string& name,
                               std::span<const std::pair<double, double>> points) {
  require_writable("insert_series");
  // One transaction for all points: a series is stored whole or not at all, and one commit is
  // much cheaper than one per point.
  in_transaction(connection_.get(), "BEGIN IMMEDIATE", fmt::format("cannot start transaction on results database '{}'", path_),
                        fmt::format("cannot commit series '{}' of trial {} to results database '{}'", name,
                        trial_id, path_), [&] {
    insert_points(trial_id, name, points);
  });
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
      throw_store_error(StoreErrorKind::bad_input, fmt::format("results database '{}' holds unknown trial status '{}'", path_,
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

// --- claims -------------------------------------------------------------------------------------

const ClaimOwner& ClaimOwner::this_process() {
  static const ClaimOwner owner = [] {
    ClaimOwner o;
    char name[256] = {};
    o.host = gethostname(name, sizeof name - 1) == 0 ? name : "unknown";
    // Processes in different pid namespaces (containers) may share a host name: a pid means
    // something only inside its namespace, so the namespace is part of where the claim was made.
    std::error_code error;
    const auto ns = std::filesystem::read_symlink("/proc/self/ns/pid", error);
    if (!error) o.host += " " + ns.string();
    o.pid = ::getpid();
    const auto fields = proc_stat_fields(o.pid);
    if (fields.size() >= 20) o.process_start = std::stoll(fields[19]);
    std::random_device entropy;
    o.token = fmt::format("{:08x}{:08x}{:08x}{:08x}", entropy(), entropy(), entropy(), entropy());
    return o;
  }();
  return owner;
}

bool TrialStore::is_stored(const TrialKey& key) {
  StatementUse use(select_status_.get());
  bind_key_without_index(use, key);
  use.bind(6, key.trial_index);
  return use.step() && use.text(0) != to_string(TrialStatus::error);
}

bool TrialStore::claim(const TrialKey& key, const ClaimOwner& owner) {
  require_writable("claim");
  // One write transaction: two processes claiming the same trial take turns, and the second
  // sees the first one's claim.
  return in_transaction(connection_.get(), "BEGIN IMMEDIATE", fmt::format("cannot start transaction on results database '{}'", path_),
                        fmt::format("cannot commit a claim to results database '{}'", path_), [&] {
    bool available = !is_stored(key);
    if (available) {
      StatementUse use(select_claim_.get());
      bind_key_without_index(use, key);
      use.bind(6, key.trial_index);
      if (use.step()) {
        const ClaimRow row{use.text(0), use.text(3), use.integer(1), use.integer(2), use.real(4)};
        available = row.token == owner.token || !claim_is_live(row, owner, unix_time_now());
      }
    }
    if (available) {
      StatementUse use(upsert_claim_.get());
      bind_key_without_index(use, key);
      use.bind(6, key.trial_index);
      use.bind(7, owner.host);
      use.bind(8, owner.pid);
      use.bind(9, owner.process_start);
      use.bind(10, owner.token);
      use.bind(11, unix_time_now());
      if (use.step()) throw std::logic_error("an INSERT returned a row");
    }
    return available;
  });
}

std::vector<TrialProgress> TrialStore::progress(const std::vector<TrialKey>& keys, const ClaimOwner& self) {
  require_writable("progress");  // the claims table is a writer's
  // One read transaction: every answer comes from the same snapshot. It never blocks a writer.
  return in_transaction(connection_.get(), "BEGIN", fmt::format("cannot read results database '{}'", path_),
                        fmt::format("cannot read results database '{}'", path_), [&] {
    const double now = unix_time_now();
    std::vector<TrialProgress> states;
    states.reserve(keys.size());
    for (const TrialKey& key : keys) {
      std::optional<std::string> status;
      {
        StatementUse use(select_status_.get());
        bind_key_without_index(use, key);
        use.bind(6, key.trial_index);
        if (use.step()) status = use.text(0);
      }
      if (status && *status != to_string(TrialStatus::error)) {
        states.push_back(TrialProgress::stored);
        continue;
      }
      StatementUse use(select_claim_.get());
      bind_key_without_index(use, key);
      use.bind(6, key.trial_index);
      if (use.step()) {
        // A claim left by this process (a failed attempt) or by an owner that is gone: run it.
        const ClaimRow row{use.text(0), use.text(3), use.integer(1), use.integer(2), use.real(4)};
        states.push_back(row.token != self.token && claim_is_live(row, self, now) ? TrialProgress::claimed_by_other
                                                                                  : TrialProgress::needs_runner);
      } else {
        // Unclaimed: an error row was stored by whoever retried the trial in this run.
        states.push_back(status ? TrialProgress::stored_error : TrialProgress::needs_runner);
      }
    }
    return states;
  });
}

std::int64_t TrialStore::refresh_claims(const ClaimOwner& owner) {
  require_writable("refresh_claims");
  StatementUse use(refresh_claims_.get());
  use.bind(1, unix_time_now());
  use.bind(2, owner.token);
  use.step();
  return sqlite3_changes64(connection_.get());
}

void TrialStore::release_claims(const ClaimOwner& owner) {
  require_writable("release_claims");
  StatementUse use(delete_claims_of_owner_.get());
  use.bind(1, owner.token);
  use.step();
}

ClaimHeartbeat::ClaimHeartbeat(const std::string& database_path, ClaimOwner owner)
    : store_(TrialStore::open(database_path)), owner_(std::move(owner)) {
  thread_ = std::jthread([this](std::stop_token stop) {
    const auto interval = std::chrono::duration<double>(kClaimHeartbeatInterval);
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, stop, interval, [] { return false; }) && !stop.stop_requested()) {
      try {
        store_.refresh_claims(owner_);
      } catch (const StoreError&) {
        // Busy past the timeout or a passing I/O error: the next beat tries again; the claims go
        // stale only after kClaimStaleAfter without any successful beat.
      }
    }
  });
}

ClaimHeartbeat::~ClaimHeartbeat() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
  try {
    store_.release_claims(owner_);
  } catch (const StoreError&) {
    // Unreleased claims go stale on their own (at once on this host, once the process is gone).
  }
}

}  // namespace hyfal
