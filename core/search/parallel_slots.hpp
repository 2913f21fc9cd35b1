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
#include <exception>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/util/rng.hpp"
#include "core/util/trial_cpu_clock.hpp"

namespace hyfal {

// The seed of slot `slot` of round `round` of a trial whose seed is `trial_seed`.
constexpr std::uint64_t slot_seed(std::uint64_t trial_seed, std::uint64_t round, std::uint64_t slot) {
  std::uint64_t h = splitmix64(trial_seed ^ 0x736c6f7473656564ULL);  // "slotseed"
  h = splitmix64(h ^ round);
  return splitmix64(h ^ (slot * 0x9e3779b97f4a7c15ULL));
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

// Rounds of slots with a standing helper, for planners whose rounds are short (HyDICE on
// navigation: 8 propagations of ~15 µs, then a serial commit). parallel_slots forks and joins
// per round; when a round lasts ~100 µs the other thread has gone to sleep between rounds and
// is woken for each (a futex wake, tens of µs on a virtual machine), and the caller sleeps in
// the join the same way, so a second thread gained a batch-8 HyDICE trial 1.41x (cpu 9.98 s,
// wall 6.52 s, 2026-12-04). Here a helper task stays for the whole growth phase instead: it
// spins between rounds (with a pause; it yields every kYieldEvery spins) and claims slots of
// each round as soon as the coordinator publishes it; the coordinator claims slots too, so no
// slot ever waits for the helper, and with one thread (or while the helper's thread is busy
// elsewhere, e.g. with HyDICE's next lead search) the coordinator runs every slot itself.
// Which thread runs a slot never changes what it computes: the results are those of
// parallel_slots. cpu_s counts the helper's slot bodies, not its spinning.
//
// Protocol: one atomic ticket = round (32 bits) | count (16) | next slot (16). The coordinator
// writes the round's body, resets `done_`, then publishes the ticket (release); a slot is
// claimed by a compare-and-swap on the ticket (a stale round fails it), marked in `finished_`
// and counted in `done_` (release) when it has run; the coordinator commits slot i once it
// sees finished_[i] (acquire) and returns from run() when done_ = count (acquire), so the next
// round's writes happen after every read of this one.
class SlotRounds {
 public:
  static constexpr std::size_t kMaxSlots = 0xffff;

  explicit SlotRounds(TrialCpuClock* cpu) : cpu_(cpu), coordinator_(std::this_thread::get_id()) {}
  SlotRounds(const SlotRounds&) = delete;
  SlotRounds& operator=(const SlotRounds&) = delete;

  // Runs body(i) for every i in [0, count) (count <= kMaxSlots) on the calling thread (the
  // coordinator) and, when it is standing by, the helper; returns when all have run. An
  // exception of a body is rethrown here once every slot of the round has finished.
  template <class Body>
  void run(std::size_t count, Body& body) {
    run(count, body, [](std::size_t) { return false; });
  }
  // The same, and commit(i) for i = 0, 1, ... in order, on the calling thread, as soon as slot i
  // has run, while later slots may still be running (so the coordinator commits instead of
  // waiting for the helper's last slot); once commit returns true (the search ended), no
  // further slot is committed. Slots that threw are not committed, nor any after them.
  // The bodies must not read what commit writes.
  template <class Body, class Commit>
  void run(std::size_t count, Body& body, Commit&& commit) {
    if (count == 0) return;
    if (count > kMaxSlots) throw std::invalid_argument("SlotRounds::run: more than 65535 slots in a round");
    if (count > capacity_) {
      finished_ = std::make_unique<std::atomic<std::uint64_t>[]>(count);
      capacity_ = count;
    }
    run_ = [](void* b, std::size_t i) { (*static_cast<Body*>(b))(i); };
    body_ = &body;
    done_.store(0, std::memory_order_relaxed);
    ++round_;
    ticket_.store(pack(static_cast<std::uint32_t>(round_), static_cast<std::uint32_t>(count), 0),
                  std::memory_order_release);
    std::size_t next = 0;  // the next slot to commit
    bool committing = true;
    std::exception_ptr commit_error;
    for (unsigned spins = 0; done_.load(std::memory_order_acquire) < count || (committing && next < count);) {
      if (committing && next < count) {
        const std::uint64_t f = finished_[next].load(std::memory_order_acquire);
        if (f >> 1 == round_) {
          if (f & 1) {
            committing = false;  // slot `next` threw
          } else {
            try {
              committing = !commit(next);
            } catch (...) {
              commit_error = std::current_exception();
              committing = false;
            }
            ++next;
          }
          continue;
        }
      }
      if (claim_and_run(static_cast<std::uint32_t>(round_), 0)) continue;
      pause(spins++);
    }
    for (std::exception_ptr& e : error_)
      if (e) std::rethrow_exception(std::exchange(e, nullptr));
    if (commit_error) std::rethrow_exception(commit_error);
  }

  // The helper's loop: claims the slots of each round until close(). Returns at once on the
  // coordinator's thread (it must never wait there for rounds that only it can publish).
  void help() {
    if (std::this_thread::get_id() == coordinator_) return;
    std::uint32_t last = 0;
    for (unsigned spins = 0; !closed_.load(std::memory_order_acquire);) {
      const std::uint64_t t = ticket_.load(std::memory_order_acquire);
      if (round_of(t) != last && next_of(t) < count_of(t)) {
        last = round_of(t);
        if (cpu_)
          cpu_->task([&] { work(last, 1); });
        else
          work(last, 1);
        spins = 0;
        continue;
      }
      pause(spins++);
    }
  }
  void close() { closed_.store(true, std::memory_order_release); }

 private:
  static constexpr unsigned kYieldEvery = 4096;
  static std::uint64_t pack(std::uint32_t round, std::uint32_t count, std::uint32_t next) {
    return (static_cast<std::uint64_t>(round) << 32) | (static_cast<std::uint64_t>(count) << 16) | next;
  }
  static std::uint32_t round_of(std::uint64_t t) { return static_cast<std::uint32_t>(t >> 32); }
  static std::uint32_t count_of(std::uint64_t t) { return static_cast<std::uint32_t>(t >> 16) & 0xffff; }
  static std::uint32_t next_of(std::uint64_t t) { return static_cast<std::uint32_t>(t) & 0xffff; }
  static void pause(unsigned spins) {
    if (spins % kYieldEvery == kYieldEvery - 1) {
      std::this_thread::yield();
      return;
    }
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
  }
  // Claims and runs one slot of `round`; false when none is left. `who`: 0 coordinator, 1 helper.
  bool claim_and_run(std::uint32_t round, int who) {
    std::uint64_t t = ticket_.load(std::memory_order_acquire);
    while (round_of(t) == round && next_of(t) < count_of(t)) {
      if (!ticket_.compare_exchange_weak(t, t + 1, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
      const std::uint32_t i = next_of(t);
      bool failed = false;
      try {
        run_(body_, i);
      } catch (...) {
        if (!error_[who]) error_[who] = std::current_exception();
        failed = true;
      }
      // round_ (64 bits: it never wraps) is the claimed round's: the coordinator wrote it before
      // the ticket and changes it only after done_ counts this slot.
      finished_[i].store((round_ << 1) | (failed ? 1 : 0), std::memory_order_release);
      done_.fetch_add(1, std::memory_order_release);
      return true;
    }
    return false;
  }
  void work(std::uint32_t round, int who) {
    while (claim_and_run(round, who)) {
    }
  }
  TrialCpuClock* cpu_;
  std::thread::id coordinator_;
  void (*run_)(void*, std::size_t) = nullptr;
  void* body_ = nullptr;
  std::uint64_t round_ = 0;  // written by the coordinator before each ticket, read by the helper after it
  std::atomic<std::uint64_t> ticket_{0};
  std::unique_ptr<std::atomic<std::uint64_t>[]> finished_;  // per slot: (round << 1) | threw
  std::size_t capacity_ = 0;
  std::atomic<std::size_t> done_{0};
  std::atomic<bool> closed_{false};
  std::exception_ptr error_[2];
};

// Runs coordinate(rounds) on the calling thread with a helper standing by on another thread of
// the arena (when the arena has one and it is free), for the rounds that coordinate runs
// through rounds.run(). With one thread, coordinate runs alone and run() does every slot.
template <class Coordinate>
void with_slot_rounds(TrialCpuClock* cpu, Coordinate&& coordinate) {
  SlotRounds rounds(cpu);
  if (tbb::this_task_arena::max_concurrency() <= 1) {
    coordinate(rounds);
    return;
  }
  struct Close {
    SlotRounds& r;
    ~Close() { r.close(); }
  };
  parallel_slots(2, nullptr, [&](std::size_t lane) {
    if (lane == 0) {
      Close close{rounds};
      if (cpu)
        cpu->task([&] { coordinate(rounds); });
      else
        coordinate(rounds);
    } else {
      rounds.help();
    }
  });
}

}  // namespace hyfal
