// `hyfal plot`: figures through Debian's Python and matplotlib (scripts/plot_tables.py for the
// tables `hyfal reproduce` writes, scripts/plot_witness.py for one witness), and the figures
// `hyfal reproduce` writes beside each table.
#pragma once
#include <string>

namespace hyfal::cli {

struct PlotArgs {
  std::string tables_dir;  // hyfal plot TABLES_DIR: every figure of the CSVs there
  std::string witness;     // hyfal plot --witness FILE: a picture of one witness
  std::string out;         // a folder (tables) or F.png (witness; F.svg beside it)
  std::string tree;        // --tree T.csv: the search tree drawn under the witness (default: F.tree.csv beside it)
  bool out_given = false;  // --out was given (else the default: TABLES_DIR, the witness's path)
};

// Checks the arguments (UsageError: one line, exit 2, nothing written), then runs the script
// with its output on this process's stdout and stderr. Returns the exit code: 0; 2 when the
// script refuses its input; 3 when the environment lacks the interpreter, matplotlib or the
// script (one line saying what to install).
int cmd_plot(const PlotArgs& args);

// The figures of table `id` (out_dir/<id>*.png and .svg, as far as the table has figures), for
// `hyfal reproduce`: one line on stderr says what was written, or why nothing was (e.g.
// matplotlib missing). Never throws and never fails the reproduce.
void write_table_figures(const std::string& out_dir, const std::string& id);

}  // namespace hyfal::cli
