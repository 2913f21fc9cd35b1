// Resolving `key=value` settings against declared options (suite parameters, method options):
// the one validation layer every entry point (run, reproduce, validate, instance export) uses.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/planner.hpp"

namespace hyfal {

// A setting that does not resolve: an unknown key, a value of the wrong type or out of range.
class OptionError : public InputError {
 public:
  using InputError::InputError;
  const char* name() const noexcept override { return "OptionError"; }
};

// The valid values of a setting, parsed from OptionSpec::range (see core/planner.hpp).
struct ValueRange {
  enum class Kind { any, interval, choices } kind = Kind::any;
  double lo = 0.0, hi = 0.0;  // interval bounds (may be infinite)
  bool lo_open = false, hi_open = false;
  std::vector<std::string> choices;

  // Throws std::logic_error on a malformed range text (a programming error in a declaration).
  static ValueRange parse(std::string_view text);
  bool contains(const Json& value) const;
};

// Parses `text` as a value of the same JSON type as `like` (integer, number, bool, string,
// array); throws OptionError naming `key` otherwise.
Json parse_option_value(const std::string& key, const std::string& text, const Json& like);

// Parses `text` for `spec` (its type, then its range); throws OptionError
// "--set key=text: key must be in [lo, hi]" (or "one of a|b") otherwise.
Json parse_setting(const OptionSpec& spec, const std::string& text);

// Defaults of `specs` overridden by `sets`; every key of `sets` must be declared in `specs`,
// given once, and its value must be of the declared type and inside the declared range.
Json resolve_options(const std::vector<OptionSpec>& specs,
                     const std::vector<std::pair<std::string, std::string>>& sets);

bool has_option(const std::vector<OptionSpec>& specs, const std::string& key);

// "must be in [1, 1000]" / "must be one of metric|t2go" / "" (any): for messages and `hyfal list`.
std::string describe_range(const OptionSpec& spec);

}  // namespace hyfal
