// Witness: a trajectory with what it falsifies (suite, instance, method, seed, requirement), and
// its JSON file format (hyfal-witness/1; see README).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/system.hpp"
#include "core/util/error.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

// An STL witness's requirement (instance parameter `requirement`): as named and as written, and
// the robustness of the witness's trace as the validator re-simulates and samples it (< 0).
struct WitnessRequirement {
  std::string id;  // "" for a formula given inline
  std::string formula;
  double robustness = 0.0;
};

struct Witness {
  std::string suite;
  Json instance;
  std::string method;
  std::int64_t trial_seed = 0;
  std::vector<std::string> state_names, input_names;
  Trajectory trajectory;
  std::optional<WitnessRequirement> requirement;  // STL witnesses only
};

// The witness of a trajectory of `system`, with the names and instance the system declares.
Witness make_witness(const System& system, std::string method, std::int64_t trial_seed, Trajectory trajectory);

// A witness file that cannot be read: not JSON, or a field missing, mistyped or out of range.
class WitnessError : public InputError {
 public:
  using InputError::InputError;
  const char* name() const noexcept override { return "WitnessError"; }
};

Json to_json(const Witness& w);
// Throws WitnessError naming the first missing or malformed field: a missing member, a wrong
// JSON type, a non-finite number, a vector whose length differs from state_names/input_names, an
// integer (mode, transition, seed) outside its type's range (never wrapped).
Witness witness_from_json(const Json& j);
// witness_from_json of a file's text; a JSON syntax error or a number beyond double's range
// (1e999) is a WitnessError giving where the parser stopped (byte offset, line and column, all
// counted from 1) and the cause. Throws nothing else.
Witness witness_from_text(std::string_view text);

}  // namespace hyfal
