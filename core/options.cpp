#include "core/options.hpp"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>

namespace hyfal {

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

bool has_option(const std::vector<OptionSpec>& specs, const std::string& key) {
  for (const auto& s : specs)
    if (s.key == key) return true;
  return false;
}

Json resolve_options(const std::vector<OptionSpec>& specs,
                     const std::vector<std::pair<std::string, std::string>>& sets) {
  Json out = Json::object();
  for (const auto& s : specs) out[s.key] = s.default_value;
  for (const auto& [key, text] : sets) {
    const OptionSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.key == key) spec = &s;
    if (!spec) throw OptionError(fmt::format("unknown setting '{}'", key));
    out[key] = parse_option_value(key, text, spec->default_value);
  }
  return out;
}

}  // namespace hyfal
