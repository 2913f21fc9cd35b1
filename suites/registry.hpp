// The suite registry: a new suite is one file under suites/ plus one line in registry.cpp.
#pragma once
#include <string_view>
#include <vector>

#include "core/suite.hpp"

namespace hyfal {

SuiteEntry thermostat_suite();
SuiteEntry example31_suite();
SuiteEntry linear_suite();
SuiteEntry hovercraft_suite();
SuiteEntry guard_intruder_suite();
SuiteEntry navigation_suite();
SuiteEntry blimp_suite();
SuiteEntry aircraft_suite();
SuiteEntry at_suite();
SuiteEntry cc_suite();
SuiteEntry f16_suite();
SuiteEntry afc_suite();
SuiteEntry nn_suite();
SuiteEntry sc_suite();

const std::vector<SuiteEntry>& all_suites();
// A resolved instance as its key: the parameters at their unkeyed value (OptionSpec::unkeyed_value:
// the empty requirement, the behaviour before a parameter was added) left out.
Json canonical_instance(const std::vector<OptionSpec>& parameters, Json instance);
const SuiteEntry* find_suite(std::string_view name);

}  // namespace hyfal
