// TrialRecord: what one trial of one method on one suite instance produced.
// core defines it; parallel/ fills it, results/ stores and summarizes it.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hyfal {

// node_cap: the run's node cap (--max-nodes) ended it; budget: the method's own budget (its
// `budget` option: simulations, passes, simulation-equivalents) was spent. Databases written
// before `budget` existed call both node_cap (results/store.cpp maps those rows on read).
enum class TrialStatus { falsified, not_found, timeout, node_cap, budget, error };

constexpr std::string_view to_string(TrialStatus s) {
  switch (s) {
    case TrialStatus::falsified:
      return "falsified";
    case TrialStatus::not_found:
      return "not_found";
    case TrialStatus::timeout:
      return "timeout";
    case TrialStatus::node_cap:
      return "node_cap";
    case TrialStatus::budget:
      return "budget";
    case TrialStatus::error:
      return "error";
  }
  return "error";
}

inline std::optional<TrialStatus> parse_trial_status(std::string_view s) {
  for (auto st : {TrialStatus::falsified, TrialStatus::not_found, TrialStatus::timeout, TrialStatus::node_cap,
                  TrialStatus::budget, TrialStatus::error})
    if (to_string(st) == s) return st;
  return std::nullopt;
}

// Identifies a trial: a rerun with an equal key is the same trial (resume skips it).
// instance and config are canonical JSON (sorted keys, no spaces).
struct TrialKey {
  std::string experiment;
  std::string suite;
  std::string instance;
  std::string method;
  std::string config;
  std::int64_t trial_index = 0;
  friend bool operator==(const TrialKey&, const TrialKey&) = default;
};

struct TrialRecord {
  TrialKey key;
  std::int64_t seed = 0;  // 63-bit trial seed, so it fits SQLite's INTEGER unchanged
  TrialStatus status = TrialStatus::error;
  bool validated = false;  // the witness re-simulated and reached s <= tol
  double wall_s = 0.0;
  double cpu_s = 0.0;
  std::int64_t nodes = 0;
  std::int64_t propagations = 0;
  std::int64_t integration_steps = 0;
  std::string witness;  // path of the witness JSON, empty when none
  std::string error;    // error text, empty when none
  int threads = 1;      // size of the thread pool the trial ran in
  std::string host;
  std::string git_commit;
  std::string started_at;  // ISO 8601 UTC, e.g. 2026-11-22T03:14:15.123Z
  std::string finished_at;
  std::string metrics = "{}";  // JSON object of method-specific scalars (coverage, beta, ...)
  // With an STL requirement metrics also holds "robustness" (a falsified trial's: its witness's, as
  // the validator re-simulates it; otherwise the lowest upper bound of any node of the search)
  // and "simulations", the simulation-equivalents: simulated time / the requirement's horizon
  // (absent when the horizon is unbounded).
  // Progress series (name, points), stored in the `series` table with the trial's id.
  std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>> series;
};

}  // namespace hyfal
