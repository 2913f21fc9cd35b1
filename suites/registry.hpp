// The suite registry: a new suite is one folder under suites/ (NAME/NAME.cpp defining
// `SuiteEntry NAME_suite()`, and NAME/CMakeLists.txt) plus one line hyfal_suite(NAME) in
// suites/CMakeLists.txt, which generates the list registry.cpp expands.
#pragma once
#include <string_view>
#include <vector>

#include "core/run/suite_entry.hpp"

namespace hyfal {

const std::vector<SuiteEntry>& all_suites();
// A resolved instance as its key: the parameters at their unkeyed value (OptionSpec::unkeyed_value:
// the empty requirement, the behaviour before a parameter was added) left out.
Json canonical_instance(const std::vector<OptionSpec>& parameters, Json instance);
const SuiteEntry* find_suite(std::string_view name);

}  // namespace hyfal
