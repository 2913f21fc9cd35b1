#include "suites/registry.hpp"

namespace hyfal {

const std::vector<SuiteEntry>& all_suites() {
  static const std::vector<SuiteEntry> suites = {
      thermostat_suite(),
      example31_suite(),
      linear_suite(),
      hovercraft_suite(),
      guard_intruder_suite(),
      navigation_suite(),
      blimp_suite(),
      aircraft_suite(),
  };
  return suites;
}

const SuiteEntry* find_suite(std::string_view name) {
  for (const auto& s : all_suites())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace hyfal
