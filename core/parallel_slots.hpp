// Intra-trial parallelism, deterministic (issue 12; the select / propagate / commit phases of
// Kino-PAX, Perrault et al. 2025, on a CPU):
//  - a planner with the method option `batch` = B > 1 grows its search in rounds of B expansion
//    slots; slot s of round r draws its random numbers from its own stream, seeded by
//    slot_seed(trial seed, r, s): never from the thread that runs it;
//  - the slots of a round read the search as it was at the start of the round (frozen) and
//    write only their own scratch, so they can run in any order on any number of threads
//    (parallel_slots);
//  - the coordinator then commits the slots' results in slot order.
// Results therefore depend on B but not on the number of threads. B = 1 is each planner's
// sequential algorithm, with the trial's single stream (the committed paper tables use it).
//
// parallel_slots runs on the calling thread's oneTBB arena: inside the trial engine that is the
// run's arena, so threads with no trial of their own steal the slots of running trials (nested
// parallelism with work stealing, one arena for trials and their workers).
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/planner.hpp"
#include "core/rng.hpp"
#include "core/trial_cpu.hpp"

namespace hyfal {

// The seed of slot `slot` of round `round` of a trial whose seed is `trial_seed`.
constexpr std::uint64_t slot_seed(std::uint64_t trial_seed, std::uint64_t round, std::uint64_t slot) {
  std::uint64_t h = splitmix64(trial_seed ^ 0x736c6f7473656564ULL);  // "slotseed"
  h = splitmix64(h ^ round);
  return splitmix64(h ^ (slot * 0x9e3779b97f4a7c15ULL));
}

// The method option every planner declares.
inline OptionSpec batch_option() {
  return {"batch", 1,
          "B: expansion slots per round, selected against the frozen search, propagated in parallel, committed in slot "
          "order (results depend on B, never on --threads; 1 = the sequential algorithm)",
          "[1, 4096]"};
}

// Runs body(i) for every i in [0, count) on the calling thread's arena, in parallel where threads
// are free, and returns when all have run. Isolated: while it waits, the calling thread runs only
// these bodies (not another trial's work, whose CPU would be counted here). Each body runs
// through `cpu` (when set) so that cpu_s counts the helping threads. The release store before and
// the acq_rel count after are happens-before edges ThreadSanitizer sees (Debian's libtbb is not
// instrumented, so its own fork and join are invisible to it).
// `grain`: bodies per task (1 for slots that each propagate; more for microsecond bodies).
template <class Body>
void parallel_slots(std::size_t count, TrialCpuClock* cpu, Body&& body, std::size_t grain = 1) {
  if (count == 0) return;
  if (count == 1) {
    body(std::size_t{0});
    return;
  }
  std::atomic<std::size_t> started{0}, finished{0};
  started.store(1, std::memory_order_release);
  auto run = [&](std::size_t i) {
    (void)started.load(std::memory_order_acquire);
    if (cpu)
      cpu->task([&] { body(i); });
    else
      body(i);
    finished.fetch_add(1, std::memory_order_acq_rel);
  };
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, count, grain < 1 ? 1 : grain),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) run(i);
        },
        tbb::simple_partitioner());
  });
  (void)finished.load(std::memory_order_acquire);
}

}  // namespace hyfal
