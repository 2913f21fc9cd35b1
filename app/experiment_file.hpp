// Paper tables (experiments/paper/<id>.toml, what `hyfal reproduce` runs) and experiments
// (experiments/NAME.toml, what `hyfal run FILE` runs) as TOML files. The formats are documented
// in the README ("Tables and experiments as TOML files"); a new table or experiment is one such
// file, no C++.
#pragma once
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/error.hpp"
#include "core/run/paper_table.hpp"
#include "core/run/suite_entry.hpp"
#include "results/table_writer.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {

// A table or experiment file that cannot be used. The message is one line naming the file, the
// line and column, and the key: "FILE:LINE:COLUMN: KEY: what is wrong" ("FILE:LINE:COLUMN: what"
// for a TOML syntax error). The CLI reports it as a bad input (exit 2) before anything is written.
class ExperimentFileError : public InputError {
 public:
  using InputError::InputError;
  const char* name() const noexcept override { return "ExperimentFileError"; }
};

// Reads a paper table from the TOML `text` of the file `file_name` (used in messages only).
// Everything is checked here, so that `reproduce` refuses a bad file before it opens a database:
// TOML syntax, unknown and missing keys, value types, the suite and every row's method (by the
// registries), every setting's key (a parameter of the suite or an option of a method that can
// receive it) and its value (type and range), the shape of the paper's numbers (one per column;
// [block][row][column] for a sweep), and the profiles' sizes. The paper's numbers are TOML
// numbers, "N/A" (not reported, kNotReported) or "X" (the paper's timeout, kPaperTimeout).
// Throws ExperimentFileError.
PaperTable load_paper_table(std::string_view text, const std::string& file_name);

// A file compiled into the binary: its path in the source tree and its text.
struct EmbeddedFile {
  std::string_view path, text;
};

// experiments/paper/*.toml as they were at build time, sorted by path (app/embed_files.cmake
// generates the definition).
std::span<const EmbeddedFile> embedded_paper_table_files();

// The compiled-in paper tables, read once, in file order. Each file is named after its table
// (experiments/paper/<id>.toml). Throws ExperimentFileError for a file that does not read (the
// tests read every one, so a release never has one).
const std::vector<PaperTable>& builtin_paper_tables();

// The compiled-in table with this id, or nullptr.
const PaperTable* find_builtin_paper_table(std::string_view id);

// One trial group of an experiment: a suite instance and a method with its options, where it sits
// in the experiment's table.
struct ExperimentGroup {
  const SuiteEntry* suite = nullptr;
  const MethodEntry* method = nullptr;
  std::string method_label;  // the method entry's label (its name unless the file gives one)
  Settings settings;         // the suite's settings, then the method's options
  GroupPlace place;          // block, row and column labels
};

// An experiment file: suites with instance settings and methods with options, where a list of
// values expands to a grid (every combination, in file order, the last key varying fastest); every
// method runs on every suite instance with the same trials, caps and seed. The table lays the
// groups out by dimensions: "suite", "method" (the entry's label) and any setting key.
struct ExperimentFile {
  std::string name;  // the experiment: its key in the database, witness folder and table files
  int trials = 10;
  double timeout_s = 60.0;
  std::int64_t max_nodes = 1'000'000;
  std::uint64_t seed = 1;
  std::vector<std::string> rows, columns, blocks;  // dimensions; a varying one not placed joins rows
  GroupMeasure value = GroupMeasure::time_median_s;
  // The row the verdicts compare every other row against (`[table] baseline`, a row label as the
  // table prints it, e.g. "rrt" or "history, step=0.1"); default: the first row.
  std::string baseline;
  std::vector<ExperimentGroup> groups;  // suites x their grid x methods x their grid
};

// Reads an experiment file; checks everything load_paper_table checks of the same keys (syntax,
// keys, types, registry names, setting keys and values), the experiment name (as --experiment)
// and the layout, and that `baseline` names a row. Throws ExperimentFileError.
ExperimentFile load_experiment_file(std::string_view text, const std::string& file_name);

}  // namespace hyfal
