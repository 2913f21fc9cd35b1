#include "suites/registry.hpp"

#include <string>
#include <utility>

#include "core/requirements/requirement.hpp"

namespace hyfal {

namespace {

// Every suite's last instance parameter: the STL requirement to falsify. Empty (the default) is
// reachability of the suite's unsafe set, and is left out of the instance key (unkeyed_value),
// so the keys (and the trial seeds drawn from them) of every reachability run stay as they were.
SuiteEntry with_requirement_parameter(SuiteEntry s) {
  s.parameters.push_back({"requirement", "",
                          "STL requirement to falsify: the id of one the suite declares (hyfal list) or a formula over "
                          "its signals (docs/requirements.md); empty: reach the unsafe set",
                          "", ""});
  s.make = [make = std::move(s.make), parameters = s.parameters](const Json& instance) {
    return stl::with_requirement(make(canonical_instance(parameters, instance)), instance.value("requirement", std::string()));
  };
  return s;
}

}  // namespace

const std::vector<SuiteEntry>& all_suites() {
  static const std::vector<SuiteEntry> suites = [] {
    std::vector<SuiteEntry> all = {
        thermostat_suite(),
        example31_suite(),
        linear_suite(),
        hovercraft_suite(),
        guard_intruder_suite(),
        navigation_suite(),
        blimp_suite(),
        aircraft_suite(),
        at_suite(),
        cc_suite(),
    };
    for (auto& s : all) s = with_requirement_parameter(std::move(s));
    return all;
  }();
  return suites;
}

Json canonical_instance(const std::vector<OptionSpec>& parameters, Json instance) {
  for (const OptionSpec& p : parameters)
    if (p.unkeyed_value && instance.contains(p.key) && instance[p.key] == *p.unkeyed_value) instance.erase(p.key);
  return instance;
}

const SuiteEntry* find_suite(std::string_view name) {
  for (const auto& s : all_suites())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace hyfal
