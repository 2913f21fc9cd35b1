// `hyfal simulate`: a suite instance driven by a given input signal (an ARCH-COMP input CSV), its
// trace and each requirement's robustness; `hyfal witness --format arch-csv`: a witness's input
// signal as such a CSV. Together: replay someone else's counterexample, or hand ours to them.
//
// The CSV (ARCH-COMP's validation format): a time column, then one column per input in the
// suite's input order; a header row is optional (`time` or `t`, then the input names). Row k's
// inputs hold from its time to the next row's (piecewise constant); the last row's time ends the
// simulation (its inputs are not used). Times start at 0 and increase; values lie in the inputs'
// box. The header may name an input by its name or by an alias the suite declares
// (SystemInfo::input_aliases: `time,throttle,brake` for at). Anything else: one line naming the
// row and column, exit 2, nothing written.
//
// Each requirement is judged on the trace (core/requirements/trace_monitor.hpp, TraceVerdict): a
// trace shorter than a requirement's horizon is a prefix, shown with its robustness interval and
// the verdict it decides, else "unknown: trace too short". A requirement given with
// --set requirement=X that such a trace cannot decide is an error (exit 2, nothing written).
#pragma once
#include <string>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/simulate/input_signal.hpp"
#include "core/requirements/trace_monitor.hpp"

namespace hyfal::cli {

struct SimulateArgs {
  std::string suite;
  std::vector<std::string> sets;  // key=value instance parameters
  std::string input;              // the input CSV
  std::string trace;              // where to write the trace CSV ("" none, "-" stdout)
  std::string interpolation = "zoh";  // the CSV's rows as zoh (held) or linear control points
};

int cmd_simulate(const SimulateArgs& args);

// `hyfal witness FILE --format arch-csv [-o OUT]`.
int cmd_witness_csv(const std::string& file, const std::string& output);

// The pieces of an input CSV's text for a system with `inputs` (names, each also called by its
// `aliases`, which may be empty) inside `box`; throws UsageError naming `where`, the row and the
// column. linear_step > 0: the rows are control points of a linear signal, cut into pieces of at
// most that length (stl::linear_signal_pieces); 0: each row's input is held until the next.
std::vector<stl::InputPiece> parse_input_csv(const std::string& text, const std::vector<std::string>& inputs,
                                             const Box& box, const std::string& where,
                                             const std::vector<std::vector<std::string>>& aliases = {},
                                             double linear_step = 0.0);

// The names an input CSV's header may give its columns, as `time (or t), u1 (or throttle), ...`.
std::string accepted_input_names(const std::vector<std::string>& inputs,
                                 const std::vector<std::vector<std::string>>& aliases);
std::string accepted_input_names(const SystemInfo& info);

}  // namespace hyfal::cli
