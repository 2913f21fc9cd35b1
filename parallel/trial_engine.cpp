#include "parallel/trial_engine.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <optional>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <mutex>

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/rng.hpp"
#include "core/trial_cpu.hpp"

namespace hyfal {

namespace fs = std::filesystem;

namespace {

// Writes `text` to `path` atomically (temporary file, then rename): a reader never sees half.
// Any failure removes the temporary file and throws EnvironmentError with the cause.
void write_file_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  const auto fail = [&](const std::string& what, int error) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw EnvironmentError(fmt::format("cannot write witness '{}': {}: {}", path.string(), what, std::strerror(error)));
  };
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) fail(fmt::format("cannot create '{}'", path.parent_path().string()), ec.value());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create it", errno);
  for (std::size_t written = 0; written < text.size();) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      ::close(fd);
      fail("write failed", error);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail("write failed", errno);  // e.g. ENOSPC reported at close (NFS)
  fs::rename(tmp, path, ec);
  if (ec) fail("cannot rename the temporary file", ec.value());
}

}  // namespace

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
    auto planner = job.method->make(job.method_options);
    const SystemInfo& info = job.system->info();
    const PlannerContext ctx{*job.system, info.parameters, static_cast<std::uint64_t>(job.seed),
                             job.limits, options.cancel, &cpu};
    PlannerOutcome out = planner->solve(ctx);
    rec.nodes = out.counters.nodes;
    rec.propagations = out.counters.propagations;
    rec.integration_steps = out.counters.integration_steps;
    rec.status = out.status;
    rec.metrics = out.metrics.dump();
    for (auto& s : out.series) rec.series.emplace_back(std::move(s.name), std::move(s.points));
    if (out.status == TrialStatus::falsified) {
      if (!out.trajectory) throw std::logic_error("the planner reported falsified without a trajectory");
      const Witness w = make_witness(*job.system, job.key.method, job.seed, std::move(*out.trajectory));
      const ValidationReport report = validate_witness(*job.system, w);
      rec.validated = report.valid;
      result.witness_text = to_json(w).dump(1) + "\n";
      if (!report.valid) {  // a trial counts as falsified only if its witness validates
        rec.status = TrialStatus::error;
        rec.error = "witness failed validation: " + report.reason;
      }
    }
  } catch (const std::exception& e) {
    rec.status = TrialStatus::error;
    rec.validated = false;  // no witness vouches for it
    result.witness_text.clear();
    rec.error = e.what();
  } catch (...) {
    rec.validated = false;
    result.witness_text.clear();
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
  write_file_atomically(path, result.witness_text);
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
