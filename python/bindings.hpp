// The bindings of the Python module `hyfal`, one function per file; python/module.cpp calls them.
#pragma once
#include <pybind11/pybind11.h>

namespace hyfal::python {

void bind_stl(pybind11::module_& m);        // python/stl_bindings.cpp
void bind_suites(pybind11::module_& m);     // python/suite_bindings.cpp
void bind_black_box(pybind11::module_& m);  // python/black_box_bindings.cpp
void bind_falsify(pybind11::module_& m);    // python/falsify_bindings.cpp
// The error classes of core/util/error.hpp and their translation (python/module.cpp).
void bind_errors(pybind11::module_& m);

}  // namespace hyfal::python
