#include "parallel/trial_engine.hpp"

#include "core/requirements/requirement.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <optional>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/util/files.hpp"
#include "core/util/rng.hpp"
#include "core/util/trial_cpu_clock.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {

namespace fs = std::filesystem;

int default_thread_count() { return std::max(1, tbb::info::default_concurrency()); }

std::string iso8601_now() {
  const auto now = std::chrono::system_clock::now();
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count();
  const std::time_t secs = static_cast<std::time_t>(ms / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1,
                     tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms % 1000));
}

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

std::string witness_path(const std::string& dir, const TrialKey& key) {
  const std::uint64_t h = splitmix64(fnv1a(key.config, fnv1a(key.instance)));
  return (fs::path(dir) / key.experiment / key.suite / key.method /
          fmt::format("{:016x}-t{}.json", h, key.trial_index))
      .string();
}

std::string tree_path(const std::string& witness_path) {
  fs::path p(witness_path);
  p.replace_extension(".tree.csv");
  return p.string();
}

namespace {

// Per node of one tree, how many nodes its subtree holds (itself included): parents come before
// their children, so one pass from the last node adds each subtree into its parent's.
std::vector<std::uint64_t> subtree_sizes(const RecordedTree& t) {
  std::vector<std::uint64_t> size(t.parent.size(), 1);
  for (std::size_t i = t.parent.size(); i-- > 0;)
    if (t.parent[i] >= 0) size[static_cast<std::size_t>(t.parent[i])] += size[i];
  return size;
}

// A state name as a CSV header cell (no separators, quotes or line breaks).
std::string header_cell(std::string name) {
  for (char& ch : name)
    if (ch == ',' || ch == '"' || ch == '\n' || ch == '\r') ch = '_';
  return name;
}

}  // namespace

std::string tree_file_text(const TreeRecorder& recorder, const SystemInfo& info, std::size_t max_edges,
                           std::size_t max_values) {
  std::vector<const RecordedTree*> trees;
  for (const RecordedTree& t : recorder.trees()) trees.push_back(&t);
  std::stable_sort(trees.begin(), trees.end(), [](const auto* a, const auto* b) { return a->index < b->index; });
  const std::size_t dim = recorder.dim();
  std::size_t nodes = 0, roots = 0;
  for (const RecordedTree* t : trees) {
    nodes += t->parent.size();
    roots += static_cast<std::size_t>(std::count(t->parent.begin(), t->parent.end(), std::int64_t{-1}));
  }
  // Within the limits every node is kept. Beyond them, the nodes whose subtree holds at least s
  // nodes, for the smallest s within both: the trunk and the branches of each tree without their
  // last twigs, so the picture keeps the tree's shape and reach (a node kept keeps its parent,
  // whose subtree is larger). Roots are always kept.
  std::vector<std::vector<std::uint64_t>> sizes;
  std::vector<std::uint64_t> non_root_sizes;
  for (const RecordedTree* t : trees) {
    sizes.push_back(subtree_sizes(*t));
    for (std::size_t i = 0; i < t->parent.size(); ++i)
      if (t->parent[i] >= 0) non_root_sizes.push_back(sizes.back()[i]);
  }
  const std::size_t value_room = dim == 0 ? nodes : max_values / dim;  // nodes the values allow
  const std::size_t edge_room = std::min(max_edges, value_room > roots ? value_room - roots : 0);
  std::uint64_t s = 1;
  if (non_root_sizes.size() > edge_room) {
    // The (edge_room + 1)-th largest size plus one: at most edge_room nodes have a size >= s.
    std::nth_element(non_root_sizes.begin(), non_root_sizes.begin() + static_cast<std::ptrdiff_t>(edge_room),
                     non_root_sizes.end(), std::greater<>());
    s = non_root_sizes[edge_room] + 1;
  }
  std::size_t kept = 0;
  for (std::size_t ti = 0; ti < trees.size(); ++ti)
    for (std::size_t i = 0; i < trees[ti]->parent.size(); ++i) kept += trees[ti]->parent[i] < 0 || sizes[ti][i] >= s;

  std::string text = "# hyfal-tree/1: the search tree(s) of the trial whose witness is beside this file (hyfal run --save-trees)\n";
  text += "# one row per node: tree (its index in the method's forest), node (its row in the tree), parent (the parent's "
          "node; -1 at a root; a parent comes before its children), mode, state\n";
  if (s == 1)
    text += fmt::format("# nodes: {} in {} tree(s), every node\n", nodes, trees.size());
  else
    text += fmt::format(
        "# nodes: {} of {} in {} tree(s), subsampled: the roots and the nodes whose subtree holds at least {} nodes "
        "(the trunk and branches without their last twigs; at most {} edges and {} state values)\n",
        kept, nodes, trees.size(), s, max_edges, max_values);
  text += "tree,node,parent,mode";
  for (std::size_t d = 0; d < dim; ++d) {
    text += ',';
    text += header_cell(d < info.state_names.size() && !info.state_names[d].empty() ? info.state_names[d]
                                                                                  : fmt::format("x{}", d));
  }
  text += "\n";
  std::vector<std::int64_t> row_of;
  for (std::size_t ti = 0; ti < trees.size(); ++ti) {
    const RecordedTree& t = *trees[ti];
    row_of.assign(t.parent.size(), -1);
    std::int64_t rows = 0;
    for (std::size_t i = 0; i < t.parent.size(); ++i) {
      if (t.parent[i] >= 0 && sizes[ti][i] < s) continue;
      row_of[i] = rows;
      const std::int64_t parent = t.parent[i] < 0 ? -1 : row_of[static_cast<std::size_t>(t.parent[i])];
      fmt::format_to(std::back_inserter(text), "{},{},{},{}", t.index, rows, parent, t.mode[i]);
      for (std::size_t d = 0; d < dim; ++d) fmt::format_to(std::back_inserter(text), ",{:.9g}", t.states[i * dim + d]);
      text += '\n';
      ++rows;
    }
  }
  return text;
}

TrialResult compute_trial(const TrialJob& job, const EngineOptions& options) {
  TrialResult result;
  TrialRecord& rec = result.record;
  rec.key = job.key;
  rec.seed = job.seed;
  rec.host = options.host;
  rec.git_commit = options.git_commit;
  rec.started_at = iso8601_now();
  const auto wall0 = std::chrono::steady_clock::now();
  TrialCpuClock cpu;  // this thread's CPU plus that of the planner's tasks on other threads
  try {
    check_method_for_system(*job.method, *job.system);  // the CLI refuses such a pair before a run
    auto planner = job.method->make(job.method_options);
    const SystemInfo& info = job.system->info();
    std::optional<TreeRecorder> trees;
    if (options.save_trees) trees.emplace(info.dim());
    const PlannerContext ctx{*job.system, info.parameters, static_cast<std::uint64_t>(job.seed),
                             job.limits, options.cancel, &cpu, trees ? &*trees : nullptr};
    PlannerOutcome out = planner->solve(ctx);
    rec.nodes = out.counters.nodes;
    rec.propagations = out.counters.propagations;
    rec.integration_steps = out.counters.integration_steps;
    if (const SystemInfo& i = job.system->info(); i.requirement) {
      // Simulation-equivalents: the simulated time over the requirement's horizon (how many
      // whole simulations the search's propagations add up to; unbounded requirements: none).
      const double horizon = i.requirement->formula.horizon();
      if (std::isfinite(horizon) && horizon > 0.0) out.metrics["simulations"] = out.counters.simulated_time / horizon;
    }
    rec.status = out.status;
    for (auto& s : out.series) rec.series.emplace_back(std::move(s.name), std::move(s.points));
    if (out.status == TrialStatus::falsified) {
      if (!out.trajectory) throw std::logic_error("the planner reported falsified without a trajectory");
      Witness w = make_witness(*job.system, job.key.method, job.seed, std::move(*out.trajectory));
      const ValidationReport report = validate_witness(*job.system, w);
      rec.validated = report.valid;
      if (report.robustness) {  // STL: the witness's robustness is the validator's, from its own trace
        w.requirement->robustness = *report.robustness;
        out.metrics["robustness"] = *report.robustness;
      }
      result.witness_text = to_json(w).dump(1) + "\n";
      if (!report.valid) {  // a trial counts as falsified only if its witness validates
        rec.status = TrialStatus::error;
        rec.error = "witness failed validation: " + report.reason;
      }
      if (trees) result.tree_text = tree_file_text(*trees, info);
    }
    rec.metrics = out.metrics.dump();
  } catch (const std::exception& e) {
    rec.status = TrialStatus::error;
    rec.validated = false;  // no witness vouches for it
    result.witness_text.clear();
    result.tree_text.clear();
    rec.error = e.what();
  } catch (...) {
    rec.validated = false;
    result.witness_text.clear();
    result.tree_text.clear();
    rec.status = TrialStatus::error;
    rec.error = "unknown exception";
  }
  rec.cpu_s = cpu.seconds();
  rec.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  rec.finished_at = iso8601_now();
  return result;
}

void keep_witness(TrialResult& result, const std::string& witness_dir) {
  if (result.witness_text.empty() || witness_dir.empty()) return;
  const std::string path = witness_path(witness_dir, result.record.key);
  if (!result.tree_text.empty()) write_file_atomic(tree_path(path), result.tree_text, "witness");  // never a witness without it
  write_file_atomic(path, result.witness_text, "witness");
  result.record.witness = path;
}

TrialRecord run_trial(const TrialJob& job, const EngineOptions& options) {
  TrialResult result = compute_trial(job, options);
  keep_witness(result, options.witness_dir);
  return std::move(result.record);
}

void run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
                const TrialClaim& claim) {
  const int threads = options.threads > 0 ? options.threads : default_thread_count();
  // The engine's own stop source: a failure stops the trials in flight through it, and so does
  // the caller's cancel token (forwarded).
  std::stop_source stop;
  std::optional<std::stop_callback<std::function<void()>>> forward_cancel;
  if (options.cancel.stop_possible())
    forward_cancel.emplace(options.cancel, std::function<void()>([&stop] { stop.request_stop(); }));
  EngineOptions trial_options = options;
  trial_options.cancel = stop.get_token();

  std::mutex sink_mutex;  // serializes the sink, the claims and the fields below
  std::exception_ptr failure;
  std::size_t done = 0, skipped = 0, falsified = 0;
  const auto fail = [&](std::exception_ptr error) {  // under sink_mutex
    if (!failure) failure = std::move(error);
    stop.request_stop();
  };
  const auto t0 = std::chrono::steady_clock::now();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, jobs.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            {
              std::lock_guard lock(sink_mutex);
              if (failure) return;  // no new trial after a failure
              try {
                if (claim && !claim(jobs[i])) {
                  ++skipped;
                  continue;
                }
              } catch (...) {
                fail(std::current_exception());
                return;
              }
            }
            std::optional<TrialRecord> rec;
            std::exception_ptr error;
            try {
              rec = run_trial(jobs[i], trial_options);
            } catch (...) {
              error = std::current_exception();
            }
            std::lock_guard lock(sink_mutex);
            if (error) fail(std::move(error));
            if (failure) return;  // stopped by a failure: its result is not kept, it reruns on resume
            rec->threads = threads;
            try {
              sink(*rec);
            } catch (...) {
              fail(std::current_exception());
              return;
            }
            ++done;
            falsified += rec->status == TrialStatus::falsified;
            if (options.progress) {
              const std::size_t total = jobs.size() - skipped;
              const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
              const double eta = el / static_cast<double>(done) * static_cast<double>(total - done);
              fmt::print(stderr, "\r[hyfal] {}/{} trials, {} falsified, {:.1f} s elapsed, ETA {:.1f} s   ",
                         done, total, falsified, el, eta);
            }
          }
        },
        tbb::simple_partitioner());
  });
  // Acquire the lock the last sink call released: an explicit happens-before edge from every
  // sink call to the caller, visible to ThreadSanitizer (TBB's own joins are not instrumented).
  std::lock_guard lock(sink_mutex);
  if (options.progress && done > 0) fmt::print(stderr, "\n");
  if (failure) std::rethrow_exception(failure);
}

}  // namespace hyfal
