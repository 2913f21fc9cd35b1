#include "core/witness/witness.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/requirements/requirement.hpp"

namespace hyfal {

namespace {

Json vec(const std::vector<double>& v) { return Json(v); }

// j[key], or a WitnessError naming the field when j is not an object or has no such member.
const Json& member(const Json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw WitnessError(fmt::format("witness: missing field '{}{}'", where, key));
  return j.at(key);
}

WitnessError wrong_type(const char* key, const std::string& where, const char* expected) {
  return WitnessError(fmt::format("witness: field '{}{}' has the wrong type (expected {})", where, key, expected));
}

// Reads j[key] as T (strings, lists of strings), with a WitnessError that names the field.
template <class T>
T field(const Json& j, const char* key, const std::string& where) {
  const Json& v = member(j, key, where);
  try {
    return v.get<T>();
  } catch (const Json::exception&) {
    throw WitnessError(fmt::format("witness: field '{}{}' has the wrong type", where, key));
  }
}

// j[key] as an integer in [lo, hi]. A JSON number written as a float ("1e3") counts when it is
// integral. Anything else is a WitnessError naming the field and the range: the value is never
// wrapped into range (-1 is not the largest Mode) nor converted with undefined behaviour.
template <class T>
T integer_field(const Json& j, const char* key, const std::string& where, T lo, T hi) {
  const Json& v = member(j, key, where);
  if (!v.is_number()) throw wrong_type(key, where, "an integer");
  const auto in_range = [&](auto i) { return std::cmp_greater_equal(i, lo) && std::cmp_less_equal(i, hi); };
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (in_range(u)) return static_cast<T>(u);
  } else if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    if (in_range(i)) return static_cast<T>(i);
  } else {
    const double d = v.get<double>();
    // 2^64 and -2^63 are exact doubles: inside these bounds the conversions below are exact.
    if (std::isfinite(d) && d == std::floor(d)) {
      if (d >= 0.0 && d < 18446744073709551616.0) {
        const auto u = static_cast<std::uint64_t>(d);
        if (in_range(u)) return static_cast<T>(u);
      } else if (d < 0.0 && d >= -9223372036854775808.0) {
        const auto i = static_cast<std::int64_t>(d);
        if (in_range(i)) return static_cast<T>(i);
      }
    }
  }
  throw WitnessError(
      fmt::format("witness: field '{}{}' = {} is out of range (an integer in [{}, {}])", where, key, v.dump(), lo, hi));
}

// j[key] as a finite number.
double number_field(const Json& j, const char* key, const std::string& where) {
  const Json& v = member(j, key, where);
  if (!v.is_number()) throw wrong_type(key, where, "a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw WitnessError(fmt::format("witness: field '{}{}' is not finite", where, key));
  return d;
}

// j[key] as a list of finite numbers, of expected_size values unless that is -1.
std::vector<double> numbers(const Json& j, const char* key, const std::string& where, std::size_t expected_size) {
  const Json& a = member(j, key, where);
  if (!a.is_array()) throw wrong_type(key, where, "an array of numbers");
  if (expected_size != static_cast<std::size_t>(-1) && a.size() != expected_size)
    throw WitnessError(
        fmt::format("witness: field '{}{}' has {} values, expected {}", where, key, a.size(), expected_size));
  std::vector<double> v;
  v.reserve(a.size());
  for (const Json& x : a) {
    if (!x.is_number()) throw wrong_type(key, where, "an array of numbers");
    v.push_back(x.get<double>());
    if (!std::isfinite(v.back()))
      throw WitnessError(fmt::format("witness: field '{}{}' holds a non-finite value", where, key));
  }
  return v;
}

// Where a JSON text failed to parse, and why: nlohmann's SAX interface reports the byte offset
// of every error, the number overflow ("1e999", out_of_range.406) included, which its DOM
// parser throws without one.
struct ParseErrorLocator final : nlohmann::json_sax<Json> {
  std::size_t position = 0;
  std::string cause;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t pos, const std::string&, const nlohmann::detail::exception& ex) override {
    position = pos;
    cause = ex.what();
    // nlohmann's what() is "[json.exception.KIND.ID] parse error at line L, column C: CAUSE" or
    // "[json.exception.KIND.ID] CAUSE": keep CAUSE (the location is reported separately).
    if (const auto b = cause.find("] "); b != std::string::npos) cause.erase(0, b + 2);
    if (cause.rfind("parse error", 0) == 0)
      if (const auto c = cause.find(": "); c != std::string::npos) cause.erase(0, c + 2);
    return false;
  }
};

}  // namespace

Witness witness_from_text(std::string_view text) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {
    ParseErrorLocator where;
    Json::sax_parse(text, &where);
    if (where.cause.empty()) where.cause = e.what();  // (the SAX pass found nothing: keep the original)
    // Line and column of the byte (1-based, as editors count).
    const std::size_t at = std::min(where.position, text.size());
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < at; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw WitnessError(
        fmt::format("JSON error at byte {} (line {}, column {}): {}", where.position, line, column, where.cause));
  }
  return witness_from_json(j);
}

Witness make_witness(const System& system, std::string method, std::int64_t trial_seed, Trajectory trajectory) {
  const SystemInfo& info = system.info();
  Witness w;
  w.suite = info.suite;
  w.instance = info.instance;
  w.method = std::move(method);
  w.trial_seed = trial_seed;
  w.state_names = info.state_names;
  w.input_names = info.input_names;
  w.trajectory = std::move(trajectory);
  if (info.sparse_witness_states) {
    // States only where the input changes (and at the ends): the validator re-simulates every
    // piece from its own state anyway, and compares the states that are recorded.
    auto& pieces = w.trajectory.pieces;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const bool starts = i == 0 || pieces[i].u != pieces[i - 1].u;
      const bool ends = i + 1 == pieces.size() || pieces[i].u != pieces[i + 1].u;
      if (!starts) std::vector<double>().swap(pieces[i].x_start);
      if (!ends) std::vector<double>().swap(pieces[i].x_end);
    }
  }
  if (info.requirement) w.requirement = WitnessRequirement{info.requirement->id, info.requirement->text, 0.0};
  return w;
}

Json to_json(const Witness& w) {
  const Trajectory& t = w.trajectory;
  Json pieces = Json::array();
  for (const auto& p : t.pieces) {
    Json piece = {{"mode", p.mode}, {"u", vec(p.u)}, {"duration", p.duration}};
    if (!p.x_start.empty()) piece["x_start"] = vec(p.x_start);  // not recorded: left out
    if (!p.x_end.empty()) piece["x_end"] = vec(p.x_end);
    piece["transition"] = p.transition;
    pieces.push_back(std::move(piece));
  }
  Json j = {{"format", "hyfal-witness/1"},
            {"suite", w.suite},
            {"instance", w.instance},
            {"method", w.method},
            {"trial_seed", w.trial_seed},
            {"parameters", vec(t.parameters)},
            {"state_names", w.state_names},
            {"input_names", w.input_names},
            {"initial", {{"mode", t.initial_mode}, {"x", vec(t.initial_x)}}},
            {"pieces", pieces},
            {"final", {{"mode", t.final_mode}, {"x", vec(t.final_x)}, {"spec", t.final_spec}}}};
  if (w.requirement)
    j["requirement"] = {
        {"id", w.requirement->id}, {"formula", w.requirement->formula}, {"robustness", w.requirement->robustness}};
  if (t.linear_input) {
    Json values = Json::array();
    for (const auto& v : t.linear_input->values) values.push_back(vec(v));
    j["input_signal"] = {{"shape", "linear"},
                         {"times", vec(t.linear_input->times)},
                         {"values", values},
                         {"piece", t.linear_input->piece}};
  }
  return j;
}

Witness witness_from_json(const Json& j) {
  if (!j.is_object()) throw WitnessError("witness: the document is not a JSON object");
  if (field<std::string>(j, "format", "") != "hyfal-witness/1")
    throw WitnessError("witness: field 'format' is not \"hyfal-witness/1\"");
  Witness w;
  w.suite = field<std::string>(j, "suite", "");
  if (!member(j, "instance", "").is_object()) throw wrong_type("instance", "", "an object");
  w.instance = j.at("instance");
  w.method = field<std::string>(j, "method", "");
  w.trial_seed = integer_field<std::int64_t>(j, "trial_seed", "", std::numeric_limits<std::int64_t>::min(),
                                             std::numeric_limits<std::int64_t>::max());
  w.state_names = field<std::vector<std::string>>(j, "state_names", "");
  w.input_names = field<std::vector<std::string>>(j, "input_names", "");
  const std::size_t n = w.state_names.size(), m = w.input_names.size();
  Trajectory& t = w.trajectory;
  constexpr Mode kModeMax = std::numeric_limits<Mode>::max();
  t.parameters = numbers(j, "parameters", "", static_cast<std::size_t>(-1));
  const Json& initial = member(j, "initial", "");
  t.initial_mode = integer_field<Mode>(initial, "mode", "initial.", 0, kModeMax);
  t.initial_x = numbers(initial, "x", "initial.", n);
  const Json& pieces = member(j, "pieces", "");
  if (!pieces.is_array()) throw wrong_type("pieces", "", "an array");
  t.pieces.reserve(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Json& pj = pieces[i];
    const std::string where = fmt::format("pieces[{}].", i);
    TrajectoryPiece p;
    p.mode = integer_field<Mode>(pj, "mode", where, 0, kModeMax);
    p.u = numbers(pj, "u", where, m);
    p.duration = number_field(pj, "duration", where);
    if (!(p.duration >= 0.0)) throw WitnessError(fmt::format("witness: field '{}duration' must be >= 0", where));
    // Optional (SystemInfo::sparse_witness_states): a piece may leave its states out.
    if (pj.contains("x_start")) p.x_start = numbers(pj, "x_start", where, n);
    if (pj.contains("x_end")) p.x_end = numbers(pj, "x_end", where, n);
    // -1: no transition at the end of the piece; otherwise a guard index of the piece's mode.
    p.transition = pj.contains("transition")
                       ? integer_field<int>(pj, "transition", where, -1, std::numeric_limits<int>::max())
                       : -1;
    t.pieces.push_back(std::move(p));
  }
  const Json& final_j = member(j, "final", "");
  t.final_mode = integer_field<Mode>(final_j, "mode", "final.", 0, kModeMax);
  t.final_x = numbers(final_j, "x", "final.", n);
  t.final_spec = number_field(final_j, "spec", "final.");
  if (j.contains("requirement")) {
    const Json& rj = member(j, "requirement", "");
    w.requirement = WitnessRequirement{field<std::string>(rj, "id", "requirement."),
                                       field<std::string>(rj, "formula", "requirement."),
                                       number_field(rj, "robustness", "requirement.")};
  }
  if (j.contains("input_signal")) {
    const Json& sj = member(j, "input_signal", "");
    if (!sj.is_object()) throw wrong_type("input_signal", "", "an object");
    if (field<std::string>(sj, "shape", "input_signal.") != "linear")
      throw WitnessError("witness: field 'input_signal.shape' is not \"linear\" (the only declared input signal)");
    LinearInput in;
    in.times = numbers(sj, "times", "input_signal.", static_cast<std::size_t>(-1));
    const Json& values = member(sj, "values", "input_signal.");
    if (!values.is_array()) throw wrong_type("values", "input_signal.", "an array of arrays of numbers");
    if (values.size() != in.times.size())
      throw WitnessError(
          fmt::format("witness: field 'input_signal.values' has {} control points, 'input_signal.times' {}",
                      values.size(), in.times.size()));
    for (std::size_t k = 0; k < values.size(); ++k) {
      const std::string where = fmt::format("input_signal.values[{}]", k);
      if (!values[k].is_array()) throw wrong_type("", where, "an array of numbers");
      std::vector<double> v;
      for (const Json& x : values[k]) {
        if (!x.is_number() || !std::isfinite(x.get<double>()))
          throw wrong_type("", where, "an array of finite numbers");
        v.push_back(x.get<double>());
      }
      if (v.size() != m)
        throw WitnessError(fmt::format("witness: field '{}' has {} values, expected {}", where, v.size(), m));
      in.values.push_back(std::move(v));
    }
    in.piece = number_field(sj, "piece", "input_signal.");
    if (!(in.piece > 0.0)) throw WitnessError("witness: field 'input_signal.piece' must be > 0");
    t.linear_input = std::move(in);
  }
  return w;
}

}  // namespace hyfal
