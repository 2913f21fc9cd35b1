// hyfal merge OUT IN...: the databases of shards (or of separate runs) merged into one.
#pragma once
#include <string>
#include <vector>

namespace hyfal::cli {

struct MergeArgs {
  std::string out;
  std::vector<std::string> inputs;
  std::string witness_dir;  // empty: witness paths are kept as stored
};

// Merges every trial (with its series) of the inputs into out, creating it if missing. The
// inputs are only read. A trial whose key is already present (in out or an earlier input) is
// the same trial when seed, status, nodes, propagations and integration_steps agree: skipped,
// so merging twice changes nothing. A stored error row gives way to a result of the same key
// (errors are retried, as on resume). Any other difference is a conflict: UsageError naming the
// input, the key and the field, and nothing is written. Everything is checked first, then
// written in one transaction. Returns the exit code (0).
int cmd_merge(const MergeArgs& args);

}  // namespace hyfal::cli
