#include "core/run/option_spec.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

namespace hyfal {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

double parse_bound(std::string_view s, std::string_view range) {
  s = trim(s);
  if (s == "inf" || s == "+inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size())
    throw std::logic_error(fmt::format("malformed range '{}': bound '{}'", range, s));
  return v;
}

}  // namespace

ValueRange ValueRange::parse(std::string_view text) {
  ValueRange r;
  const std::string_view t = trim(text);
  if (t.empty()) return r;
  if (t.front() == '[' || t.front() == '(') {
    const auto comma = t.find(',');
    if (comma == std::string_view::npos || (t.back() != ']' && t.back() != ')'))
      throw std::logic_error(fmt::format("malformed range '{}'", text));
    r.kind = Kind::interval;
    r.lo_open = t.front() == '(';
    r.hi_open = t.back() == ')';
    r.lo = parse_bound(t.substr(1, comma - 1), text);
    r.hi = parse_bound(t.substr(comma + 1, t.size() - comma - 2), text);
    if (!(r.lo <= r.hi)) throw std::logic_error(fmt::format("malformed range '{}': lo > hi", text));
    return r;
  }
  r.kind = Kind::choices;
  std::size_t start = 0;
  while (start <= t.size()) {
    const auto bar = t.find('|', start);
    const std::string_view choice =
        trim(t.substr(start, bar == std::string_view::npos ? std::string_view::npos : bar - start));
    if (choice.empty()) throw std::logic_error(fmt::format("malformed range '{}': empty choice", text));
    r.choices.emplace_back(choice);
    if (bar == std::string_view::npos) break;
    start = bar + 1;
  }
  return r;
}

bool ValueRange::contains(const Json& v) const {
  switch (kind) {
    case Kind::any:
      return true;
    case Kind::interval: {
      if (!v.is_number()) return false;
      const double x = v.get<double>();
      if (std::isnan(x)) return false;
      if (lo_open ? !(x > lo) : !(x >= lo)) return false;
      if (hi_open ? !(x < hi) : !(x <= hi)) return false;
      return true;
    }
    case Kind::choices:
      if (!v.is_string()) return false;
      for (const auto& c : choices)
        if (v.get_ref<const std::string&>() == c) return true;
      return false;
  }
  return false;
}

std::string describe_range(const OptionSpec& spec) {
  const ValueRange r = ValueRange::parse(spec.range);
  switch (r.kind) {
    case ValueRange::Kind::any:
      return "";
    case ValueRange::Kind::interval:
      return fmt::format("must be in {}", spec.range);
    case ValueRange::Kind::choices:
      return fmt::format("must be one of {}", spec.range);
  }
  return "";
}

Json parse_option_value(const std::string& key, const std::string& text, const Json& like) {
  Json v;
  try {
    v = Json::parse(text);
  } catch (const Json::exception&) {  // not JSON, or a number out of range: a bare string
    v = text;
  }
  const auto bad = [&](const char* what) {
    return OptionError(fmt::format("--set {}={}: expected {}", key, text, what));
  };
  if (like.is_number_integer()) {
    // Integer settings are counts and sizes: they must fit a 32-bit int.
    if (!v.is_number_integer()) throw bad("an integer");
    const auto i = v.get<std::int64_t>();
    if (v.is_number_unsigned() && v.get<std::uint64_t>() > 2147483647ULL) throw bad("an integer below 2^31");
    if (i > 2147483647LL || i < -2147483647LL) throw bad("an integer of magnitude below 2^31");
    return v;
  }
  if (like.is_number()) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) throw bad("a finite number");
    return Json(v.get<double>());
  }
  if (like.is_boolean()) {
    if (!v.is_boolean()) throw bad("true or false");
    return v;
  }
  if (like.is_array()) {
    if (!v.is_array()) throw bad("a JSON array");
    return v;
  }
  if (like.is_string()) return Json(text);
  return v;
}

Json parse_setting(const OptionSpec& spec, const std::string& text) {
  Json v = parse_option_value(spec.key, text, spec.default_value);
  if (!ValueRange::parse(spec.range).contains(v))
    throw OptionError(fmt::format("--set {}={}: {} {}", spec.key, text, spec.key, describe_range(spec)));
  return v;
}

bool has_option(const std::vector<OptionSpec>& specs, const std::string& key) {
  for (const auto& s : specs)
    if (s.key == key) return true;
  return false;
}

Json resolve_options(const std::vector<OptionSpec>& specs,
                     const std::vector<std::pair<std::string, std::string>>& sets) {
  Json out = Json::object();
  for (const auto& s : specs) out[s.key] = s.default_value;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const auto& [key, text] = sets[i];
    const OptionSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.key == key) spec = &s;
    if (!spec) throw OptionError(fmt::format("unknown setting '{}'", key));
    for (std::size_t j = 0; j < i; ++j)
      if (sets[j].first == key)
        throw OptionError(fmt::format("--set {}: given twice ({} and {})", key, sets[j].second, text));
    out[key] = parse_setting(*spec, text);
  }
  return out;
}

}  // namespace hyfal
