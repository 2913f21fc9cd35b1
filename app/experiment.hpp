// `hyfal run FILE.toml`: an experiment file (app/experiment_file.hpp) through the runner, its
// table written as Markdown and CSV.
#pragma once
#include <string>

namespace hyfal::cli {

struct ExperimentArgs {
  std::string file;
  int threads = 0;
  std::string db = "results/hyfal.sqlite", witness_dir = "results/witnesses", out_dir = "results/tables";
  std::string shard;  // --shard i/K, empty for all trials
  bool plan = false;  // --plan: print the sizing and run nothing
  bool quiet = false; // no progress line or resuming note
  bool save_trees = false;  // --save-trees
};

// Reads and checks the file and resolves every group before anything is written (a bad file or
// group: UsageError / ExperimentFileError, exit 2), runs the trials the database lacks (resuming),
// writes OUT/NAME.md and OUT/NAME.csv and prints the Markdown. Returns 1 if a trial ended in an
// error, else 0.
int cmd_run_experiment(const ExperimentArgs& args);

}  // namespace hyfal::cli
