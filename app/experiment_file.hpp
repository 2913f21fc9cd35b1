// Paper tables as TOML files (experiments/paper/<id>.toml): what `hyfal reproduce` runs. The
// format is documented in the README ("Tables and experiments as TOML files"); a new table is one
// such file, no C++.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/paper_table.hpp"

namespace hyfal {

// A table or experiment file that cannot be used. The message is one line naming the file, the
// line and column, and the key: "FILE:LINE:COLUMN: KEY: what is wrong" ("FILE:LINE:COLUMN: what"
// for a TOML syntax error). The CLI reports it as a bad input (exit 2) before anything is written.
class ExperimentFileError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
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

}  // namespace hyfal
