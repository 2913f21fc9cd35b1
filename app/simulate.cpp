#include "app/simulate.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/runner.hpp"
#include "core/util/files.hpp"
#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/witness/witness.hpp"
#include "suites/registry.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/simulate/input_signal.hpp"
#include "core/model/signal_model.hpp"
#include "core/simulate/input_simulator.hpp"

namespace hyfal::cli {

namespace {

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  for (char c : line) {
    if (c == ',') {
      fields.push_back(field);
      field.clear();
    } else if (c != '\r' && c != ' ' && c != '\t') {
      field += c;
    }
  }
  fields.push_back(field);
  return fields;
}

bool parse_number(const std::string& s, double& v) {
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  return ec == std::errc() && ptr == end && std::isfinite(v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The system of `suite` with `sets`; UsageError on a bad name or value.
std::shared_ptr<const System> make_system(const std::string& suite_name, const std::vector<std::string>& sets_text) {
  const SuiteEntry* suite = find_suite(suite_name);
  if (!suite) throw UsageError(fmt::format("unknown suite '{}' (see 'hyfal list')", suite_name));
  std::vector<std::pair<std::string, std::string>> sets;
  for (const auto& s : sets_text) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError(fmt::format("--set {}: expected key=value", s));
    sets.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  try {
    return suite->make(canonical_instance(suite->parameters, resolve_options(suite->parameters, sets)));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

std::string trace_csv(const SystemInfo& info, const stl::SimulatedTrace& trace) {
  std::string out = "time";
  for (const auto& s : stl::system_signals(info)) out += "," + s.name;
  out += "\n";
  for (std::size_t i = 0; i < trace.samples(); ++i) {
    out += fmt::format("{:.17g}", trace.time[i]);
    for (const auto& signal : trace.signals) out += fmt::format(",{:.17g}", signal[i]);
    out += "\n";
  }
  return out;
}

}  // namespace

std::string accepted_input_names(const std::vector<std::string>& inputs,
                                 const std::vector<std::vector<std::string>>& aliases) {
  std::string out = "time (or t)";
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    out += ", " + inputs[i];
    if (i < aliases.size() && !aliases[i].empty()) out += fmt::format(" (or {})", fmt::join(aliases[i], " or "));
  }
  return out;
}

std::string accepted_input_names(const SystemInfo& info) { return accepted_input_names(info.input_names, info.input_aliases); }

std::vector<stl::InputPiece> parse_input_csv(const std::string& text, const std::vector<std::string>& inputs,
                                             const Box& box, const std::string& where,
                                             const std::vector<std::vector<std::string>>& aliases, double linear_step) {
  std::istringstream in(text);
  std::string line;
  std::vector<double> times;
  std::vector<std::vector<double>> values;
  std::vector<int> row_of;  // each sample's row in the file
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = split_fields(line);
    double t = 0.0;
    if (times.empty() && row == 1 && !parse_number(fields[0], t)) {  // a header
      const auto names = [&](std::size_t i) {
        std::vector<std::string> v{inputs[i]};
        if (i < aliases.size()) v.insert(v.end(), aliases[i].begin(), aliases[i].end());
        return v;
      };
      const auto is_one_of = [](const std::string& field, const std::vector<std::string>& accepted) {
        return std::any_of(accepted.begin(), accepted.end(), [&](const std::string& a) { return lower(field) == lower(a); });
      };
      bool ok = fields.size() == inputs.size() + 1 && is_one_of(fields[0], {"time", "t"});
      for (std::size_t i = 0; ok && i < inputs.size(); ++i) ok = is_one_of(fields[i + 1], names(i));
      if (!ok)
        throw UsageError(fmt::format("'{}': row 1: the header '{}' does not name the columns as expected: {}", where,
                                     one_line(line), accepted_input_names(inputs, aliases)));
      continue;
    }
    if (fields.size() != inputs.size() + 1)
      throw UsageError(fmt::format("'{}': row {}: {} columns, expected {} (time and {})", where, row, fields.size(),
                                   inputs.size() + 1, fmt::join(inputs, ", ")));
    std::vector<double> u(inputs.size());
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = 0.0;
      if (!parse_number(fields[c], v))
        throw UsageError(fmt::format("'{}': row {}, column {}: '{}' is not a finite number", where, row, c + 1,
                                     one_line(fields[c])));
      if (c == 0)
        t = v;
      else
        u[c - 1] = v;
    }
    times.push_back(t);
    values.push_back(std::move(u));
    row_of.push_back(row);
  }
  // What the signal must be (stl::sampled_signal_problem, as the Python module checks it), in the
  // file's rows and columns.
  using Kind = stl::SampledSignalProblem::Kind;
  if (const auto p = stl::sampled_signal_problem(times, values, box)) {
    const int at = p->sample < row_of.size() ? row_of[p->sample] : row;
    switch (p->kind) {
      case Kind::too_few:
        throw UsageError(fmt::format("'{}': at least two rows are needed (a start and an end time)", where));
      case Kind::first_time: throw UsageError(fmt::format("'{}': row {}: the first time must be 0", where, at));
      case Kind::not_increasing:
        throw UsageError(fmt::format("'{}': row {}: time {} does not increase", where, at, p->value));
      case Kind::outside:
        throw UsageError(fmt::format("'{}': row {}, column {} ({}): {} is outside [{}, {}]", where, at, p->input + 2,
                                     inputs[p->input], p->value, box.lo[p->input], box.hi[p->input]));
    }
  }
  return stl::sampled_signal_pieces(times, std::move(values), box, linear_step);
}

int cmd_simulate(const SimulateArgs& args) {
  const auto system = make_system(args.suite, args.sets);
  const SystemInfo& info = system->info();
  // Linear: pieces of the integrator's step (its largest, for an adaptive one), each holding the
  // line's midpoint value.
  const double linear_step = args.interpolation == "linear" ? stl::linear_piece_step(info) : 0.0;
  std::vector<stl::InputPiece> pieces;
  if (!args.input.empty()) {
    pieces = parse_input_csv(read_input_file(args.input), info.input_names, system->inputs(info.initial_mode).box,
                             args.input, info.input_aliases, linear_step);
  } else if (!info.input_names.empty()) {
    throw UsageError(fmt::format("--input is required: suite '{}' has inputs ({})", info.suite, accepted_input_names(info)));
  } else {  // no inputs: one piece as long as the longest horizon its requirements read
    double length = info.requirement ? info.requirement->formula.horizon() : 0.0;
    for (const auto& r : info.requirements) length = std::max(length, stl::resolve_requirement(info, r.id).formula.horizon());
    if (!(length > 0.0 && std::isfinite(length)))
      throw UsageError(fmt::format("--input: suite '{}' has no inputs and no bounded requirement to give the simulation's "
                                   "length: give a CSV of times only (time, 0, T)",
                                   info.suite));
    pieces.push_back({length, {}});
  }
  const stl::SimulatedTrace trace = stl::simulate_inputs(*system, pieces, info.parameters);
  // Every verdict before anything is written: a requirement asked for by name that the trace
  // cannot decide is refused.
  struct Row {
    std::string name;
    stl::TraceVerdict verdict;
  };
  std::vector<Row> rows;
  const double end = trace.time.back();
  for (const auto& d : info.requirements) {
    const stl::Requirement requirement = stl::resolve_requirement(info, d.id);
    rows.push_back({d.id, stl::TraceMonitor(requirement).judge(trace)});
  }
  if (info.requirement) {
    const stl::Requirement& asked = *info.requirement;
    const stl::TraceVerdict verdict = stl::TraceMonitor(asked).judge(trace);
    if (!verdict.complete && !verdict.decided())
      throw UsageError(fmt::format("'{}': the trace ends at {:.6g} s, but requirement {} reads {:.6g} s (its horizon): "
                                   "its verdict is unknown; give an input signal of at least {:.6g} s",
                                   args.input, end, asked.id.empty() ? "'" + one_line(asked.text) + "'" : asked.id,
                                   verdict.horizon, verdict.horizon));
    if (asked.id.empty()) rows.push_back({"(--set requirement)", verdict});
  }
  if (!args.trace.empty()) {
    if (args.trace == "-")
      std::cout << trace_csv(info, trace);
    else
      write_file_atomic(args.trace, trace_csv(info, trace), "trace");
  }
  std::ostream& out = args.trace == "-" ? std::cerr : std::cout;
  out << fmt::format("{} samples over [0, {:.6g}] s{}\n", trace.samples(), end,
                     trace.end == PropagationEnd::invariant  ? " (the system's invariant ended it early)"
                     : trace.end == PropagationEnd::rejected ? " (rejected: a non-finite state or a Zeno chain)"
                                                             : "");
  out << "| requirement | robustness | falsified |\n|---|--:|---|\n";
  for (const auto& [name, v] : rows) {
    if (v.complete) {
      out << fmt::format("| {} | {:.6g} | {} |\n", name, v.bounds.lower, v.falsified() ? "yes" : "no");
      continue;
    }
    // A prefix: every extension's robustness lies in the interval shown.
    const std::string bounds = fmt::format("[{:.6g}, {:.6g}]", v.bounds.lower, v.bounds.upper);
    if (v.decided())
      out << fmt::format("| {} | {} | {} (decided by the {:.6g} s given; the horizon is {:.6g} s) |\n", name, bounds,
                         v.falsified() ? "yes" : "no", end, v.horizon);
    else
      out << fmt::format("| {} | {} | unknown: trace too short (needs {:.6g} s) |\n", name, bounds, v.horizon);
  }
  return 0;
}

int cmd_witness_csv(const std::string& file, const std::string& output) {
  Witness w;
  try {
    w = witness_from_text(read_input_file(file));
  } catch (const WitnessError& e) {
    throw UsageError(one_line(fmt::format("'{}': {}", file, e.what())));
  }
  std::string csv = "time";
  for (const auto& name : w.input_names) csv += "," + name;
  csv += "\n";
  double t = 0.0;
  for (const auto& piece : w.trajectory.pieces) {
    if (piece.duration <= 0.0) continue;  // a zero-time piece holds no input
    csv += fmt::format("{:.17g}", t);
    for (double u : piece.u) csv += fmt::format(",{:.17g}", u);
    csv += "\n";
    t += piece.duration;
  }
  csv += fmt::format("{:.17g}", t);  // the end: the last piece's inputs, unused
  const std::vector<double> last = w.trajectory.pieces.empty() ? std::vector<double>(w.input_names.size(), 0.0)
                                                                : w.trajectory.pieces.back().u;
  for (double u : last) csv += fmt::format(",{:.17g}", u);
  csv += "\n";
  if (output.empty() || output == "-")
    std::cout << csv;
  else
    write_file_atomic(output, csv, "input CSV");
  return 0;
}

}  // namespace hyfal::cli
