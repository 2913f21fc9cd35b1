// A suite: one benchmark system family. Its instance parameters (key, default, help) are
// resolved into a canonical JSON instance key, from which it builds a System.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/model/system.hpp"
#include "core/run/option_spec.hpp"

namespace hyfal {

struct SuiteEntry {
  std::string name;
  std::string description;
  std::vector<OptionSpec> parameters;
  // Builds the system of a resolved instance; throws std::invalid_argument on bad values.
  std::function<std::shared_ptr<const System>(const Json& instance)> make;
  // The instance as JSON for outside tools (`hyfal instance export`); empty: SystemInfo only.
  std::function<Json(const Json& instance)> export_instance = {};
};

}  // namespace hyfal
