// Resolving `key=value` settings against declared options (suite parameters, method options):
// the one validation layer every entry point (run, reproduce, validate, instance export) uses.
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/model/system.hpp"
#include "core/util/error.hpp"

namespace hyfal {

// A declared setting (a method option or a suite's instance parameter): key, default (its JSON
// type is the setting's type), help text and the valid values, declared once beside the default
// (as OMPL's declareParam does with a range string):
//   "[1, 1000]", "(0, 1]", "[0, inf)"  an interval (integers and numbers; inf allowed as a bound)
//   "metric|t2go"                      the allowed strings
//   ""                                 any value of the type (booleans, and the `requirement` text,
//                                      which its parser checks; a test checks)
// The functions below check values against it; `hyfal list` prints it.
struct OptionSpec {
  std::string key;
  Json default_value;
  std::string help;
  std::string range = {};
  // A suite parameter or method option added after results were stored: at this value (the
  // behaviour before it existed) it is left out of the instance key, or of the options in the
  // trial's config (canonical_instance), so stored keys, and the trial seeds drawn from them, keep
  // meaning what they meant. Unset: always keyed.
  std::optional<Json> unkeyed_value = std::nullopt;
};

// A setting that does not resolve: an unknown key, a value of the wrong type or out of range.
class OptionError : public InputError {
 public:
  using InputError::InputError;
  const char* name() const noexcept override { return "OptionError"; }
};

// The valid values of a setting, parsed from OptionSpec::range (above).
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
