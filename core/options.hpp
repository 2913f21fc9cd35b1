// Resolving `key=value` settings against declared options (suite parameters, method options).
#pragma once
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/planner.hpp"

namespace hyfal {

class OptionError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Parses `text` as a value of the same JSON type as `like` (integer, number, bool, string,
// array); throws OptionError naming `key` otherwise.
Json parse_option_value(const std::string& key, const std::string& text, const Json& like);

// Defaults of `specs` overridden by `sets`; every key of `sets` must be declared in `specs`.
Json resolve_options(const std::vector<OptionSpec>& specs,
                     const std::vector<std::pair<std::string, std::string>>& sets);

bool has_option(const std::vector<OptionSpec>& specs, const std::string& key);

}  // namespace hyfal
