#include "suites/registry.hpp"

#include <string>
#include <utility>

#include "core/requirements/requirement.hpp"
#include "suite_list.hpp"  // generated: HYFAL_SUITES(X), one X(NAME) per hyfal_suite line

namespace hyfal {

#define HYFAL_DECLARE_SUITE(name) SuiteEntry name##_suite();
HYFAL_SUITES(HYFAL_DECLARE_SUITE)
#undef HYFAL_DECLARE_SUITE

namespace {

// Every suite's last instance parameters: the STL requirement to falsify and its margin. Empty (the default) is
// reachability of the suite's unsafe set, and is left out of the instance key (unkeyed_value),
// so the keys (and the trial seeds drawn from them) of every reachability run stay as they were.
SuiteEntry with_requirement_parameter(SuiteEntry s) {
  // Left out of the key at 0 (every run before the parameter existed).
  s.parameters.push_back({"margin", 0.0,
                          "STL requirements: a run falsifies only at robustness <= -margin (every comparison of the "
                          "requirement tightened by it, formula.hpp with_margin), so a witness survives a simulator a "
                          "little off; robustness is then reported for the tightened requirement",
                          "[0, 1e12]", 0.0});
  s.parameters.push_back({"requirement", "",
                          "STL requirement to falsify: the id of one the suite declares (hyfal list) or a formula over "
                          "its signals (docs/requirements.md); empty: reach the unsafe set",
                          "", ""});
  s.make = [make = std::move(s.make), parameters = s.parameters](const Json& instance) {
    return stl::with_requirement(make(canonical_instance(parameters, instance)), instance.value("requirement", std::string()),
                                 instance.value("margin", 0.0));
  };
  return s;
}

}  // namespace

const std::vector<SuiteEntry>& all_suites() {
  static const std::vector<SuiteEntry> suites = [] {
#define HYFAL_SUITE_ENTRY(name) name##_suite(),
    std::vector<SuiteEntry> all = {HYFAL_SUITES(HYFAL_SUITE_ENTRY)};
#undef HYFAL_SUITE_ENTRY
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
