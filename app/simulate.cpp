#include "app/simulate.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/runner.hpp"
#include "core/files.hpp"
#include "core/options.hpp"
#include "core/requirements/requirement.hpp"
#include "core/trajectory.hpp"
#include "suites/registry.hpp"

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

std::vector<stl::InputPiece> parse_input_csv(const std::string& text, const std::vector<std::string>& inputs,
                                             const Box& box, const std::string& where) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::pair<double, std::vector<double>>> rows;
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = split_fields(line);
    double t = 0.0;
    if (rows.empty() && row == 1 && !parse_number(fields[0], t)) {  // a header
      const bool ok = fields.size() == inputs.size() + 1 && (lower(fields[0]) == "time" || lower(fields[0]) == "t");
      bool names = ok;
      for (std::size_t i = 0; ok && i < inputs.size(); ++i) names = names && fields[i + 1] == inputs[i];
      if (!names)
        throw UsageError(fmt::format("'{}': row 1: the header must be time,{}", where, fmt::join(inputs, ",")));
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
      if (c == 0) {
        t = v;
        continue;
      }
      const std::size_t k = c - 1;
      if (v < box.lo[k] - 1e-9 || v > box.hi[k] + 1e-9)
        throw UsageError(fmt::format("'{}': row {}, column {} ({}): {} is outside [{}, {}]", where, row, c + 1,
                                     inputs[k], v, box.lo[k], box.hi[k]));
      u[k] = std::min(box.hi[k], std::max(box.lo[k], v));
    }
    if (rows.empty() && t != 0.0) throw UsageError(fmt::format("'{}': row {}: the first time must be 0", where, row));
    if (!rows.empty() && !(t > rows.back().first))
      throw UsageError(fmt::format("'{}': row {}: time {} does not increase", where, row, t));
    rows.emplace_back(t, std::move(u));
  }
  if (rows.size() < 2) throw UsageError(fmt::format("'{}': at least two rows are needed (a start and an end time)", where));
  std::vector<stl::InputPiece> pieces;
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) pieces.push_back({rows[k + 1].first - rows[k].first, rows[k].second});
  return pieces;
}

int cmd_simulate(const SimulateArgs& args) {
  const auto system = make_system(args.suite, args.sets);
  const SystemInfo& info = system->info();
  const auto pieces = parse_input_csv(read_input_file(args.input), info.input_names, system->inputs(info.initial_mode).box,
                                      args.input);
  const stl::SimulatedTrace trace = stl::simulate_inputs(*system, pieces, info.parameters);
  if (!args.trace.empty()) {
    if (args.trace == "-")
      std::cout << trace_csv(info, trace);
    else
      write_file_atomic(args.trace, trace_csv(info, trace), "trace");
  }
  std::ostream& out = args.trace == "-" ? std::cerr : std::cout;
  out << fmt::format("{} samples over [0, {:.6g}] s{}\n", trace.samples(), trace.time.back(),
                     trace.end == PropagationEnd::invariant  ? " (the system's invariant ended it early)"
                     : trace.end == PropagationEnd::rejected ? " (rejected: a non-finite state or a Zeno chain)"
                                                             : "");
  out << "| requirement | robustness | falsified |\n|---|--:|---|\n";
  std::vector<std::pair<std::string, std::string>> requirements;
  for (const auto& d : info.requirements) requirements.emplace_back(d.id, d.id);
  if (info.requirement && info.requirement->id.empty()) requirements.emplace_back("(--set requirement)", info.requirement->text);
  for (const auto& [name, value] : requirements) {
    const double rho = stl::trace_robustness(stl::resolve_requirement(info, value), trace);
    out << fmt::format("| {} | {:.6g} | {} |\n", name, rho, rho < 0.0 ? "yes" : "no");
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
