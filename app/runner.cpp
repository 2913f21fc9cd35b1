#include "app/runner.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "app/plan.hpp"
#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "parallel/cluster.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

#ifndef HYFAL_SOURCE_DIR
#define HYFAL_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace hyfal {

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
  g.instance = canonical_instance(suite->parameters, resolve_options(suite->parameters, instance_sets));
  g.options = resolve_options(method->options, method_sets);
  try {
    g.system = suite->make(g.instance);
  } catch (const InputError&) {
    throw;  // hyfal's own (a RequirementError...) keeps its class
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());  // a suite's own refusal
  }
  // The method's own checks (relations between options, what it needs of the system) run here,
  // once, so that a bad combination is reported before the database is opened, not per trial.
  try {
    check_method_for_system(*method, *g.system);
  } catch (const std::invalid_argument& e) {
    throw MethodNotApplicable(fmt::format("method '{}' on suite '{}': {}", method->name, suite->name, e.what()));
  }
  try {
    if (method->check_system) method->check_system(*g.system, g.options);
    (void)method->make(g.options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("method '{}' on suite '{}': {}", method->name, suite->name, e.what()));
  }
  g.config = {{"master_seed", spec.seed}, {"max_nodes", spec.max_nodes}, {"timeout_s", spec.timeout_s},
              {"options", canonical_instance(method->options, g.options)}};  // an option at its unkeyed value left out
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

std::string one_line(std::string_view text) {
  std::string out;
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  return out;
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

std::optional<GroupsRun> run_groups(const std::string& what, const std::vector<const TrialGroup*>& groups,
                                    const RunOptions& o) {
  if (o.plan) {
    (void)print_plan(what, groups, o.shard, o.db);
    return std::nullopt;
  }
  if (o.save_trees && Cluster::current() && Cluster::current()->size() > 1)
    throw UsageError("--save-trees: not under mpirun (the workers' results do not carry trees); run without mpirun");
  GroupsRun run{TrialStore::open(o.db), make_engine_options(o.threads, o.witness_dir, o.progress), 0, 0, 0, 0, {}};
  run.engine.save_trees = o.save_trees;
  std::vector<TrialJob> jobs;
  std::int64_t position = 0;  // of the group's trial 0 in the full job list
  for (const TrialGroup* g : distinct_groups(groups)) {
    auto group_jobs = prepare_jobs(*g, run.store.stored_trial_indices(g->base), o.shard, position);
    const auto in_shard = static_cast<std::size_t>(o.shard.count_in(position, g->spec.trials));
    run.total += in_shard;
    run.stored_before += in_shard - group_jobs.size();
    position += g->spec.trials;
    for (auto& j : group_jobs) jobs.push_back(std::move(j));
  }
  if (!o.quiet && run.stored_before > 0)
    fmt::print(stderr, "[hyfal] resuming: {} of {} trials{} already stored in {}\n", run.stored_before, run.total,
               o.shard.whole() ? "" : " of shard " + o.shard.text(), o.db);
  const JobsRun jobs_run = run_jobs(jobs, run.store, run.engine);
  run.run_now = jobs_run.run_now;
  run.errors = jobs_run.errors;

  run.trials.resize(groups.size());
  std::map<std::string, std::vector<TrialRecord>> by_experiment;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const std::string& experiment = groups[i]->spec.experiment;
    auto it = by_experiment.find(experiment);
    if (it == by_experiment.end()) it = by_experiment.emplace(experiment, run.store.load(experiment)).first;
    for (const TrialRecord& record : it->second)
      if (groups[i]->contains(record)) run.trials[i].push_back(record);
  }
  return run;
}

}  // namespace hyfal
