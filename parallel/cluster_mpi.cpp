// The MPI implementation of Cluster (parallel/cluster.hpp), built when CMake finds MPI.
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>

#include "parallel/cluster.hpp"

namespace hyfal {

namespace {

using Clock = std::chrono::steady_clock;

// Message tags. A job and a result carry the coordinator's dispatch id in their first 8 bytes.
enum Tag : int {
  kHello = 1,   // worker -> 0: protocol, build, host, pid
  kWelcome,     // 0 -> worker: threads per rank
  kRefuse,      // 0 -> worker: the run cannot use it (another build)
  kJob,         // 0 -> worker: id + encode_job
  kResult,      // worker -> 0: id + encode_result
  kFatal,       // worker -> 0: this rank cannot run trials (message)
  kCancel,      // 0 -> worker: stop and drop the trials in flight
  kStop,        // 0 -> worker: the command is over
  kHeartbeat,   // both ways, every second, handled by the link thread
  kLost = -1,   // not sent: the link reports a peer silent for the peer timeout
  kLocal = -2,  // not sent: a result of rank 0's own executor
};
constexpr int kProtocol = 1;

std::string with_id(std::uint64_t id, const std::string& payload) {
  std::string out(8, '\0');
  std::memcpy(out.data(), &id, 8);
  return out + payload;
}
std::pair<std::uint64_t, std::string> split_id(const std::string& bytes) {
  if (bytes.size() < 8) throw std::invalid_argument("malformed message: no dispatch id");
  std::uint64_t id = 0;
  std::memcpy(&id, bytes.data(), 8);
  return {id, bytes.substr(8)};
}
std::string cbor(const Json& j) {
  const std::vector<std::uint8_t> b = Json::to_cbor(j);
  return {b.begin(), b.end()};
}
Json uncbor(const std::string& bytes) {
  Json j = Json::from_cbor(bytes, true, false);
  if (j.is_discarded() || !j.is_object()) throw std::invalid_argument("malformed control message");
  return j;
}

// What a process receives: a message from a peer, a lost peer, or a local result.
struct Event {
  int peer = 0;
  int tag = 0;
  std::string bytes;
  std::uint64_t id = 0;
  std::optional<TrialResult> local;
};

class EventQueue {
 public:
  void push(Event e) {
    {
      std::lock_guard lock(mutex_);
      events_.push_back(std::move(e));
    }
    cv_.notify_one();
  }
  std::optional<Event> pop(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    if (!cv_.wait_for(lock, timeout, [&] { return !events_.empty(); })) return std::nullopt;
    Event e = std::move(events_.front());
    events_.pop_front();
    return e;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Event> events_;
};

// The one thread of a process that calls MPI: it initializes and finalizes MPI, sends what the
// other threads queue (non-blocking sends, so two ranks sending large messages to each other
// cannot deadlock), receives into the event queue, and exchanges heartbeats.
class MpiLink {
 public:
  MpiLink(int* argc, char*** argv, EventQueue& events) : events_(events) {
    thread_ = std::thread([this, argc, argv] { loop(argc, argv); });
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return ready_; });
    if (!init_error_.empty()) {
      lock.unlock();
      thread_.join();
      throw ClusterFailure(init_error_);
    }
  }
  MpiLink(const MpiLink&) = delete;
  MpiLink& operator=(const MpiLink&) = delete;
  ~MpiLink() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Ends without MPI_Finalize: once a rank is gone, OpenMPI's finalize may wait for it for ever
  // (seen with --enable-recovery), so the surviving ranks leave without it.
  void skip_finalize() { skip_finalize_ = true; }

  void send(int peer, int tag, std::string bytes) {
    {
      std::lock_guard lock(mutex_);
      outbox_.push_back({peer, tag, std::move(bytes)});
    }
    cv_.notify_all();
  }

 private:
  struct Outgoing {
    int peer, tag;
    std::string bytes;
  };
  struct InFlight {
    MPI_Request request;
    std::unique_ptr<std::string> bytes;  // stays put until the send completes
    int peer;
  };
  struct Incoming {
    MPI_Request request;
    std::unique_ptr<std::string> bytes;  // stays put until the receive completes
    int tag;
  };

  // The link thread: start MPI, then pass after pass send, receive, deliver, beat and watch the
  // peers until a stop has been flushed; then leave MPI.
  void loop(int* argc, char*** argv) {
    if (!start_mpi(argc, argv)) return;
    for (;;) {
      bool stopping = false;
      bool busy = send_queued(stopping);
      reap_sends();
      busy = receive() || busy;
      busy = deliver() || busy;
      const auto now = Clock::now();
      beat(now);
      watch_peers(now);
      if (stopping && flushed(now)) break;
      if (!busy) idle(stopping);
    }
    leave_mpi();
  }

  bool start_mpi(int* argc, char*** argv) {
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
      std::lock_guard lock(mutex_);
      init_error_ = "MPI_Init_thread failed: this rank cannot join the MPI job";
      ready_ = true;
      cv_.notify_all();
      return false;
    }
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    timeout_ = std::chrono::duration<double>(peer_timeout_seconds());
    const auto start = Clock::now();
    // Rank 0 watches every worker; a worker watches rank 0 only.
    if (rank_ == 0)
      for (int r = 1; r < size_; ++r) peers_.push_back(r);
    else
      peers_.push_back(0);
    for (int p : peers_) last_seen_[p] = start;
    next_beat_ = start;
    // A test makes one rank die right after it starts sending its first result, the moment at
    // which its peer has the message's header but not yet its bytes.
    const char* die = std::getenv("HYFAL_TEST_DIE_SENDING_RESULT");
    die_sending_result_ = die && *die && std::atoi(die) == rank_;
    {
      std::lock_guard lock(mutex_);
      ready_ = true;
    }
    cv_.notify_all();
    return true;
  }

  void isend(int peer, int tag, std::string bytes) {
    InFlight f{MPI_REQUEST_NULL, std::make_unique<std::string>(std::move(bytes)), peer};
    if (MPI_Isend(f.bytes->data(), static_cast<int>(f.bytes->size()), MPI_BYTE, peer, tag, MPI_COMM_WORLD,
                  &f.request) == MPI_SUCCESS)
      sending_.push_back(std::move(f));
    if (die_sending_result_ && tag == kResult) std::_Exit(9);
  }

  // Starts a send of everything the other threads queued (to live peers). True if there was any.
  bool send_queued(bool& stopping) {
    std::vector<Outgoing> out;
    {
      std::lock_guard lock(mutex_);
      out.swap(outbox_);
      stopping = stopping_;
    }
    for (auto& o : out)
      if (!dead_.count(o.peer)) isend(o.peer, o.tag, std::move(o.bytes));
    return !out.empty();
  }

  void reap_sends() {
    for (std::size_t i = 0; i < sending_.size();) {
      int done = 0;
      if (MPI_Test(&sending_[i].request, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS || done) {
        sending_[i] = std::move(sending_.back());
        sending_.pop_back();
      } else {
        ++i;
      }
    }
  }

  // Receives never block this thread: a message matched here is received with MPI_Imrecv and
  // tested on each pass. A blocking MPI_Recv of a message whose sender was killed after its
  // header arrived (shared memory moves larger messages by a single-copy get from the sender's
  // memory) could wait for ever, and this thread would stop sending heartbeats, so the other
  // ranks would take this one for lost too. True if a message was matched.
  bool receive() {
    bool any = false;
    for (;;) {
      int flag = 0;
      MPI_Message message = MPI_MESSAGE_NULL;
      MPI_Status status;
      if (MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &message, &status) != MPI_SUCCESS || !flag)
        return any;
      any = true;
      int count = 0;
      MPI_Get_count(&status, MPI_BYTE, &count);
      Incoming in{MPI_REQUEST_NULL, std::make_unique<std::string>(static_cast<std::size_t>(std::max(count, 0)), '\0'),
                  status.MPI_TAG};
      if (MPI_Imrecv(in.bytes->data(), count, MPI_BYTE, &message, &in.request) == MPI_SUCCESS)
        receiving_[status.MPI_SOURCE].push_back(std::move(in));
    }
  }

  // Completed receives go to the event queue per peer in the order they were sent (a JOB after
  // its WELCOME, a STOP last). True if any completed.
  bool deliver() {
    bool any = false;
    for (auto& [source, queue] : receiving_) {
      while (!queue.empty()) {
        int done = 0;
        const bool failed = MPI_Test(&queue.front().request, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS;
        if (!failed && !done) break;
        any = true;
        Incoming in = std::move(queue.front());
        queue.pop_front();
        if (failed || dead_.count(source) || !last_seen_.count(source)) continue;  // a lost peer stays lost
        last_seen_[source] = Clock::now();
        if (in.tag != kHeartbeat) events_.push(Event{source, in.tag, std::move(*in.bytes), 0, std::nullopt});
      }
    }
    return any;
  }

  void beat(Clock::time_point now) {
    if (now < next_beat_) return;
    for (int p : peers_)
      if (!dead_.count(p)) isend(p, kHeartbeat, {});
    next_beat_ = now + std::chrono::seconds(1);
  }

  // A peer silent for longer than the timeout is lost: the other threads hear of it once.
  void watch_peers(Clock::time_point now) {
    for (int p : peers_)
      if (!dead_.count(p) && now - last_seen_[p] > timeout_) {
        dead_.insert(p);
        events_.push(Event{p, kLost, {}, 0, std::nullopt});
        // Its receives in progress may never complete: their buffers stay allocated (MPI may
        // still write into them), and the process leaves without MPI_Finalize.
        auto& pending = receiving_[p];
        for (auto& in : pending) abandoned_.push_back(std::move(in));
        pending.clear();
      }
  }

  // Stopping: flush what is queued (a STOP, a last result), but never wait long for a peer that
  // is gone: a send to it may never complete. True when the loop may end.
  bool flushed(Clock::time_point now) {
    if (!stop_deadline_) stop_deadline_ = now + std::chrono::seconds(5);
    bool pending = false;
    for (const auto& f : sending_) pending = pending || !dead_.count(f.peer);
    std::lock_guard lock(mutex_);
    return outbox_.empty() && (!pending || now > *stop_deadline_);
  }

  void idle(bool stopping) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, std::chrono::milliseconds(1), [&] { return !outbox_.empty() || (stopping_ && !stopping); });
  }

  void leave_mpi() {
    for (auto& f : sending_) {
      int done = 0;
      MPI_Test(&f.request, &done, MPI_STATUS_IGNORE);
      if (!done) {
        MPI_Cancel(&f.request);
        MPI_Request_free(&f.request);
      }
    }
    // Receives still pending (of lost peers, or unfinished at the stop) keep their buffers: the
    // process is leaving and MPI could still write into them.
    for (auto& in : abandoned_) static_cast<void>(in.bytes.release());
    for (auto& [source, queue] : receiving_)
      for (auto& in : queue) static_cast<void>(in.bytes.release());
    if (!skip_finalize_) MPI_Finalize();
  }

  // The link thread's own state (only it touches these).
  std::chrono::duration<double> timeout_{0.0};
  std::vector<int> peers_;
  std::map<int, Clock::time_point> last_seen_;
  std::set<int> dead_;
  std::vector<InFlight> sending_;
  std::map<int, std::deque<Incoming>> receiving_;  // by source, in matching order
  std::vector<Incoming> abandoned_;                // of lost peers; never freed
  Clock::time_point next_beat_;
  std::optional<Clock::time_point> stop_deadline_;
  bool die_sending_result_ = false;

  EventQueue& events_;
  std::atomic<bool> skip_finalize_{false};
  std::mutex mutex_;
  std::condition_variable cv_;
  bool ready_ = false, stopping_ = false;
  std::string init_error_;
  std::vector<Outgoing> outbox_;
  int rank_ = 0, size_ = 1;
  std::thread thread_;
};

// Runs trials on its own oneTBB arena of `threads` threads, each trial one task, so that threads
// without a trial of their own help the running ones (parallel_slots steals on this arena).
// Results go to `done` on the thread that ran the trial, unless the executor was cancelled.
class TrialExecutor {
 public:
  using Done = std::function<void(std::uint64_t id, TrialResult&&)>;
  TrialExecutor(int threads, EngineOptions options, Done done)
      : threads_(threads > 0 ? threads : default_thread_count()),
        // Every arena thread is a worker (no slot kept for a master thread that never joins),
        // so the process needs threads_ workers plus the master TBB counts.
        control_(tbb::global_control::max_allowed_parallelism,
                 std::max<std::size_t>(threads_ + 1,
                                       tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism))),
        arena_(threads_, 0),
        options_(std::move(options)),
        done_(std::move(done)) {
    options_.cancel = stop_.get_token();
    options_.witness_dir.clear();  // rank 0 writes the witnesses
  }
  TrialExecutor(const TrialExecutor&) = delete;
  TrialExecutor& operator=(const TrialExecutor&) = delete;
  ~TrialExecutor() {
    cancel();
    wait();
  }

  int threads() const { return threads_; }

  void submit(std::uint64_t id, TrialJob job) {
    {
      std::lock_guard lock(mutex_);
      ++in_flight_;
    }
    arena_.enqueue([this, id, job = std::move(job)] {
      TrialResult r = compute_trial(job, options_);
      r.record.threads = threads_;
      if (!stop_.stop_requested()) done_(id, std::move(r));
      std::lock_guard lock(mutex_);  // notify under the lock: the executor may be destroyed right after
      --in_flight_;
      idle_.notify_all();
    });
  }
  // Asks the trials in flight to stop; their results are dropped.
  void cancel() { stop_.request_stop(); }
  void wait() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return in_flight_ == 0; });
  }

 private:
  int threads_;
  tbb::global_control control_;
  tbb::task_arena arena_;
  EngineOptions options_;
  Done done_;
  std::stop_source stop_;
  std::mutex mutex_;
  std::condition_variable idle_;
  int in_flight_ = 0;
};

std::string build_identity(const std::string& git_commit) {
  // A test can make one rank claim another build (the version check cannot be tested otherwise).
  if (const char* fake = std::getenv("HYFAL_TEST_BUILD_ID"); fake && *fake) return fake;
  return git_commit;
}

Cluster* g_current = nullptr;

class MpiCluster final : public Cluster {
 public:
  MpiCluster(int* argc, char*** argv) : link_(argc, argv, events_) { g_current = this; }
  ~MpiCluster() override {
    g_current = nullptr;
    if (link_.rank() == 0 && !finished_) finish(1);
  }

  int rank() const override { return link_.rank(); }
  int size() const override { return link_.size(); }

  int serve(const SystemResolver& resolve, const std::string& git_commit) override;
  void check_ranks(const std::string& git_commit) override;
  void run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
                  const TrialClaim& claim) override;
  void finish(int rc) override {
    finished_ = true;
    for (int w = 1; w < size(); ++w)
      if (workers_[w].state != Worker::dead) link_.send(w, kStop, cbor({{"rc", rc}, {"lost_peer", lost_peer_}}));
  }

 private:
  struct Worker {
    // unknown: no hello yet; greeted: same build, no threads yet; ready: welcomed with threads.
    enum State { unknown, greeted, ready, dead, refused } state = unknown;
    int threads = 1, default_threads = 1;
    std::string host;
  };
  void on_hello(int w, const Event& e, const std::string& git_commit);
  class Run;

  EventQueue events_;
  MpiLink link_;
  std::map<int, Worker> workers_;
  std::uint64_t next_id_ = 1;
  bool finished_ = false;
  bool lost_peer_ = false;  // a worker was lost: no rank may finalize MPI (see MpiLink::skip_finalize)
};

void MpiCluster::on_hello(int w, const Event& e, const std::string& git_commit) {
  Worker& worker = workers_[w];
  const Json hello = uncbor(e.bytes);
  worker.host = hello.value("host", std::string("?"));
  worker.default_threads = std::max(1, hello.value("default_threads", 1));
  const std::string mine = build_identity(git_commit);
  const std::string theirs = hello.value("build", std::string());
  if (hello.value("protocol", 0) != kProtocol || theirs != mine) {
    worker.state = Worker::refused;
    link_.send(w, kRefuse, {});
    throw ClusterSetupError(fmt::format("rank {} (host {}) runs hyfal built from '{}' (protocol {}), rank 0 from '{}' "
                                      "(protocol {}): every rank must run the same build",
                                      w, worker.host, theirs, hello.value("protocol", 0), mine, kProtocol));
  }
  worker.state = Worker::greeted;
}

void MpiCluster::check_ranks(const std::string& git_commit) {
  for (int w = 1; w < size(); ++w) workers_[w];
  const auto waiting = [&] {
    for (const auto& [w, worker] : workers_)
      if (worker.state == Worker::unknown) return true;
    return false;
  };
  while (waiting()) {
    std::optional<Event> e = events_.pop(std::chrono::milliseconds(200));
    if (!e) continue;
    if (e->tag == kHello) on_hello(e->peer, *e, git_commit);
    if (e->tag == kLost) {  // never started: the others run its share
      workers_[e->peer].state = Worker::dead;
      lost_peer_ = true;
      link_.skip_finalize();
    }
  }
}

// One run_trials call on rank 0: the queue of jobs (larger first where the caller knows), the
// trials in flight per rank, and the steps of the dispatch loop.
class MpiCluster::Run {
 public:
  Run(MpiCluster& cluster, const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
      const TrialClaim& claim)
      : c_(cluster), jobs_(jobs), options_(options), sink_(sink), claim_(claim),
        local_threads_(options.threads > 0 ? options.threads : default_thread_count()),
        local_(local_threads_, options, [&events = cluster.events_](std::uint64_t id, TrialResult&& r) {
          events.push(Event{0, kLocal, {}, id, std::move(r)});
        }) {
    std::vector<std::size_t> order(jobs.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return jobs[a].priority > jobs[b].priority; });
    queue_.assign(order.begin(), order.end());
    rank_in_order_.resize(jobs.size());
    for (std::size_t k = 0; k < order.size(); ++k) rank_in_order_[order[k]] = k;
  }

  void run() {
    try {
      for (;;) {
        welcome();
        dispatch();
        if (queue_.empty() && !any_in_flight()) break;
        std::optional<Event> e = c_.events_.pop(std::chrono::milliseconds(200));
        if (e) on_event(*e);
      }
    } catch (...) {
      cancel_all();
      throw;
    }
    if (options_.progress && done_ > 0) fmt::print(stderr, "\n");
  }

 private:
  // --threads per rank; 0: each rank's own core count.
  void welcome() {
    for (auto& [w, worker] : c_.workers_)
      if (worker.state == Worker::greeted) {
        worker.threads = options_.threads > 0 ? options_.threads : worker.default_threads;
        worker.state = Worker::ready;
        c_.link_.send(w, kWelcome, cbor({{"threads", worker.threads}}));
      }
  }

  // A second job per thread waits on each rank while many remain, so a rank never idles for a
  // round trip between two short trials; near the end, one per thread, so no job waits behind a
  // long one while another rank is free.
  std::size_t capacity(int rank) const {
    const int threads = rank == 0 ? local_threads_ : c_.workers_.at(rank).threads;
    int total = local_threads_;
    for (const auto& [w, worker] : c_.workers_)
      if (worker.state == Worker::ready) total += worker.threads;
    return static_cast<std::size_t>(threads) * (queue_.size() > 2 * static_cast<std::size_t>(total) ? 2 : 1);
  }

  void dispatch() {
    std::vector<int> ranks{0};
    for (const auto& [w, worker] : c_.workers_)
      if (worker.state == Worker::ready) ranks.push_back(w);
    for (int rank : ranks)
      while (!queue_.empty() && in_flight_[rank].size() < capacity(rank)) {
        const std::size_t i = queue_.front();
        queue_.pop_front();
        if (claim_ && !claim_(jobs_[i])) {
          ++skipped_;
          continue;
        }
        const std::uint64_t id = c_.next_id_++;
        dispatched_[id] = {i, rank};
        in_flight_[rank].insert(id);
        if (rank == 0)
          local_.submit(id, jobs_[i]);
        else
          c_.link_.send(rank, kJob, with_id(id, encode_job(jobs_[i])));
      }
  }

  void on_event(Event& e) {
    switch (e.tag) {
      case kLocal: finish_trial(e.id, std::move(*e.local)); break;
      case kResult: {
        auto [id, payload] = split_id(e.bytes);
        finish_trial(id, decode_result(payload));
        break;
      }
      case kHello: c_.on_hello(e.peer, e, options_.git_commit); break;
      case kFatal:
        c_.workers_[e.peer].state = Worker::dead;
        throw ClusterFailure(fmt::format("rank {} (host {}): {}", e.peer, c_.workers_[e.peer].host,
                                          uncbor(e.bytes).value("message", std::string("failed"))));
      case kLost: requeue_lost(e.peer); break;
      default: break;
    }
  }

  void finish_trial(std::uint64_t id, TrialResult result) {
    const auto it = dispatched_.find(id);
    if (it == dispatched_.end()) return;  // a result of a cancelled run, or a duplicate
    const int rank = it->second.second;
    in_flight_[rank].erase(id);
    dispatched_.erase(it);
    keep_witness(result, options_.witness_dir);
    sink_(result.record);
    ++done_;
    falsified_ += result.record.status == TrialStatus::falsified;
    if (options_.progress) {
      const std::size_t total = jobs_.size() - skipped_;
      const double el = std::chrono::duration<double>(Clock::now() - t0_).count();
      const double eta = el / static_cast<double>(done_) * static_cast<double>(total - done_);
      fmt::print(stderr, "\r[hyfal] {}/{} trials on {} ranks, {} falsified, {:.1f} s elapsed, ETA {:.1f} s   ", done_,
                 total, c_.size(), falsified_, el, eta);
    }
  }

  // A lost worker's trials in flight go back to the front of the queue, in the order they were
  // handed out (the claims are rank 0's: still ours).
  void requeue_lost(int peer) {
    Worker& w = c_.workers_[peer];
    w.state = Worker::dead;
    c_.lost_peer_ = true;
    c_.link_.skip_finalize();
    std::vector<std::size_t> orphans;
    for (const std::uint64_t id : in_flight_[peer]) {
      orphans.push_back(dispatched_[id].first);
      dispatched_.erase(id);
    }
    in_flight_[peer].clear();
    std::sort(orphans.begin(), orphans.end(), [&](std::size_t a, std::size_t b) { return rank_in_order_[a] > rank_in_order_[b]; });
    for (const std::size_t i : orphans) queue_.push_front(i);
    fmt::print(stderr, "[hyfal] rank {} (host {}) went silent for {:.0f} s: its {} trials in flight go to other ranks\n",
               peer, w.host.empty() ? "?" : w.host, peer_timeout_seconds(), orphans.size());
  }

  bool any_in_flight() const {
    for (const auto& [rank, ids] : in_flight_)
      if (!ids.empty()) return true;
    return false;
  }

  void cancel_all() {
    for (const auto& [rank, ids] : in_flight_)
      if (rank != 0 && !ids.empty() && c_.workers_[rank].state == Worker::ready) c_.link_.send(rank, kCancel, {});
    local_.cancel();
    local_.wait();
  }

  MpiCluster& c_;
  const std::vector<TrialJob>& jobs_;
  const EngineOptions& options_;
  const TrialSink& sink_;
  const TrialClaim& claim_;
  const int local_threads_;
  TrialExecutor local_;
  std::deque<std::size_t> queue_;
  std::vector<std::size_t> rank_in_order_;
  std::map<std::uint64_t, std::pair<std::size_t, int>> dispatched_;  // id -> (job, rank)
  std::map<int, std::set<std::uint64_t>> in_flight_;                 // rank -> ids
  std::size_t done_ = 0, skipped_ = 0, falsified_ = 0;
  const Clock::time_point t0_ = Clock::now();
};

void MpiCluster::run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
                            const TrialClaim& claim) {
  Run(*this, jobs, options, sink, claim).run();
}

int MpiCluster::serve(const SystemResolver& resolve, const std::string& git_commit) {
  EngineOptions base;
  base.host = host_name();
  base.git_commit = git_commit;
  link_.send(0, kHello,
             cbor({{"protocol", kProtocol},
                   {"build", build_identity(git_commit)},
                   {"host", base.host},
                   {"pid", static_cast<std::int64_t>(::getpid())},
                   {"default_threads", default_thread_count()}}));
  // A worker builds each suite instance once (a 1024^2 maze takes a while), however many trials.
  std::map<std::pair<std::string, std::string>, std::shared_ptr<const System>> systems;
  const SystemResolver cached = [&](const std::string& suite, const std::string& instance) {
    std::shared_ptr<const System>& s = systems[{suite, instance}];
    if (!s) s = resolve(suite, instance);
    return s;
  };
  int threads = 1;
  std::unique_ptr<TrialExecutor> executor;
  const auto start_executor = [&] {
    executor = std::make_unique<TrialExecutor>(threads, base, [this](std::uint64_t id, TrialResult&& r) {
      link_.send(0, kResult, with_id(id, encode_result(r)));
    });
  };
  const auto fatal = [&](const std::string& message) {
    executor.reset();
    link_.send(0, kFatal, cbor({{"message", message}}));
    fmt::print(stderr, "hyfal: error: rank {} (host {}): {}\n", rank(), base.host, message);
    return 3;
  };
  for (;;) {
    std::optional<Event> e = events_.pop(std::chrono::milliseconds(200));
    if (!e) continue;
    try {
      switch (e->tag) {
        case kWelcome:
          threads = uncbor(e->bytes).at("threads").get<int>();
          try {
            start_executor();
          } catch (const std::exception& ex) {
            return fatal(fmt::format("cannot start a oneTBB arena of {} threads: {}", threads, ex.what()));
          }
          break;
        case kRefuse: return 2;  // rank 0 says why
        case kJob: {
          if (!executor) return fatal("a job arrived before the welcome");
          auto [id, payload] = split_id(e->bytes);
          TrialJob job;
          try {
            job = decode_job(payload, cached);
          } catch (const std::exception& ex) {
            return fatal(fmt::format("cannot set up a trial: {}", ex.what()));
          }
          executor->submit(id, std::move(job));
          break;
        }
        case kCancel:
          if (executor) {
            executor->cancel();
            executor->wait();
            start_executor();
          }
          break;
        case kStop:
          executor.reset();
          if (uncbor(e->bytes).value("lost_peer", false)) link_.skip_finalize();
          return 0;
        case kLost:
          executor.reset();
          fmt::print(stderr, "hyfal: error: rank {} (host {}) lost rank 0 (no message for {:.0f} s): it stops\n", rank(),
                     base.host, peer_timeout_seconds());
          // Not through MPI_Finalize: it would wait for rank 0, which is gone.
          std::fflush(nullptr);
          std::_Exit(3);
        default: break;
      }
    } catch (const std::exception& ex) {
      return fatal(ex.what());
    }
  }
}

}  // namespace

Cluster* Cluster::current() { return g_current; }

std::unique_ptr<Cluster> Cluster::join_if_launched(int* argc, char*** argv) {
  const int size = launcher_size();
  if (size <= 1) return nullptr;
  return std::make_unique<MpiCluster>(argc, argv);
}

}  // namespace hyfal
