// `hyfal reproduce`: a paper table's rows through the runner (app/runner.hpp), written beside the
// paper's numbers.
#pragma once
#include <cstdint>
#include <string>

#include "app/runner.hpp"
#include "core/run/paper_table.hpp"

namespace hyfal::cli {

struct ReproduceArgs {
  std::string id, profile;
  int threads = 0;
  std::uint64_t seed = 1;
  std::string db = "results/hyfal.sqlite", witness_dir = "results/witnesses", out_dir = "results/tables";
  std::string shard;  // --shard i/K, empty for all trials
  bool plan = false;  // --plan: print the sizing and run nothing
  bool save_trees = false;  // --save-trees: each witness's search tree(s) beside it
};

// hyfal reproduce ID --profile P: runs the table's rows (resuming), writes OUT/ID.md and
// OUT/ID.csv and prints the Markdown. Returns 1 if a trial ended in an error, else 0.
int cmd_reproduce(const ReproduceArgs& args);

// The table `hyfal reproduce` names: the path of a table file (anything ending in ".toml" or
// holding a '/'), or the id of a compiled-in table (experiments/paper/<id>.toml). Throws
// UsageError for an unknown id or an unreadable file, ExperimentFileError for a bad file.
PaperTable find_table(const std::string& id_or_path);

}  // namespace hyfal::cli
