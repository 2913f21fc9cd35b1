// hyfal's one error hierarchy. Every failure hyfal reports to a user has one of two causes, and
// each edge turns the cause into its own convention in one place (app/main.cpp: report_failure;
// python/module.cpp: the exception translator):
//
//   cause         | C++ base          | CLI                      | Python
//   --------------|-------------------|--------------------------|------------------------------
//   the input     | InputError        | one line, exit 2         | hyfal.InputError (ValueError)
//   the machine   | EnvironmentError  | one line, exit 3; a      | hyfal.EnvironmentError (OSError)
//                 |                   | rerun resumes            |
//
// Beneath them (each reaches Python as hyfal.<name>, a subclass of its base's class):
//   InputError:       OptionError (core/run/option_spec.hpp), RequirementError (core/requirements),
//                     WitnessError (core/witness/witness.hpp), ExperimentFileError (app), UsageError and
//                     MethodNotApplicable (app), StoreInputError (results), ClusterSetupError
//                     (parallel)
//   EnvironmentError: StoreEnvironmentError (results), ClusterFailure (parallel)
// StoreError and ClusterError are the mixins their two subclasses share (a catch of either sees
// both kinds); they are no std::exception of their own, so a catch of std::exception sees each
// failure once.
//
// Anything else that escapes (std::logic_error, a std::bad_alloc...) is a bug or a resource the
// process could not get: exit 1 on the CLI, pybind11's own translation in Python.
#pragma once
#include <exception>
#include <stdexcept>

namespace hyfal {

enum class ErrorKind {
  input,        // the user's input is wrong; nothing was written
  environment,  // the machine failed (a disk, a database, a peer); what was stored stands
};

// The mixin every hyfal error carries: its cause and the name its Python class has.
class Error {
 public:
  virtual ~Error() = default;
  virtual ErrorKind error_kind() const noexcept = 0;
  // The class's name in the Python module (hyfal.<name>), e.g. "OptionError".
  virtual const char* name() const noexcept = 0;
};

// A bad input: a setting, a formula, a file, a command line. std::invalid_argument beneath, so
// that code validating a suite's or method's settings catches it with the library's own errors.
class InputError : public std::invalid_argument, public Error {
 public:
  using std::invalid_argument::invalid_argument;
  ErrorKind error_kind() const noexcept final { return ErrorKind::input; }
  const char* name() const noexcept override { return "InputError"; }
};

// A failure of the machine, not of the input or of a trial: a file that cannot be written (disk
// full, permission lost, its folder gone), a database the disk failed, a peer that vanished. A
// run cannot keep the trial's result, so it stops; a rerun resumes.
class EnvironmentError : public std::runtime_error, public Error {
 public:
  using std::runtime_error::runtime_error;
  ErrorKind error_kind() const noexcept final { return ErrorKind::environment; }
  const char* name() const noexcept override { return "EnvironmentError"; }
};

// The hyfal error behind e, or nullptr when e is none of hyfal's (a bug, std::bad_alloc).
inline const Error* hyfal_error(const std::exception& e) noexcept { return dynamic_cast<const Error*>(&e); }

// The CLI's exit code for e: 2 for an input error, 3 for an environment error, 1 for anything else.
inline int exit_code_of(const std::exception& e) noexcept {
  const Error* h = hyfal_error(e);
  if (!h) return 1;
  return h->error_kind() == ErrorKind::input ? 2 : 3;
}

}  // namespace hyfal
