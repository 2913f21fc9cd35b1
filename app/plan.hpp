// --plan: the size of a run or table (trials, caps, an upper bound of CPU-hours, what remains),
// printed without running anything, so that a user can size a cluster allocation.
#pragma once
#include <string>
#include <vector>

#include "app/runner.hpp"
#include "app/shard.hpp"

namespace hyfal {

// Prints the plan of the trial groups (in job-list order; groups sharing trials are counted
// once) restricted to the shard. Creates and changes no file: the database is opened read-only,
// and only if it exists, to count what is already stored. Returns the exit code (0).
int print_plan(const std::string& what, const std::vector<const TrialGroup*>& groups, const Shard& shard,
               const std::string& db);

}  // namespace hyfal
