// The one validation layer for settings (core/run/option_spec.hpp): declared ranges, their parsing, and
// that every suite parameter and method option declares a range its default satisfies.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/run/option_spec.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

TEST(ValueRange, Intervals) {
  const ValueRange closed = ValueRange::parse("[1, 1000]");
  EXPECT_EQ(closed.kind, ValueRange::Kind::interval);
  EXPECT_TRUE(closed.contains(Json(1)));
  EXPECT_TRUE(closed.contains(Json(1000)));
  EXPECT_FALSE(closed.contains(Json(0)));
  EXPECT_FALSE(closed.contains(Json(1001)));
  EXPECT_FALSE(closed.contains(Json("5")));
  const ValueRange open = ValueRange::parse("(0, 1]");
  EXPECT_FALSE(open.contains(Json(0.0)));
  EXPECT_TRUE(open.contains(Json(1e-300)));
  EXPECT_TRUE(open.contains(Json(1.0)));
  const ValueRange half = ValueRange::parse("[0, inf)");
  EXPECT_TRUE(half.contains(Json(1e300)));
  EXPECT_FALSE(half.contains(Json(-1e-300)));
  EXPECT_FALSE(half.contains(Json(std::numeric_limits<double>::quiet_NaN())));
}

TEST(ValueRange, Choices) {
  const ValueRange r = ValueRange::parse("metric|t2go");
  EXPECT_EQ(r.kind, ValueRange::Kind::choices);
  EXPECT_TRUE(r.contains(Json("t2go")));
  EXPECT_FALSE(r.contains(Json("T2GO")));
  EXPECT_FALSE(r.contains(Json(1)));
  EXPECT_EQ(ValueRange::parse("").kind, ValueRange::Kind::any);
}

TEST(ValueRange, MalformedDeclarationsAreProgrammingErrors) {
  EXPECT_THROW(ValueRange::parse("[1, 0]"), std::logic_error);
  EXPECT_THROW(ValueRange::parse("[1 0]"), std::logic_error);
  EXPECT_THROW(ValueRange::parse("[a, 2]"), std::logic_error);
  EXPECT_THROW(ValueRange::parse("a||b"), std::logic_error);
}

TEST(ResolveOptions, ChecksTypeRangeAndRepetition) {
  const std::vector<OptionSpec> specs = {{"k", 10, "count", "[1, 1000]"},
                                         {"mode", "a", "choice", "a|b"},
                                         {"p", 0.5, "probability", "[0, 1]"},
                                         {"flag", false, "switch"}};
  const Json o = resolve_options(specs, {{"k", "7"}, {"mode", "b"}});
  EXPECT_EQ(o.at("k"), 7);
  EXPECT_EQ(o.at("mode"), "b");
  EXPECT_EQ(o.at("p"), 0.5);
  EXPECT_THROW(resolve_options(specs, {{"k", "0"}}), OptionError);
  EXPECT_THROW(resolve_options(specs, {{"k", "1001"}}), OptionError);
  EXPECT_THROW(resolve_options(specs, {{"mode", "c"}}), OptionError);
  EXPECT_THROW(resolve_options(specs, {{"p", "1.5"}}), OptionError);
  EXPECT_THROW(resolve_options(specs, {{"k", "5"}, {"k", "6"}}), OptionError);
  EXPECT_THROW(resolve_options(specs, {{"nosuch", "1"}}), OptionError);
  try {
    resolve_options(specs, {{"k", "-5"}});
    FAIL() << "k=-5 accepted";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(), "--set k=-5: k must be in [1, 1000]");
  }
}

// Every declared setting has a range (booleans and the requirement may omit it), the range parses, and the default
// lies in it; so `hyfal list` and the README can show every valid range.
void expect_declared(const std::string& owner, const std::vector<OptionSpec>& specs) {
  for (const OptionSpec& s : specs) {
    SCOPED_TRACE(owner + " " + s.key);
    // A requirement and adaptive's cp are any text, checked by their parsers (and tested there).
    if (!s.default_value.is_boolean() && s.key != "requirement" && !(owner.starts_with("method adaptive") && s.key == "cp")) {
      EXPECT_FALSE(s.range.empty()) << "no range declared";
    }
    ValueRange r;
    ASSERT_NO_THROW(r = ValueRange::parse(s.range));
    EXPECT_TRUE(r.contains(s.default_value)) << "default " << s.default_value.dump() << " outside " << s.range;
    if (r.kind == ValueRange::Kind::choices) {
      EXPECT_TRUE(s.default_value.is_string());
    }
    if (r.kind == ValueRange::Kind::interval) {
      EXPECT_TRUE(s.default_value.is_number());
    }
  }
}

TEST(DeclaredSettings, EverySuiteParameterAndMethodOptionHasARange) {
  for (const SuiteEntry& s : all_suites()) expect_declared("suite " + s.name, s.parameters);
  for (const MethodEntry& m : all_methods()) expect_declared("method " + m.name, m.options);
}

// The defaults build: every suite's default instance, and every method's default options.
TEST(DeclaredSettings, DefaultsAreAccepted) {
  for (const SuiteEntry& s : all_suites()) {
    SCOPED_TRACE(s.name);
    EXPECT_NO_THROW(s.make(resolve_options(s.parameters, {})));
  }
  for (const MethodEntry& m : all_methods()) {
    SCOPED_TRACE(m.name);
    EXPECT_NO_THROW(m.make(resolve_options(m.options, {})));
  }
}

// Each interval bound is enforced for every numeric setting: one step outside is refused with an
// OptionError, before a suite or planner sees it.
TEST(DeclaredSettings, ValuesJustOutsideEveryIntervalAreRefused) {
  const auto check = [](const std::vector<OptionSpec>& specs) {
    for (const OptionSpec& s : specs) {
      const ValueRange r = ValueRange::parse(s.range);
      if (r.kind != ValueRange::Kind::interval) continue;
      SCOPED_TRACE(s.key + " " + s.range);
      const bool integer = s.default_value.is_number_integer();
      if (std::isfinite(r.lo) && r.lo > -2e9) {
        const double below = integer ? (r.lo_open ? r.lo : r.lo - 1) : (r.lo_open ? r.lo : r.lo - 1e-3 * (1 + std::abs(r.lo)));
        const std::string text = integer ? std::to_string(static_cast<long long>(below)) : Json(below).dump();
        EXPECT_THROW(resolve_options(specs, {{s.key, text}}), OptionError) << text;
      }
      if (std::isfinite(r.hi) && r.hi < 2e9) {
        const double above = integer ? (r.hi_open ? r.hi : r.hi + 1) : (r.hi_open ? r.hi : r.hi + 1e-3 * (1 + std::abs(r.hi)));
        const std::string text = integer ? std::to_string(static_cast<long long>(above)) : Json(above).dump();
        EXPECT_THROW(resolve_options(specs, {{s.key, text}}), OptionError) << text;
      }
    }
  };
  for (const SuiteEntry& s : all_suites()) check(s.parameters);
  for (const MethodEntry& m : all_methods()) check(m.options);
}

// A method states what it needs of a system; HyDICE on a suite without a decomposition is refused
// up front (check_system), not per trial.
TEST(MethodChecks, HydiceNeedsADecomposition) {
  const SuiteEntry* thermostat = find_suite("thermostat");
  const SuiteEntry* navigation = find_suite("navigation");
  ASSERT_TRUE(thermostat && navigation);
  const auto t = thermostat->make(resolve_options(thermostat->parameters, {}));
  const auto n = navigation->make(resolve_options(navigation->parameters, {}));
  for (const char* name : {"hydice", "hydice-noleads"}) {
    const MethodEntry* m = find_method(name);
    ASSERT_TRUE(m && m->check_system);
    const Json o = resolve_options(m->options, {});
    EXPECT_THROW(m->check_system(*t, o), std::invalid_argument) << name;
    EXPECT_NO_THROW(m->check_system(*n, o)) << name;
  }
}

TEST(InputGrid, SizeIsBoundedAndValuesStayInTheBox) {
  EXPECT_THROW(InputSet::grid({{0, 0, 0}, {1, 1, 1}}, 1000), std::invalid_argument);
  const InputSet s = InputSet::grid({{0.1, -3.0}, {0.7, 0.3}}, 7);
  for (std::size_t j = 0; j < s.count(); ++j)
    for (std::size_t i = 0; i < s.dim(); ++i) {
      EXPECT_GE(s.input(j)[i], s.box.lo[i]);
      EXPECT_LE(s.input(j)[i], s.box.hi[i]);
    }
}

}  // namespace
}  // namespace hyfal
