// The Python module `hyfal`: STL robustness on numpy arrays, the suites' models, falsification
// through the app library's runner, and the results database as numpy columns. A thin layer: every
// computation is the C++ library's (core/requirements, suites/registry, app/runner with
// parallel/trial_engine, results/store). This file holds the module and the translation of
// hyfal's errors (core/util/error.hpp) into Python classes; the bindings are python/*_bindings.cpp,
// their shared conversions python/conversions.hpp.
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <pybind11/pybind11.h>

#include "app/experiment_file.hpp"
#include "app/runner.hpp"
#include "core/util/error.hpp"
#include "core/run/option_spec.hpp"
#include "core/requirements/formula.hpp"
#include "core/witness/witness.hpp"
#include "parallel/cluster.hpp"
#include "python/bindings.hpp"
#include "results/store.hpp"

#ifndef HYFAL_VERSION
#define HYFAL_VERSION "0"
#endif

namespace hyfal::python {
namespace {

namespace py = pybind11;

// Each C++ error class of core/util/error.hpp as a Python class: its name (Error::name()), its bases
// in the module (or Python's own for the two roots and the mixins) and its docstring.
struct ErrorClass {
  const char* name;
  std::vector<const char*> bases;  // names in this table, or "ValueError", "OSError", "Exception"
  const char* doc;
};

const std::vector<ErrorClass>& error_classes() {
  static const std::vector<ErrorClass> classes = {
      {"InputError", {"ValueError"}, "A bad input: nothing was run or written (the CLI's exit 2)."},
      {"EnvironmentError",
       {"OSError"},
       "The machine failed (a disk, a database, a peer); what was stored stands and the same call resumes "
       "(the CLI's exit 3)."},
      {"OptionError", {"InputError"}, "A setting that does not resolve: an unknown key, a wrong type, out of range."},
      {"RequirementError",
       {"InputError"},
       "A formula that cannot be parsed; its attribute `column` is the 1-based column in the formula's text."},
      {"WitnessError", {"InputError"}, "A witness that cannot be read: a field missing, mistyped or out of range."},
      {"ExperimentFileError", {"InputError"}, "A table or experiment file that cannot be used."},
      {"UsageError", {"InputError"}, "A request the runner refuses (an unknown suite or method, a bad name...)."},
      {"MethodNotApplicable", {"UsageError"}, "A method that cannot drive the system at all."},
      {"StoreError",
       {"Exception"},
       "Any failure of a results database (StoreInputError or StoreEnvironmentError); `sqlite_code` is "
       "SQLite's result code behind it, 0 when none."},
      {"StoreInputError", {"InputError", "StoreError"}, "A path that is not a usable hyfal results database."},
      {"StoreEnvironmentError",
       {"EnvironmentError", "StoreError"},
       "The machine failed a results database that was fine (disk full, I/O error, locked too long)."},
      {"ClusterError", {"Exception"}, "A failure of a distributed run (ClusterSetupError or ClusterFailure)."},
      {"ClusterSetupError", {"InputError", "ClusterError"}, "A distributed run's set-up the user can fix."},
      {"ClusterFailure", {"EnvironmentError", "ClusterError"}, "A rank or peer of a distributed run failed."},
  };
  return classes;
}

// The Python classes, by name (made once, at import; they live as long as the module).
std::map<std::string, py::object, std::less<>>& python_classes() {
  static auto* classes = new std::map<std::string, py::object, std::less<>>();
  return *classes;
}

py::object builtin_class(std::string_view name) {
  if (name == "ValueError") return py::reinterpret_borrow<py::object>(PyExc_ValueError);
  if (name == "OSError") return py::reinterpret_borrow<py::object>(PyExc_OSError);
  return py::reinterpret_borrow<py::object>(PyExc_Exception);
}

// "--set key=value: ..." (the CLI's wording) without the flag: from Python the key was a keyword.
std::string without_set_flag(std::string message) {
  if (message.rfind("--set ", 0) == 0) message.erase(0, 6);
  return message;
}

// Raises e as its Python class: the class of its name, else the class of its kind (a subclass
// this module does not list still arrives as InputError or EnvironmentError).
void raise_as_python(const std::exception& e, const Error& h) {
  auto& classes = python_classes();
  auto it = classes.find(h.name());
  if (it == classes.end()) it = classes.find(h.error_kind() == ErrorKind::input ? "InputError" : "EnvironmentError");
  std::string message = e.what();
  if (dynamic_cast<const OptionError*>(&e) || dynamic_cast<const UsageError*>(&e))
    message = without_set_flag(std::move(message));
  py::object error = it->second(message);
  if (const auto* r = dynamic_cast<const stl::RequirementError*>(&e)) error.attr("column") = r->column();
  if (const auto* s = dynamic_cast<const StoreError*>(&e)) error.attr("sqlite_code") = s->sqlite_code();
  PyErr_SetObject(it->second.ptr(), error.ptr());
}

// Throws the C++ error of that name (every class of error_classes() that is no mixin): the
// test hook hyfal._raise_error, so that tests reach the translation of errors no Python call
// can provoke on a healthy machine (a failing disk, a lost peer).
[[noreturn]] void raise_cpp_error(const std::string& name, const std::string& message) {
  if (name == "InputError") throw InputError(message);
  if (name == "EnvironmentError") throw EnvironmentError(message);
  if (name == "OptionError") throw OptionError(message);
  if (name == "RequirementError") throw stl::RequirementError(7, message);
  if (name == "WitnessError") throw WitnessError(message);
  if (name == "ExperimentFileError") throw ExperimentFileError(message);
  if (name == "UsageError") throw UsageError(message);
  if (name == "MethodNotApplicable") throw MethodNotApplicable(message);
  if (name == "StoreInputError") throw_store_error(StoreErrorKind::bad_input, message, 26);
  if (name == "StoreEnvironmentError") throw_store_error(StoreErrorKind::environment, message, 13);
  if (name == "ClusterSetupError") throw ClusterSetupError(message);
  if (name == "ClusterFailure") throw ClusterFailure(message);
  throw std::logic_error("no hyfal error is called " + name);
}

}  // namespace

void bind_errors(py::module_& m) {
  auto& classes = python_classes();
  for (const ErrorClass& c : error_classes()) {
    py::tuple bases(c.bases.size());
    for (std::size_t i = 0; i < c.bases.size(); ++i) {
      const auto it = classes.find(c.bases[i]);
      bases[i] = it != classes.end() ? it->second : builtin_class(c.bases[i]);
    }
    const std::string qualified = std::string("hyfal.") + c.name;
    py::object cls =
        py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(qualified.c_str(), c.doc, bases.ptr(), nullptr));
    if (!cls) throw py::error_already_set();
    m.attr(c.name) = cls;
    classes.emplace(c.name, std::move(cls));
  }
  m.def("_raise_error", &raise_cpp_error, py::arg("name"), py::arg("message"),
        "Test hook: raises the C++ error of that name through the module's translation.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::exception& e) {
      const Error* h = hyfal_error(e);
      if (!h) throw;  // not hyfal's: pybind11's own translation (std::invalid_argument: ValueError...)
      raise_as_python(e, *h);
    }
  });
}

}  // namespace hyfal::python

PYBIND11_MODULE(hyfal, m) {
  namespace py = pybind11;
  using namespace hyfal;
  m.doc() =
      "hyfal: falsification of hybrid systems (STL robustness on numpy arrays, the suites' models, the falsifiers "
      "of `hyfal run`, and results databases as numpy columns). See the README's Python section.";
  m.attr("__version__") = HYFAL_VERSION;
  python::bind_errors(m);
  python::bind_stl(m);
  python::bind_suites(m);
  python::bind_black_box(m);
  python::bind_falsify(m);
}
