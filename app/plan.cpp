#include "app/plan.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>

#include <fmt/format.h>

namespace hyfal {

namespace {

std::string hours(double seconds) { return fmt::format("{:.2f}", seconds / 3600.0); }

std::string range_text(double lo, double hi, const char* unit) {
  return lo == hi ? fmt::format("{:g}{}", lo, unit) : fmt::format("{:g}{} to {:g}{}", lo, unit, hi, unit);
}

}  // namespace

int print_plan(const std::string& what, const std::vector<const TrialGroup*>& groups, const Shard& shard,
               const std::string& db) {
  const std::vector<const TrialGroup*> cells = distinct_groups(groups);
  std::int64_t all_trials = 0, shard_trials = 0, stored = 0, max_batch = 1;
  double bound_s = 0.0, remaining_s = 0.0;
  double min_timeout = 0.0, max_timeout = 0.0, min_nodes = 0.0, max_nodes = 0.0;
  // Read-only and only when present: a plan must not create the database it sizes.
  std::optional<TrialStore> store;
  std::error_code ec;
  if (std::filesystem::exists(db, ec)) store.emplace(TrialStore::open_read_only(db));
  std::int64_t position = 0;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const TrialGroup& g = *cells[c];
    const std::int64_t trials = g.spec.trials;
    const std::int64_t in_shard = shard.count_in(position, trials);
    std::int64_t done = 0;
    if (store) {
      // prepare_jobs drops stored trials (status other than error): errored ones run again.
      done = in_shard - static_cast<std::int64_t>(
                            prepare_jobs(g, store->stored_trial_indices(g.base), shard, position).size());
    }
    position += trials;
    all_trials += trials;
    shard_trials += in_shard;
    stored += done;
    bound_s += static_cast<double>(in_shard) * g.spec.timeout_s;
    remaining_s += static_cast<double>(in_shard - done) * g.spec.timeout_s;
    const double nodes = static_cast<double>(g.spec.max_nodes);
    min_timeout = c == 0 ? g.spec.timeout_s : std::min(min_timeout, g.spec.timeout_s);
    max_timeout = c == 0 ? g.spec.timeout_s : std::max(max_timeout, g.spec.timeout_s);
    min_nodes = c == 0 ? nodes : std::min(min_nodes, nodes);
    max_nodes = c == 0 ? nodes : std::max(max_nodes, nodes);
    if (g.options.is_object() && g.options.contains("batch") && g.options["batch"].is_number_integer())
      max_batch = std::max<std::int64_t>(max_batch, g.options["batch"].get<std::int64_t>());
  }

  fmt::print("plan for {} (nothing is run)\n", what);
  if (shard.whole())
    fmt::print("  cells:     {} trial group(s), {} trials\n", cells.size(), all_trials);
  else
    fmt::print("  cells:     {} trial group(s), {} trials; shard {}: {} of them\n", cells.size(), all_trials,
               shard.text(), shard_trials);
  const auto lo_nodes = static_cast<std::int64_t>(min_nodes), hi_nodes = static_cast<std::int64_t>(max_nodes);
  const std::string nodes_text =
      lo_nodes == hi_nodes ? fmt::format("{}", hi_nodes) : fmt::format("{} to {}", lo_nodes, hi_nodes);
  fmt::print("  caps:      per trial {} wall clock, {} nodes\n", range_text(min_timeout, max_timeout, " s"), nodes_text);
  fmt::print("  CPU-hours: at most {} ({} trials x time cap / 3600; assumes one core per trial, i.e. batch 1)\n",
             hours(bound_s), shard_trials);
  if (max_batch > 1)
    fmt::print("  note:      some groups use batch up to {}: a trial may then use up to min(batch, --threads) cores,"
               " so core-hours may exceed the bound by that factor\n",
               max_batch);
  if (store)
    fmt::print("  stored:    {} of these {} trials in {}; {} remain, at most {} CPU-hours\n", stored, shard_trials,
               db, shard_trials - stored, hours(remaining_s));
  else
    fmt::print("  stored:    none ({} does not exist yet)\n", db);
  return 0;
}

}  // namespace hyfal
