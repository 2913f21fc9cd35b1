// The one error hierarchy (core/util/error.hpp): every hyfal error is an InputError (exit 2) or an
// EnvironmentError (exit 3), the mixins see both of their kinds, and a catch of std::exception
// sees each failure once.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/experiment_file.hpp"
#include "app/runner.hpp"
#include "core/util/error.hpp"
#include "core/run/option_spec.hpp"
#include "core/requirements/formula.hpp"
#include "core/witness/witness.hpp"
#include "parallel/cluster.hpp"
#include "results/store.hpp"

namespace hyfal {
namespace {

struct Case {
  std::string name;
  int exit_code;
  std::function<void()> raise;
};

std::vector<Case> every_error() {
  return {
      {"InputError", 2, [] { throw InputError("m"); }},
      {"EnvironmentError", 3, [] { throw EnvironmentError("m"); }},
      {"OptionError", 2, [] { throw OptionError("m"); }},
      {"RequirementError", 2, [] { throw stl::RequirementError(3, "m"); }},
      {"WitnessError", 2, [] { throw WitnessError("m"); }},
      {"ExperimentFileError", 2, [] { throw ExperimentFileError("m"); }},
      {"UsageError", 2, [] { throw UsageError("m"); }},
      {"MethodNotApplicable", 2, [] { throw MethodNotApplicable("m"); }},
      {"StoreInputError", 2, [] { throw_store_error(StoreErrorKind::bad_input, "m", 26); }},
      {"StoreEnvironmentError", 3, [] { throw_store_error(StoreErrorKind::environment, "m", 13); }},
      {"ClusterSetupError", 2, [] { throw ClusterSetupError("m"); }},
      {"ClusterFailure", 3, [] { throw ClusterFailure("m"); }},
  };
}

TEST(Errors, EveryTypeIsClassifiedByItsCauseAndKnowsItsName) {
  for (const Case& c : every_error()) {
    try {
      c.raise();
      FAIL() << c.name << " was not thrown";
    } catch (const std::exception& e) {
      const Error* h = hyfal_error(e);
      ASSERT_NE(h, nullptr) << c.name;
      EXPECT_EQ(std::string(h->name()), c.name);
      EXPECT_EQ(exit_code_of(e), c.exit_code) << c.name;
      EXPECT_EQ(h->error_kind() == ErrorKind::input, dynamic_cast<const InputError*>(&e) != nullptr) << c.name;
      EXPECT_EQ(h->error_kind() == ErrorKind::environment, dynamic_cast<const EnvironmentError*>(&e) != nullptr)
          << c.name;
      // Input errors stay std::invalid_argument: code that validates settings catches them all.
      EXPECT_EQ(dynamic_cast<const std::invalid_argument*>(&e) != nullptr, c.exit_code == 2) << c.name;
      EXPECT_STREQ(e.what(), c.name == "RequirementError" ? "column 3: m" : "m");
    }
  }
}

TEST(Errors, AnythingElseIsABugWithExitCodeOne) {
  EXPECT_EQ(exit_code_of(std::logic_error("x")), 1);
  EXPECT_EQ(exit_code_of(std::invalid_argument("a suite's own refusal")), 1);
  EXPECT_EQ(exit_code_of(std::runtime_error("x")), 1);
  EXPECT_EQ(hyfal_error(std::runtime_error("x")), nullptr);
}

TEST(Errors, TheStoreMixinSeesBothKindsWithTheirCodes) {
  for (const StoreErrorKind kind : {StoreErrorKind::bad_input, StoreErrorKind::environment}) {
    try {
      throw_store_error(kind, "database 'x': disk I/O error", 10);
    } catch (const StoreError& e) {
      EXPECT_EQ(e.kind(), kind);
      EXPECT_EQ(e.sqlite_code(), 10);
      EXPECT_STREQ(e.what(), "database 'x': disk I/O error");
    }
  }
  EXPECT_THROW(throw_store_error(StoreErrorKind::bad_input, "m"), InputError);
  EXPECT_THROW(throw_store_error(StoreErrorKind::environment, "m"), EnvironmentError);
}

TEST(Errors, TheClusterMixinSeesBothKindsWithTheirExitCodes) {
  try {
    throw ClusterSetupError("builds differ");
  } catch (const ClusterError& e) {
    EXPECT_EQ(e.exit_code(), 2);
    EXPECT_STREQ(e.what(), "builds differ");
  }
  try {
    throw ClusterFailure("rank 2 went silent");
  } catch (const ClusterError& e) {
    EXPECT_EQ(e.exit_code(), 3);
  }
}

TEST(Errors, ARequirementErrorKeepsItsColumnUnderAContext) {
  const stl::RequirementError inner(14, "'(' is never closed");
  const stl::RequirementError outer("requirement", inner);
  EXPECT_EQ(outer.column(), 14);
  EXPECT_STREQ(outer.what(), "requirement: column 14: '(' is never closed");
}

}  // namespace
}  // namespace hyfal
