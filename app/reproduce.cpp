#include "app/reproduce.hpp"

#include "parallel/cluster.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "app/experiment_file.hpp"
#include "app/plan.hpp"
#include "core/options.hpp"
#include "core/rng.hpp"
#include "results/paper_report.hpp"
#include "results/sweep_report.hpp"
#include "results/text_format.hpp"
#include "suites/registry.hpp"

#ifndef HYFAL_SOURCE_DIR
#define HYFAL_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace hyfal::cli {

std::string git_commit() {
  std::string out;
  if (FILE* p = popen("git -C '" HYFAL_SOURCE_DIR "' rev-parse --short=12 HEAD 2>/dev/null", "r")) {
    char buf[64];
    while (fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

void write_file_atomic(const std::string& path, const std::string& text) {
  // Callers check the folder up front (check_directory_creatable, bad input); what fails here is
  // the environment: a full disk, an I/O error, a permission lost since the check.
  const fs::path p(path), tmp = path + ".tmp";
  try {
    if (p.has_parent_path()) fs::create_directories(p.parent_path());
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out || !(out << text) || !out.flush()) {
        const int cause = errno;
        out.close();
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw EnvironmentError(fmt::format("cannot write '{}': {}", path, cause ? std::strerror(cause) : "write failed"));
      }
    }
    fs::rename(tmp, p);
  } catch (const fs::filesystem_error& e) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw EnvironmentError(fmt::format("cannot write '{}': {}", path, e.code().message()));
  }
}

void check_directory_creatable(const std::string& dir, const std::string& what) {
  std::error_code ec;
  fs::path p = fs::absolute(fs::path(dir), ec);
  if (ec) throw UsageError(fmt::format("{} '{}': {}", what, dir, ec.message()));
  // The deepest part of the path that exists must be a directory: the rest can then be created.
  while (!p.empty()) {
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st)) throw UsageError(fmt::format("{} '{}': '{}' is not a directory", what, dir, p.string()));
      if (::access(p.c_str(), W_OK | X_OK) != 0)
        throw UsageError(fmt::format("{} '{}': '{}' is not writable", what, dir, p.string()));
      return;
    }
    if (p == p.parent_path()) return;
    p = p.parent_path();
  }
}

void check_output_path(const std::string& path, const std::string& what) {
  if (path.empty()) throw UsageError(fmt::format("{} '': an empty path is not allowed", what));
  if (path.find('\0') != std::string::npos) throw UsageError(fmt::format("{}: the path holds a NUL byte", what));
}

void check_experiment_name(const std::string& name) {
  const auto bad = [&](const std::string& why) {
    return UsageError(fmt::format("--experiment '{}': {} (allowed: letters, digits, '.', '_', '-', '+', and '/' "
                                  "between non-empty parts other than '.' and '..'; at most {} characters)",
                                  name, why, kMaxExperimentName));
  };
  if (name.empty()) throw bad("empty");
  if (name.size() > kMaxExperimentName) throw bad("too long");
  for (const char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' || c == '+' || c == '/'))
      throw bad(fmt::format("character '{}' is not allowed", std::isprint(static_cast<unsigned char>(c)) ? std::string(1, c)
                                                                                                      : fmt::format("\\x{:02x}", static_cast<unsigned char>(c))));
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = name.find('/', start);
    const std::string part = name.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (part.empty()) throw bad("empty part (leading, trailing or doubled '/')");
    if (part == "." || part == "..") throw bad(fmt::format("part '{}' would leave the witness folder", part));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
}

// --- shared by run and reproduce --------------------------------------------------------------

void overlay_settings(Settings& base, const Settings& layer) {
  for (const auto& kv : layer) {
    bool replaced = false;
    for (auto& b : base)
      if (b.first == kv.first) {
        b.second = kv.second;
        replaced = true;
      }
    if (!replaced) base.push_back(kv);
  }
}

bool TrialGroup::contains(const TrialRecord& r) const {
  return r.key.experiment == base.experiment && r.key.suite == base.suite && r.key.instance == base.instance &&
         r.key.method == base.method && r.key.config == base.config && r.key.trial_index >= 0 &&
         r.key.trial_index < spec.trials;
}

TrialGroup resolve_trial_group(const TrialGroupSpec& spec) {
  const SuiteEntry* suite = spec.suite;
  const MethodEntry* method = spec.method;
  Settings instance_sets, method_sets;
  for (const auto& kv : spec.settings) {
    if (has_option(suite->parameters, kv.first))
      instance_sets.push_back(kv);
    else if (has_option(method->options, kv.first))
      method_sets.push_back(kv);
    else
      throw UsageError(fmt::format("--set {}={}: suite '{}' and method '{}' have no setting '{}' (see 'hyfal list')",
                                   kv.first, kv.second, suite->name, method->name, kv.first));
  }
  TrialGroup g;
  g.spec = spec;
  g.instance = resolve_options(suite->parameters, instance_sets);
  g.options = resolve_options(method->options, method_sets);
  try {
    g.system = suite->make(g.instance);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  // The method's own checks (relations between options, what it needs of the system) run here,
  // once, so that a bad combination is reported before the database is opened, not per trial.
  try {
    if (method->check_system) method->check_system(*g.system, g.options);
    (void)method->make(g.options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("method '{}' on suite '{}': {}", method->name, suite->name, e.what()));
  }
  g.config = {{"master_seed", spec.seed}, {"max_nodes", spec.max_nodes}, {"timeout_s", spec.timeout_s},
              {"options", g.options}};
  g.base = TrialKey{spec.experiment, suite->name, g.instance.dump(), method->name, g.config.dump(), 0};
  return g;
}

std::vector<TrialJob> prepare_jobs(const TrialGroup& g, const std::set<std::int64_t>& stored, const Shard& shard,
                                   std::int64_t first_position) {
  std::vector<TrialJob> jobs;
  for (int i = 0; i < g.spec.trials; ++i) {
    if (!shard.keeps(first_position + i) || stored.count(i)) continue;
    TrialJob job;
    job.key = g.base;
    job.key.trial_index = i;
    job.system = g.system;
    job.method = g.spec.method;
    job.method_options = g.options;
    job.limits = {g.spec.timeout_s, g.spec.max_nodes};
    job.seed = trial_seed(g.spec.seed, g.base.suite, g.base.instance, g.base.method, i);
    job.priority = g.spec.priority;
    jobs.push_back(std::move(job));
  }
  return jobs;
}

std::vector<const TrialGroup*> distinct_groups(const std::vector<const TrialGroup*>& groups) {
  std::vector<const TrialGroup*> distinct;
  std::set<std::string> seen;
  for (const TrialGroup* g : groups) {
    const TrialKey& k = g->base;
    if (seen.insert(Json::array({k.suite, k.instance, k.method, k.config}).dump()).second) distinct.push_back(g);
  }
  return distinct;
}

Shard shard_option(const std::string& text) {
  if (text.empty()) return {};
  const auto shard = parse_shard(text);
  if (!shard)
    throw UsageError(fmt::format("--shard '{}': expected i/K with 0 <= i < K <= {} (the i-th of K shares)", text,
                                 kMaxShards));
  return *shard;
}

EngineOptions make_engine_options(int threads, const std::string& witness_dir, bool progress) {
  EngineOptions eo;
  eo.threads = threads;
  eo.witness_dir = witness_dir;
  eo.progress = progress;
  eo.host = host_name();
  eo.git_commit = git_commit();
  return eo;
}

JobsRun run_jobs(const std::vector<TrialJob>& jobs, TrialStore& store, const EngineOptions& engine) {
  JobsRun result;
  if (jobs.empty()) return result;
  const ClaimOwner& owner = ClaimOwner::this_process();
  const ClaimHeartbeat heartbeat(store.path(), owner);  // releases this process's claims when it ends
  std::vector<TrialKey> keys;
  keys.reserve(jobs.size());
  for (const TrialJob& job : jobs) keys.push_back(job.key);

  const auto sink = [&](const TrialRecord& r) {
    try {
      store.insert(r);
    } catch (const StoreError& e) {
      // Stored meanwhile by another process that took this one's claim for stale (no heartbeat
      // for kClaimStaleAfter): the same trial with the same seed, so the stored row stands.
      if (e.kind() != StoreErrorKind::bad_input || !store.is_stored(r.key)) throw;
      return;
    }
    ++result.run_now;
    if (r.status == TrialStatus::error)
      fmt::print(stderr, "[hyfal] {} trial {} error: {}\n", r.key.method, r.key.trial_index, r.error);
  };
  const auto claim = [&](const TrialJob& job) { return store.claim(job.key, owner); };

  std::vector<TrialJob> pending = jobs;
  // Higher priority first (a sweep's large cells), stable: otherwise in the order given.
  std::stable_sort(pending.begin(), pending.end(),
                   [](const TrialJob& x, const TrialJob& y) { return x.priority > y.priority; });
  bool waited = false;
  for (;;) {
    if (!pending.empty()) {
      if (Cluster* cluster = Cluster::current())
        cluster->run_trials(pending, engine, sink, claim);  // on every rank of the MPI job
      else
        run_trials(pending, engine, sink, claim);
    }
    pending.clear();
    const std::vector<TrialProgress> states = store.progress(keys, owner);
    std::size_t running_elsewhere = 0;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      if (states[i] == TrialProgress::needs_runner) pending.push_back(jobs[i]);
      running_elsewhere += states[i] == TrialProgress::claimed_by_other;
    }
    if (!pending.empty()) continue;  // their owner is gone: run them here
    if (running_elsewhere == 0) {
      result.errors = static_cast<std::size_t>(std::count(states.begin(), states.end(), TrialProgress::stored_error));
      break;
    }
    if (engine.progress) {
      fmt::print(stderr, "\r[hyfal] waiting for {} trials that other processes are running   ", running_elsewhere);
      waited = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  if (waited) fmt::print(stderr, "\n");
  return result;
}

std::string read_input_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw UsageError(fmt::format("'{}' is a directory, not a file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw UsageError(fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
  return ss.str();
}

PaperTable find_table(const std::string& id_or_path) {
  const bool is_path = id_or_path.find('/') != std::string::npos ||
                       (id_or_path.size() >= 5 && id_or_path.compare(id_or_path.size() - 5, 5, ".toml") == 0);
  if (is_path) return load_paper_table(read_input_file(id_or_path), id_or_path);
  if (const PaperTable* t = find_builtin_paper_table(id_or_path)) return *t;
  throw UsageError(fmt::format("unknown table '{}' (see 'hyfal list'; a table file's path ends in .toml)", id_or_path));
}

// --- reproduce --------------------------------------------------------------------------------

namespace {

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec);
}

const TableProfile& profile_of(const PaperTable& table, const std::string& name) {
  if (name == "smoke") return table.smoke;
  if (name == "quick") return table.quick;
  if (name == "paper") return table.paper;
  throw UsageError(fmt::format("--profile {}: expected smoke, quick or paper", name));
}

// Runs the trials of `groups` (in this order) that the store does not hold yet, all in one pool;
// groups that resolve to the same trials (same instance, method and config) share them.
struct TableTrials {
  EngineOptions engine;
  std::size_t total = 0, run_now = 0, errors = 0;
};
TableTrials run_table_trials(const std::vector<const TrialGroup*>& groups, TrialStore& store, const ReproduceArgs& a,
                             int trials_per_group) {
  std::vector<TrialJob> jobs;
  std::size_t stored_count = 0, total = 0;
  const Shard shard = shard_option(a.shard);
  std::int64_t position = 0;  // of the group's trial 0 in the table's full job list
  for (const TrialGroup* g : distinct_groups(groups)) {
    auto group_jobs = prepare_jobs(*g, store.stored_trial_indices(g->base), shard, position);
    const auto in_shard = static_cast<std::size_t>(shard.count_in(position, trials_per_group));
    total += in_shard;
    stored_count += in_shard - group_jobs.size();
    position += trials_per_group;
    for (auto& j : group_jobs) jobs.push_back(std::move(j));
  }
  TableTrials t{make_engine_options(a.threads, a.witness_dir, isatty(STDERR_FILENO) != 0)};
  t.total = total;
  if (stored_count > 0)
    fmt::print(stderr, "[hyfal] resuming: {} of {} trials already stored in {}\n", stored_count, t.total, a.db);
  const JobsRun jobs_run = run_jobs(jobs, store, t.engine);
  t.run_now = jobs_run.run_now;
  t.errors = jobs_run.errors;
  return t;
}

// A shard's table holds only what its database holds: until the shards are merged, a partial one.
void print_shard_note(const ReproduceArgs& a) {
  if (a.shard.empty()) return;
  fmt::print(stderr,
             "[hyfal] note: --shard {}: the table covers only the trials in {} (this shard and any stored before); "
             "merge the shard databases (hyfal merge merged.sqlite ...) and run 'hyfal reproduce {} --profile {} "
             "--db merged.sqlite' for the full table\n",
             a.shard, a.db, a.id, a.profile);
}

ReportHeader make_header(const ReproduceArgs& a, const TableProfile& profile, const EngineOptions& eo,
                         const std::string& experiment) {
  ReportHeader h;
  h.profile = a.profile;
  h.trials = profile.trials;
  h.timeout_s = profile.timeout_s;
  h.max_nodes = profile.max_nodes;
  h.profile_settings = profile.settings;
  h.seed = a.seed;
  h.threads = a.threads > 0 ? a.threads : default_thread_count();
  h.host = eo.host;
  h.nproc = static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN));
  h.cpu_model = cpu_model_name();
  h.date_utc = utc_now();
  h.git_commit = eo.git_commit;
  h.experiment = experiment;
  return h;
}

// A sweep table: one trial group per (block, row, column, instance); all jobs in one pool.
int reproduce_sweep(const ReproduceArgs& a, const SuiteEntry* suite, const PaperTable& table,
                    const TableProfile& profile, const std::string& experiment) {
  const TableSweep& sw = *table.sweep;
  if (profile.instances < 1)
    throw UsageError(fmt::format("table '{}' profile '{}': instances must be >= 1", table.id, a.profile));
  const std::size_t blocks = sw.blocks.empty() ? 1 : sw.blocks.size();
  const std::size_t cols = sw.columns.size();
  const std::size_t run = profile.columns < 0 ? cols : std::min<std::size_t>(cols, static_cast<std::size_t>(profile.columns));
  struct Cell {
    std::size_t b, row, col;
    TrialGroup group;
  };
  std::vector<Cell> cells;
  for (std::size_t b = 0; b < blocks; ++b)
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const PaperRow& row = table.rows[r];
      const MethodEntry* method = find_method(row.method);
      if (!method)
        throw UsageError(fmt::format("table '{}' row '{}': method '{}' is not registered", table.id, row.label, row.method));
      for (std::size_t c = 0; c < run; ++c)
        for (int k = 0; k < profile.instances; ++k) {
          TrialGroupSpec spec;
          spec.experiment = experiment;
          spec.suite = suite;
          spec.method = method;
          spec.settings = profile.settings;  // then block, column, instance and row: later layers win
          if (!sw.blocks.empty()) overlay_settings(spec.settings, sw.blocks[b].settings);
          overlay_settings(spec.settings, sw.columns[c].settings);
          if (!sw.instance_key.empty()) overlay_settings(spec.settings, {{sw.instance_key, std::to_string(k)}});
          overlay_settings(spec.settings, row.settings);
          spec.trials = profile.trials;
          spec.timeout_s = profile.timeout_s;
          spec.max_nodes = profile.max_nodes;
          spec.seed = a.seed;
          // A sweep's columns grow (|Q| from 1^2 to 1024^2, N from 10 to 20): the later a column,
          // the longer its trials, so they start first and no rank is left with one at the end.
          spec.priority = static_cast<int>(c);
          try {
            cells.push_back({b, r, c, resolve_trial_group(spec)});
          } catch (const std::invalid_argument& e) {
            throw UsageError(fmt::format("table '{}' row '{}': {}", table.id, row.label, e.what()));
          } catch (const UsageError& e) {
            throw UsageError(fmt::format("table '{}' row '{}': {}", table.id, row.label, e.what()));
          }
        }
    }

  // The largest columns first, so that the pool does not end waiting on one long trial.
  std::vector<std::size_t> order(cells.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return cells[x].col > cells[y].col; });
  std::vector<const TrialGroup*> ordered;
  for (const std::size_t i : order) ordered.push_back(&cells[i].group);
  if (a.plan) return print_plan(fmt::format("table {} --profile {}", table.id, a.profile), ordered, shard_option(a.shard), a.db);
  TrialStore store = TrialStore::open(a.db);
  const TableTrials run_info = run_table_trials(ordered, store, a, profile.trials);
  const EngineOptions& eo = run_info.engine;

  std::vector<std::vector<std::vector<std::vector<TrialRecord>>>> trials(
      blocks, std::vector<std::vector<std::vector<TrialRecord>>>(table.rows.size(),
                                                                 std::vector<std::vector<TrialRecord>>(cols)));
  const auto records = store.load(experiment);
  for (const Cell& cell : cells)
    for (const TrialRecord& record : records)
      if (cell.group.contains(record)) trials[cell.b][cell.row][cell.col].push_back(record);
  SweepReport report = make_sweep_report(table, trials, static_cast<int>(run));
  if (report.suite.empty()) report.suite = suite->name;
  const ReportHeader header = make_header(a, profile, eo, experiment);
  const std::string markdown = to_markdown(report, header);
  const fs::path out_dir(a.out_dir);
  write_file_atomic((out_dir / (table.id + ".md")).string(), markdown);
  write_file_atomic((out_dir / (table.id + ".csv")).string(), to_csv(report, header));
  std::cout << markdown << std::flush;
  fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run_info.total,
             run_info.run_now, (out_dir / (table.id + ".md")).string(), (out_dir / (table.id + ".csv")).string(), a.db);
  print_shard_note(a);
  return run_info.errors ? 1 : 0;
}

}  // namespace

int cmd_reproduce(const ReproduceArgs& a) {
  // Everything is checked before the database is opened, so a bad input writes nothing.
  const PaperTable loaded = find_table(a.id);
  const PaperTable* table = &loaded;
  const SuiteEntry* suite = find_suite(table->suite);
  if (!suite) throw UsageError(fmt::format("table '{}': unknown suite '{}'", table->id, table->suite));
  const TableProfile& profile = profile_of(*table, a.profile);
  if (profile.trials < 1 || !(profile.timeout_s > 0.0) || profile.max_nodes < 1)
    throw UsageError(fmt::format("table '{}' profile '{}': trials, timeout and max_nodes must be positive",
                                 table->id, a.profile));
  if (table->rows.empty()) throw UsageError(fmt::format("table '{}' has no rows", table->id));
  const std::string experiment = fmt::format("{}/{}", table->id, a.profile);
  (void)shard_option(a.shard);  // a bad --shard is refused before anything is opened
  check_output_path(a.db, "--db");
  check_output_path(a.witness_dir, "--witness-dir");
  check_output_path(a.out_dir, "--out-dir");
  check_experiment_name(experiment);
  check_directory_creatable(a.out_dir, "--out-dir");
  check_directory_creatable(a.witness_dir, "--witness-dir");
  if (table->sweep) return reproduce_sweep(a, suite, *table, profile, experiment);

  std::vector<TrialGroup> groups;
  for (const PaperRow& row : table->rows) {
    const MethodEntry* method = find_method(row.method);
    if (!method)
      throw UsageError(fmt::format("table '{}' row '{}': method '{}' is not registered (see 'hyfal list')",
                                   table->id, row.label, row.method));
    TrialGroupSpec spec;
    spec.experiment = experiment;
    spec.suite = suite;
    spec.method = method;
    spec.settings = profile.settings;  // then the row's own, which wins
    overlay_settings(spec.settings, row.settings);
    spec.trials = profile.trials;
    spec.timeout_s = profile.timeout_s;
    spec.max_nodes = profile.max_nodes;
    spec.seed = a.seed;
    try {
      groups.push_back(resolve_trial_group(spec));
    } catch (const std::invalid_argument& e) {  // OptionError
      throw UsageError(fmt::format("table '{}' row '{}': {}", table->id, row.label, e.what()));
    } catch (const UsageError& e) {
      throw UsageError(fmt::format("table '{}' row '{}': {}", table->id, row.label, e.what()));
    }
  }

  std::vector<const TrialGroup*> ordered;
  for (const TrialGroup& g : groups) ordered.push_back(&g);
  if (a.plan) return print_plan(fmt::format("table {} --profile {}", table->id, a.profile), ordered, shard_option(a.shard), a.db);
  TrialStore store = TrialStore::open(a.db);
  const TableTrials run_info = run_table_trials(ordered, store, a, profile.trials);
  const EngineOptions& eo = run_info.engine;

  std::vector<std::vector<TrialRecord>> rows_trials(groups.size());
  for (auto& record : store.load(experiment))
    for (std::size_t r = 0; r < groups.size(); ++r)
      if (groups[r].contains(record)) rows_trials[r].push_back(record);

  PaperReport report = make_paper_report(*table, rows_trials);
  if (report.suite.empty()) report.suite = suite->name;
  const ReportHeader header = make_header(a, profile, eo, experiment);

  const std::string markdown = to_markdown(report, header);
  const fs::path out_dir(a.out_dir);
  write_file_atomic((out_dir / (table->id + ".md")).string(), markdown);
  write_file_atomic((out_dir / (table->id + ".csv")).string(), to_csv(report, header));
  for (const std::string& name : table->series) {  // per-trial series, e.g. Fig. 6's sorted n_j
    std::string csv = "row,trial_index,x,y\r\n";
    for (std::size_t r = 0; r < groups.size(); ++r)
      for (const TrialRecord& record : rows_trials[r])
        for (const auto& [x, y] : store.series_of(record.key, name))
          csv += fmt::format("{},{},{},{}\r\n", text::csv_field(table->rows[r].label), record.key.trial_index,
                             text::csv_number(x), text::csv_number(y));
    std::string file = name;  // a series name may hold '/', e.g. "coverage/tree0"
    std::replace(file.begin(), file.end(), '/', '-');
    write_file_atomic((out_dir / (table->id + "-" + file + ".csv")).string(), csv);
  }
  std::cout << markdown << std::flush;
  fmt::print(stderr, "[hyfal] {} trials ({} run now); wrote {} and {}; database {}\n", run_info.total,
             run_info.run_now, (out_dir / (table->id + ".md")).string(), (out_dir / (table->id + ".csv")).string(), a.db);
  print_shard_note(a);
  return run_info.errors ? 1 : 0;
}

}  // namespace hyfal::cli
