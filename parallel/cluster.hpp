// Distributed runs: the same trials across the ranks of an MPI job (`mpirun -n K hyfal run ...`).
//
// Rank 0 is the coordinator: it resolves the command as a one-process run does, claims each trial
// in its database, hands trials out one at a time as workers ask for more (so a long trial never
// holds up the ones behind it), writes every witness and stores every record on arrival: it is the
// only rank that opens the database, so the ranks need no shared file system. Every rank, rank 0
// included, is also a worker with its own oneTBB arena of --threads threads. Seeds come from the
// trial key only, so a run on K ranks stores what the same command stores in one process, and a
// run interrupted at one K resumes at any other.
//
// All MPI calls happen on one thread per process (the link thread; MPI_THREAD_FUNNELED), which
// also exchanges heartbeats: a worker that stays silent for the peer timeout is taken for dead
// (its trials in flight go to other ranks, where the launcher lets the job go on: OpenMPI's
// `mpirun --enable-recovery`), and a worker that loses rank 0 stops (exit 3).
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/util/error.hpp"
#include "parallel/trial_engine.hpp"
#include "parallel/trial_wire.hpp"

namespace hyfal {

// A failure of the distributed run's set-up: hyfal built without MPI but launched by mpirun,
// ranks built from different sources, a worker that cannot run trials. One line.
// The mixin of ClusterSetupError and ClusterFailure (core/util/error.hpp), so that
// `catch (const ClusterError&)` sees both.
class ClusterError {
 public:
  virtual ~ClusterError() = default;
  virtual const char* what() const noexcept = 0;
  // 2 for a set-up the user can fix, 3 for a machine that failed.
  virtual int exit_code() const noexcept = 0;
};

// A set-up the user can fix: builds differ between ranks, no MPI in this build (exit 2).
class ClusterSetupError : public InputError, public ClusterError {
 public:
  using InputError::InputError;
  const char* what() const noexcept override { return InputError::what(); }
  int exit_code() const noexcept override { return 2; }
  const char* name() const noexcept override { return "ClusterSetupError"; }
};

// A machine that failed: a rank cannot start its threads, a peer went silent (exit 3).
class ClusterFailure : public EnvironmentError, public ClusterError {
 public:
  using EnvironmentError::EnvironmentError;
  const char* what() const noexcept override { return EnvironmentError::what(); }
  int exit_code() const noexcept override { return 3; }
  const char* name() const noexcept override { return "ClusterFailure"; }
};

// This process's rank as the MPI launcher announces it in the environment (0 when none): before
// MPI starts, only rank 0 prints errors.
int launcher_rank();
// The number of ranks the launcher started (1 when none).
int launcher_size();

// The silence (seconds) after which a peer counts as gone: HYFAL_PEER_TIMEOUT_S (read on each
// rank, default 30; at least 2, as heartbeats go every second).
double peer_timeout_seconds();

class Cluster {
 public:
  // Joins the MPI job this process was started in, or returns nullptr when no MPI launcher
  // started it (or it is the only rank). Throws ClusterError when a launcher started several
  // ranks but this hyfal was built without MPI.
  static std::unique_ptr<Cluster> join_if_launched(int* argc, char*** argv);

  // The cluster this process joined, or nullptr (set by join_if_launched, cleared by ~Cluster).
  static Cluster* current();

  virtual ~Cluster() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;

  // Worker ranks (rank > 0): run the trials rank 0 hands out until it says stop. Returns the
  // exit code of this rank (0; 3 when rank 0 was lost or this rank failed).
  // git_commit identifies the build: rank 0 refuses a worker built from other sources.
  virtual int serve(const SystemResolver& resolve, const std::string& git_commit) = 0;

  // Rank 0, before the command runs: waits until every worker has said hello (or stayed silent
  // for the peer timeout: it gets no trials) and checks that all run the same build (git_commit).
  // Throws ClusterError (exit 2) otherwise, before anything is written.
  virtual void check_ranks(const std::string& git_commit) = 0;

  // Rank 0: runs the jobs on every rank with run_trials' contract: `claim` before a job is handed
  // out, `sink` once per finished trial, both on the calling thread; witnesses are written here
  // (options.witness_dir). On a failure the trials in flight everywhere are stopped and dropped
  // and the first exception is rethrown. Jobs of a rank lost on the way are run by others.
  virtual void run_trials(const std::vector<TrialJob>& jobs, const EngineOptions& options, const TrialSink& sink,
                          const TrialClaim& claim) = 0;

  // Rank 0: the command ended with exit code rc: tells the workers to stop. Called once.
  virtual void finish(int rc) = 0;
};

}  // namespace hyfal
