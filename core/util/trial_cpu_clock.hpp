// The CPU time of one trial over every thread that worked for it.
//
// A trial runs on one thread (its owner), but a planner may hand work to oneTBB tasks that
// other threads of the arena execute (RRFT grows its trees as tasks). CLOCK_THREAD_CPUTIME_ID on
// the owner alone misses their share. So: the owner's own thread-CPU delta over the trial, plus
// the thread-CPU of every task body that ran on another thread (task(), below). A planner must
// run its parallel region inside tbb::this_task_arena::isolate, so that the owner, while it
// waits for its tasks, never picks up another trial's tasks (that CPU would be counted here as
// this trial's, and the other trial's would go missing). Tasks of one trial executed by the
// owner are already in the owner's delta and are not added twice.
#pragma once
#include <time.h>

#include <atomic>
#include <cstdint>
#include <thread>

namespace hyfal {

class TrialCpuClock {
 public:
  // Starts the clock; the constructing thread is the trial's owner.
  TrialCpuClock() : owner_(std::this_thread::get_id()), owner_start_ns_(thread_cpu_ns()) {}
  TrialCpuClock(const TrialCpuClock&) = delete;
  TrialCpuClock& operator=(const TrialCpuClock&) = delete;

  // Runs a task body of this trial on the calling thread and counts its CPU when the calling
  // thread is not the owner.
  template <class Body>
  void task(Body&& body) {
    if (std::this_thread::get_id() == owner_) {
      body();
      return;
    }
    const std::int64_t t0 = thread_cpu_ns();
    struct Add {  // counted even when the body throws
      TrialCpuClock& clock;
      std::int64_t t0;
      ~Add() { clock.helpers_ns_.fetch_add(thread_cpu_ns() - t0, std::memory_order_relaxed); }
    } add{*this, t0};
    body();
  }

  // CPU seconds so far: the owner's own since the start plus the helpers'. Call on the owner
  // after the trial's parallel regions have joined.
  double seconds() const {
    return 1e-9 * static_cast<double>(thread_cpu_ns() - owner_start_ns_ + helpers_ns_.load(std::memory_order_relaxed));
  }
  // The helpers' part alone (tests, diagnostics).
  double helper_seconds() const { return 1e-9 * static_cast<double>(helpers_ns_.load(std::memory_order_relaxed)); }

  static std::int64_t thread_cpu_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  }

 private:
  std::thread::id owner_;
  std::int64_t owner_start_ns_;
  std::atomic<std::int64_t> helpers_ns_{0};
};

}  // namespace hyfal
