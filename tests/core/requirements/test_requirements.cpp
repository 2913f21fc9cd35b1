// STL requirements (core/requirements/): the parser on every ARCH-COMP requirement, its one-line
// errors with columns, absurd inputs (10^5-deep nesting, random bytes); the offline robustness
// against hand-computed values and against a brute-force O(n·w) evaluation written from the
// definitions, on thousands of random formulas and traces (seeded). As in test_fuzz:
// HYFAL_FUZZ_ITERATIONS scales both random tests' counts and HYFAL_FUZZ_SEED changes their seeds,
// for longer runs by hand. The prefix monitor: its incremental bounds equal the offline interval on
// every prefix, contain every extension's robustness, and its state stays small.
#include <gtest/gtest.h>

#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/requirements/formula.hpp"
#include "core/requirements/prefix_monitor.hpp"
#include "core/requirements/robustness.hpp"

namespace hyfal::stl {
namespace {

const std::vector<std::string> kAt{"y1", "y2", "y3", "u1", "u2"};
const std::vector<std::string> kCc{"y1", "y2", "y3", "y4", "y5"};

std::uint64_t seed_or(std::uint64_t fallback) {
  const char* s = std::getenv("HYFAL_FUZZ_SEED");
  return s ? std::strtoull(s, nullptr, 10) : fallback;
}
int scaled(int count) {
  const char* s = std::getenv("HYFAL_FUZZ_ITERATIONS");
  return static_cast<int>(std::max(1L, s ? std::strtol(s, nullptr, 10) : 1L) * count);
}

std::string error_of(const std::string& text, const std::vector<std::string>& signals = kAt) {
  try {
    parse_requirement(text, signals);
  } catch (const RequirementError& e) {
    return e.what();
  }
  return "(parsed)";
}

// --- parser ------------------------------------------------------------------------------------

TEST(RequirementParser, EveryArchCompRequirementParsesAndPrintsBack) {
  const std::vector<std::pair<std::string, const std::vector<std::string>*>> cases = {
      {"always[0,20] (y1 < 120)", &kAt},
      {"always[0,10] (y2 < 4750)", &kAt},
      {"always[0,30] ((y3 != 2 and eventually[0.001,0.1] y3 == 2) -> eventually[0.001,0.1] always[0,2.5] y3 == 2)", &kAt},
      {"(always[0,30] y2 < 3000) -> (always[0,4] y1 < 35)", &kAt},
      {"(always[0,30] y2 < 3000) -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and (always[0,20] y1 < 65))", &kAt},
      {"always[0,100] (y5 - y4 <= 40)", &kCc},
      {"always[0,70] eventually[0,30] (y5 - y4 <= 40)", &kCc},
      {"always[0,80] ((always[0,20] (y2 - y1 <= 20)) or (eventually[0,20] (y5 - y4 >= 40)))", &kCc},
      {"always[0,65] eventually[0,30] always[0,5] (y5 - y4 >= 8)", &kCc},
      {"always[0,72] eventually[0,8] ((always[0,5] (y2 - y1 >= 9)) -> (always[5,20] (y5 - y4 >= 9)))", &kCc},
      {"always[0,50] (y2 - y1 > 7.5) and always[0,50] (y3 - y2 > 7.5) and always[0,50] (y4 - y3 > 7.5) and "
       "always[0,50] (y5 - y4 > 7.5)", &kCc},
      {"always[11,50] (((u1 < 8.8 and eventually[0,0.05] u1 > 40) or (u1 > 40 and eventually[0,0.05] u1 < 8.8)) -> "
       "always[1,5] abs(y1) < 0.008)", &kAt},
      {"always[0,10] y3 <= 15 and eventually[0,10] y3 >= 8", &kAt},
      {"always (y1 > 0)", &kAt},
      {"(y1 < 3) until[0,5] (y2 > 1)", &kAt},
      {"(y1 - 2 * y2) / 4 + 1 >= -u1", &kAt},
  };
  for (const auto& [text, signals] : cases) {
    SCOPED_TRACE(text);
    const Formula f = parse_requirement(text, *signals);
    ASSERT_FALSE(f.nodes.empty());
    const std::string printed = to_string(f);
    const Formula again = parse_requirement(printed, *signals);
    EXPECT_EQ(to_string(again), printed);
    EXPECT_EQ(again.nodes.size(), f.nodes.size());
  }
}

TEST(RequirementParser, PrecedenceAndTheFormulaOrExpressionParenthesis) {
  EXPECT_EQ(to_string(parse_requirement("always[0,1] y1 < 1 and y2 < 2", kAt)),
            "((always[0,1] (y1 < 1)) and (y2 < 2))");
  EXPECT_EQ(to_string(parse_requirement("y1 < 1 or y2 < 2 and y3 < 3", kAt)), "((y1 < 1) or ((y2 < 2) and (y3 < 3)))");
  EXPECT_EQ(to_string(parse_requirement("y1 < 1 -> y2 < 2 -> y3 < 3", kAt)), "((y1 < 1) -> ((y2 < 2) -> (y3 < 3)))");
  EXPECT_EQ(to_string(parse_requirement("not y1 < 1 and y2 < 2", kAt)), "((not (y1 < 1)) and (y2 < 2))");
  EXPECT_EQ(to_string(parse_requirement("(y1 + 1) * 2 < 3", kAt)), "((2 * (y1 + 1)) < 3)");
  EXPECT_EQ(to_string(parse_requirement("((y1 < 3))", kAt)), "(y1 < 3)");
  EXPECT_EQ(to_string(parse_requirement("!(y1 < 3) && y2 > 1 || y3 == 2", kAt)),
            "(((not (y1 < 3)) and (y2 > 1)) or (y3 == 2))");
  EXPECT_EQ(to_string(parse_requirement("abs(-3) + 2 * 2 > y1", kAt)), "(7 > y1)");  // constants folded
  const Formula f = parse_requirement("always[0,30] (eventually[1,2] y1 < 1 and always[0,5] y2 < 1)", kAt);
  EXPECT_DOUBLE_EQ(f.horizon(), 35.0);
  EXPECT_EQ(f.temporal_operators(), 3);
  EXPECT_TRUE(std::isinf(parse_requirement("always y1 < 1", kAt).horizon()));
}

TEST(RequirementParser, ErrorsNameTheColumn) {
  EXPECT_EQ(error_of("always[0,20 (y1 < 120)"), "column 13: expected ']', found '('");
  EXPECT_EQ(error_of("always[0,20] (speed < 120)"), "column 15: unknown signal 'speed' (signals: y1, y2, y3, u1, u2)");
  EXPECT_EQ(error_of("always[5,2] y1 < 1"), "column 7: reversed interval [5, 2]");
  EXPECT_EQ(error_of("always[-1,2] y1 < 1"), "column 8: the interval's start must be >= 0");
  EXPECT_EQ(error_of("y1 < nan"), "column 6: unknown signal 'nan' (signals: y1, y2, y3, u1, u2)");
  EXPECT_EQ(error_of("y1 < 1e999"), "column 6: number '1e999' is out of range");
  EXPECT_EQ(error_of("y1 < 1e308 * 10"), "column 12: the constant overflows");
  EXPECT_EQ(error_of("y1 * y2 < 1"), "column 4: a product of two signals is not affine");
  EXPECT_EQ(error_of("y1 / y2 < 1"), "column 4: division by a signal is not affine");
  EXPECT_EQ(error_of("y1 / 0 < 1"), "column 4: division by zero");
  EXPECT_EQ(error_of(""), "column 1: empty requirement");
  EXPECT_EQ(error_of("y1 < 1 )"), "column 8: ')' without a matching '('");
  EXPECT_EQ(error_of("(y1 < 1"), "column 1: '(' is never closed");
  EXPECT_EQ(error_of("y1 = 1"), "column 4: '=' is not an operator (equality is '==')");
  EXPECT_EQ(error_of("y1 < 1 and"), "column 11: expected a signal, a number or '(', found the end");
  EXPECT_EQ(error_of("y1 and y2"), "column 4: expected a comparison (<, <=, >, >=, ==, !=), found 'and'");
  EXPECT_EQ(error_of("y1 < 1 y2"), "column 8: unexpected 'y2'");
  EXPECT_EQ(error_of("□ y1 < 1"), "column 1: unexpected byte 0xe2");
  EXPECT_EQ(error_of("y1 < 1.2.3"), "column 6: malformed number '1.2.3'");
  EXPECT_EQ(error_of("y1 < 3x"), "column 6: malformed number '3x'");
}

TEST(RequirementParser, AbsurdNestingIsAnErrorNotACrash) {
  for (const std::string& open : {std::string("("), std::string("not "), std::string("always[0,1] "), std::string("-")}) {
    std::string text;
    for (int i = 0; i < 100000; ++i) text += open;
    text += "y1 < 1";
    if (open == "(") text += std::string(100000, ')');
    const std::string e = error_of(text);
    EXPECT_NE(e.find("nested deeper than 256 levels"), std::string::npos) << open << ": " << e;
  }
  // At the limit's edge a deep formula still parses.
  std::string text;
  for (int i = 0; i < 100; ++i) text += "not ";
  EXPECT_EQ(parse_requirement(text + "y1 < 1", kAt).nodes.size(), 101u);
}

// Random byte strings and mutations of valid requirements: RequirementError only, in one line.
TEST(RequirementParser, FuzzedTextsGiveOneLineErrorsOnly) {
  std::mt19937_64 rng(seed_or(20261204));
  const std::vector<std::string> seeds = {
      "always[0,30] ((y3 != 2 and eventually[0.001,0.1] y3 == 2) -> eventually[0.001,0.1] always[0,2.5] y3 == 2)",
      "always[0,80] ((always[0,20] (y2 - y1 <= 20)) or (eventually[0,20] (y5 - y4 >= 40)))",
      "(y1 < 3) until[0,5] (abs(y2 - 2 * u1) > 1e-3)"};
  const std::string alphabet = "()[],.+-*/<>=!&|0123456789eE yualwsvntdib_\t\x01\xff";
  const std::vector<std::string> signals{"y1", "y2", "y3", "y4", "y5", "u1"};
  int parsed = 0, refused = 0;
  const int inputs = scaled(20000);
  for (int k = 0; k < inputs; ++k) {
    std::string s = seeds[k % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !s.empty(); ++e) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 4) {
        case 0: s[at] = alphabet[rng() % alphabet.size()]; break;
        case 1: s.erase(at, 1 + rng() % 3); break;
        case 2: s.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
        default: s = s.substr(0, at); break;
      }
    }
    try {
      const Formula f = parse_requirement(s, signals);
      EXPECT_EQ(to_string(parse_requirement(to_string(f), f.signals)), to_string(f)) << s;
      ++parsed;
    } catch (const RequirementError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_EQ(m.rfind("column ", 0), 0u) << m;
      EXPECT_GE(e.column(), 1);
      EXPECT_LE(e.column(), static_cast<int>(s.size()) + 1) << s;
      ++refused;
    }
  }
  EXPECT_GT(parsed, 100);
  EXPECT_GT(refused, 1000);
  std::printf("[ requirements fuzz ] %d inputs: %d parsed (printed and parsed back alike), %d refused in one line\n",
              inputs, parsed, refused);
}

// --- robustness: hand-computed ------------------------------------------------------------------

double rob(const std::string& text, const std::vector<double>& t, const std::vector<std::vector<double>>& signals,
           const std::vector<std::string>& names = {"a", "b"}) {
  std::vector<double> values;
  for (const auto& s : signals) values.insert(values.end(), s.begin(), s.end());
  OfflineMonitor m(parse_requirement(text, names));
  return m.robustness({t, values});
}

TEST(Robustness, HandComputedValues) {
  const std::vector<double> t{0, 10, 20, 30};
  const std::vector<double> a{0, 50, 130, 20}, b{3, 3, 2, 1};
  EXPECT_DOUBLE_EQ(rob("a < 120", t, {a, b}), 120.0);
  EXPECT_DOUBLE_EQ(rob("always[0,20] a < 120", t, {a, b}), -10.0);  // samples 0..2
  EXPECT_DOUBLE_EQ(rob("always[0,19.9] a < 120", t, {a, b}), 70.0);  // samples 0..1
  EXPECT_DOUBLE_EQ(rob("eventually[5,15] a > 100", t, {a, b}), -50.0);  // the value held at 5, and t = 10
  EXPECT_DOUBLE_EQ(rob("eventually[10,10] a > 100", t, {a, b}), -50.0);  // a point interval: t = 10
  EXPECT_DOUBLE_EQ(rob("eventually[25,100] a > 100", t, {a, b}), 30.0);  // held at 25 (t = 20), then 30
  EXPECT_DOUBLE_EQ(rob("always[40,50] a < 25", t, {a, b}), 5.0);  // beyond the end: the last value held
  EXPECT_DOUBLE_EQ(rob("always b == 3", t, {a, b}), -1.5);  // b = 1 at t = 30
  EXPECT_DOUBLE_EQ(rob("eventually b == 1", t, {a, b}), 0.5);
  EXPECT_DOUBLE_EQ(rob("always b != 0", t, {a, b}), 0.5);
  EXPECT_DOUBLE_EQ(rob("a > 1 -> b > 10", t, {a, b}), 1.0);  // max(-(0 - 1), 3 - 10)
  EXPECT_DOUBLE_EQ(rob("abs(a - 10) < 5", t, {a, b}), -5.0);
  // until: b > 1.5 must hold from 0 through the sample where a > 100 (t = 20, b = 2): min(30, 1.5,
  // 1.5, 0.5) = 0.5; with [0,15] the window ends at t = 10 (a = 50): max over j of min(a_j − 100,
  // b ≥ 1.5 so far) = min(-50, 1.5) = -50 (j = 1), -100 (j = 0).
  EXPECT_DOUBLE_EQ(rob("b > 1.5 until a > 100", t, {a, b}), 0.5);
  EXPECT_DOUBLE_EQ(rob("b > 1.5 until[0,15] a > 100", t, {a, b}), -50.0);
  EXPECT_DOUBLE_EQ(rob("b > 2.5 until[0,30] a > 100", t, {a, b}), -0.5);  // b = 2 at t = 20
}

TEST(Robustness, BothSidesOfAJumpAreInTheTrace) {
  // A jump at t = 1: a is 0 just before and 10 just after; both samples count.
  const std::vector<double> t{0, 1, 1, 2};
  const std::vector<double> a{0, 0, 10, 10};
  EXPECT_DOUBLE_EQ(rob("always[1,2] a > 5", t, {a, a}), -5.0);  // the window starts at the jump's first side
  EXPECT_DOUBLE_EQ(rob("eventually[0,1] a > 5", t, {a, a}), 5.0);
  EXPECT_DOUBLE_EQ(rob("always[0,0.5] a < 5", t, {a, a}), 5.0);
  OfflineMonitor m(parse_requirement("always[0,0] a > 5", std::vector<std::string>{"a", "b"}));
  std::vector<double> values = a;
  values.insert(values.end(), a.begin(), a.end());
  m.robustness_at_every_sample({t, values});
  const auto s = m.node_signal(m.formula().root());
  EXPECT_DOUBLE_EQ(s[1], -5.0);  // [1, 1] holds both sides of the jump
  EXPECT_DOUBLE_EQ(s[2], 5.0);
}

// critical_samples (robustness.hpp): the attaining path is a subgradient; every_blocking follows every
// term of a max that must fall and stands above 0 (and every term of a min that must rise and stands
// below 0). AT6a's shape: (always[0,2] a < 3) -> (always[0,1] b < 1).
std::map<std::pair<std::size_t, std::size_t>, double> critical(const std::string& text, const std::vector<double>& t,
                                                               const std::vector<double>& a,
                                                               const std::vector<double>& b, CriticalPath path) {
  OfflineMonitor m(parse_requirement(text, std::vector<std::string>{"a", "b"}));
  std::vector<double> values = a;
  values.insert(values.end(), b.begin(), b.end());
  m.robustness_at_every_sample({t, values});
  std::vector<SampleWeight> out;
  m.critical_samples(out, path);
  std::map<std::pair<std::size_t, std::size_t>, double> sum;  // (signal, sample) -> weight
  for (const SampleWeight& w : out) sum[{w.signal, w.sample}] += w.weight;
  return sum;
}

TEST(Robustness, CriticalSamplesFollowTheAttainingOrEveryBlockingTerm) {
  using Key = std::pair<std::size_t, std::size_t>;
  const std::string at6a = "(always[0,2] a < 3) -> (always[0,1] b < 1)";
  const std::vector<double> t{0, 1, 2};
  // a > 3 at samples 0 and 2 (the antecedent fails, its negation stands at 2 > 0); b's term at 0.5.
  const std::vector<double> a{4, 2, 5}, b{0, 0.5, 0};
  EXPECT_DOUBLE_EQ(rob(at6a, t, {a, b}), 2.0);
  const auto sub = critical(at6a, t, a, b, CriticalPath::attaining);
  EXPECT_EQ(sub, (std::map<Key, double>{{{0, 2}, 1.0}}));  // ρ = a(2) − 3 there
  const auto spread = critical(at6a, t, a, b, CriticalPath::every_blocking);
  // Both terms of the -> (each above 0); in the antecedent's always, which must rise, every sample
  // below 0 (a at 0 and 2, by their mean); in the consequent's always, which must fall, the
  // attaining sample; each atom in units of its threshold (a's 3, b's 1).
  const double sixth = 1.0 / 6.0;
  EXPECT_EQ(spread, (std::map<Key, double>{{{0, 0}, sixth}, {{0, 2}, sixth}, {{1, 1}, -1.0}}));
  // Where the consequent already stands below 0 only the antecedent blocks.
  const std::vector<double> fast{0, 2, 0};
  EXPECT_EQ(critical(at6a, t, a, fast, CriticalPath::every_blocking),
            (std::map<Key, double>{{{0, 0}, sixth}, {{0, 2}, sixth}}));
  // A falsified trace (ρ < 0): nothing blocks, the same samples as the subgradient's, in units.
  const std::vector<double> calm{2, 2, 2};
  const auto attaining = critical(at6a, t, calm, fast, CriticalPath::attaining);
  auto blocking = critical(at6a, t, calm, fast, CriticalPath::every_blocking);
  ASSERT_EQ(blocking.size(), attaining.size());
  for (auto& [key, weight] : blocking) EXPECT_DOUBLE_EQ(weight * (key.first == 0 ? 3.0 : 1.0), attaining.at(key));
  // eventually: every window sample above 0; always at the top: its attaining sample only.
  const double third = 1.0 / 3.0;
  EXPECT_EQ(critical("eventually[0,2] a > 1", t, a, b, CriticalPath::every_blocking),
            (std::map<Key, double>{{{0, 0}, third}, {{0, 1}, third}, {{0, 2}, third}}));
  EXPECT_EQ(critical("eventually[0,2] a > 1", t, a, b, CriticalPath::attaining), (std::map<Key, double>{{{0, 2}, 1.0}}));
  EXPECT_EQ(critical("always[0,2] a < 6", t, a, b, CriticalPath::every_blocking),
            (std::map<Key, double>{{{0, 2}, -1.0 / 6.0}}));
}

TEST(Robustness, RefusesTracesOfTheWrongShape) {
  OfflineMonitor m(parse_requirement("a < 1", std::vector<std::string>{"a", "b"}));
  const std::vector<double> t{0, 1}, v{1, 2, 3};
  EXPECT_THROW(m.robustness({t, v}), std::invalid_argument);
  EXPECT_THROW(m.robustness({{}, {}}), std::invalid_argument);
}

// --- robustness: brute force --------------------------------------------------------------------

// The definitions of robustness.hpp, evaluated literally: windows by scanning every sample,
// min/max by looping over the window, until by the double loop. O(n·w) per operator.
struct BruteForce {
  const Formula& f;
  const std::vector<double>& t;
  const std::vector<double>& values;
  std::size_t n;

  std::pair<std::size_t, std::size_t> window(std::size_t i, double a, double b) const {
    std::size_t s = n;
    for (std::size_t j = i; j < n; ++j)
      if (t[j] == t[i] + a) {
        s = j;
        break;
      }
    if (s == n) {  // the last sample (>= i) before t_i + a holds there
      s = i;
      for (std::size_t j = i; j < n; ++j)
        if (t[j] < t[i] + a) s = j;
    }
    std::size_t e = s;
    for (std::size_t j = s; j < n; ++j)
      if (t[j] <= t[i] + b) e = j;
    return {s, e};
  }
  double expr(int e, std::size_t i) const {
    const ExpressionNode& x = f.expressions[e];
    switch (x.kind) {
      case ExpressionNode::Kind::constant: return x.value;
      case ExpressionNode::Kind::signal: return values[static_cast<std::size_t>(x.signal) * n + i];
      case ExpressionNode::Kind::add: return expr(x.left, i) + expr(x.right, i);
      case ExpressionNode::Kind::subtract: return expr(x.left, i) - expr(x.right, i);
      case ExpressionNode::Kind::negate: return -expr(x.left, i);
      case ExpressionNode::Kind::scale: return x.value * expr(x.left, i);
      case ExpressionNode::Kind::abs: return std::abs(expr(x.left, i));
    }
    return 0;
  }
  std::vector<double> eval(int k) const {
    const FormulaNode& nd = f.nodes[k];
    std::vector<double> out(n);
    std::vector<double> l, r;
    if (nd.left >= 0) l = eval(nd.left);
    if (nd.right >= 0) r = eval(nd.right);
    for (std::size_t i = 0; i < n; ++i) {
      switch (nd.op) {
        case Operator::compare: {
          const double a = expr(nd.lhs, i), b = expr(nd.rhs, i);
          switch (nd.relation) {
            case Relation::less: case Relation::less_equal: out[i] = b - a; break;
            case Relation::greater: case Relation::greater_equal: out[i] = a - b; break;
            case Relation::equal: out[i] = 0.5 - std::abs(a - b); break;
            case Relation::not_equal: out[i] = std::abs(a - b) - 0.5; break;
          }
          break;
        }
        case Operator::negation: out[i] = -l[i]; break;
        case Operator::conjunction: out[i] = std::min(l[i], r[i]); break;
        case Operator::disjunction: out[i] = std::max(l[i], r[i]); break;
        case Operator::implication: out[i] = std::max(-l[i], r[i]); break;
        case Operator::always:
        case Operator::eventually: {
          const auto [s, e] = window(i, nd.lo, nd.hi);
          double v = nd.op == Operator::always ? 1e300 : -1e300;
          for (std::size_t j = s; j <= e; ++j) v = nd.op == Operator::always ? std::min(v, l[j]) : std::max(v, l[j]);
          out[i] = v;
          break;
        }
        case Operator::until: {
          const auto [s, e] = window(i, nd.lo, nd.hi);
          double best = -1e300;
          for (std::size_t j = s; j <= e; ++j) {
            double m = r[j];
            for (std::size_t q = i; q <= j; ++q) m = std::min(m, l[q]);
            best = std::max(best, m);
          }
          out[i] = best;
          break;
        }
      }
    }
    return out;
  }
};

// A random formula over signals a, b, of depth <= `depth`, with intervals on a grid of 0.25 (so
// that window ends often fall exactly on samples) or none.
std::string random_formula(std::mt19937_64& rng, int depth) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  auto number = [&] { return std::to_string(pick(9) - 4) + (pick(2) ? ".5" : ""); };
  auto interval = [&]() -> std::string {
    if (pick(5) == 0) return "";
    const int lo = pick(8), hi = lo + pick(12);
    return "[" + std::to_string(lo * 0.25) + "," + std::to_string(hi * 0.25) + "]";
  };
  if (depth == 0 || pick(4) == 0) {
    static const char* kRel[] = {"<", "<=", ">", ">=", "==", "!="};
    const std::string lhs = pick(2) ? "a" : (pick(2) ? "b - a" : "abs(a) + 2 * b");
    return "(" + lhs + " " + kRel[pick(6)] + " " + number() + ")";
  }
  switch (pick(7)) {
    case 0: return "(not " + random_formula(rng, depth - 1) + ")";
    case 1: return "(" + random_formula(rng, depth - 1) + " and " + random_formula(rng, depth - 1) + ")";
    case 2: return "(" + random_formula(rng, depth - 1) + " or " + random_formula(rng, depth - 1) + ")";
    case 3: return "(" + random_formula(rng, depth - 1) + " -> " + random_formula(rng, depth - 1) + ")";
    case 4: return "(always" + interval() + " " + random_formula(rng, depth - 1) + ")";
    case 5: return "(eventually" + interval() + " " + random_formula(rng, depth - 1) + ")";
    default: return "(" + random_formula(rng, depth - 1) + " until" + interval() + " " + random_formula(rng, depth - 1) + ")";
  }
}

TEST(Robustness, AgreesWithTheBruteForceDefinitionsOnRandomFormulasAndTraces) {
  std::mt19937_64 rng(seed_or(42));
  const std::vector<std::string> names{"a", "b"};
  int checked = 0;
  const int formulas = scaled(3000);
  long samples = 0;
  for (int k = 0; k < formulas; ++k) {
    const Formula f = parse_requirement(random_formula(rng, 1 + static_cast<int>(rng() % 4)), names);
    const std::size_t n = 1 + rng() % 40;
    std::vector<double> t(n), values(2 * n);
    double now = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0 && rng() % 6 != 0) now += (rng() % 2) ? 0.25 * static_cast<double>(1 + rng() % 3) : 0.1 * static_cast<double>(1 + rng() % 7);
      t[i] = now;  // equal times: the two sides of a jump
    }
    for (double& v : values) v = static_cast<double>(static_cast<int>(rng() % 13) - 6) * 0.5;
    OfflineMonitor m(f);
    const double r0 = m.robustness({t, values});  // only the samples ρ(φ, 0) reads
    ASSERT_EQ(m.robustness_at_every_sample({t, values}), r0) << to_string(f);
    const BruteForce brute{f, t, values, n};
    for (int node = 0; node < static_cast<int>(f.nodes.size()); ++node) {
      const std::vector<double> want = brute.eval(node);
      const auto got = m.node_signal(node);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_DOUBLE_EQ(got[i], want[i]) << to_string(f) << " node " << node << " sample " << i << " of " << n;
    }
    EXPECT_DOUBLE_EQ(r0, brute.eval(f.root())[0]);
    samples += static_cast<long>(n * f.nodes.size());
    ++checked;
  }
  EXPECT_EQ(checked, formulas);
  std::printf("[ brute force ] %d formulas, %ld node x sample values equal\n", checked, samples);
}

// --- prefix robustness ------------------------------------------------------------------------

// A random trace over signals a, b (as in the brute-force test): steps of 0.25 k or 0.1 k, one in
// six a jump (a repeated time), values on a grid of 0.5.
struct RandomTrace {
  std::vector<double> t, values;  // values signal-major, as TraceView reads them
};
RandomTrace random_trace(std::mt19937_64& rng, std::size_t n, double start = 0.0) {
  RandomTrace tr{std::vector<double>(n), std::vector<double>(2 * n)};
  double now = start;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && rng() % 6 != 0)
      now += (rng() % 2) ? 0.25 * static_cast<double>(1 + rng() % 3) : 0.1 * static_cast<double>(1 + rng() % 7);
    tr.t[i] = now;
  }
  for (double& v : tr.values) v = static_cast<double>(static_cast<int>(rng() % 13) - 6) * 0.5;
  return tr;
}

// Samples [from, to) of a signal-major trace as PrefixMonitor rows: time, then each signal.
std::vector<double> rows_of(const std::vector<double>& t, const std::vector<double>& values, std::size_t from,
                            std::size_t to) {
  const std::size_t n = t.size(), signals = values.size() / std::max<std::size_t>(n, 1);
  std::vector<double> out;
  for (std::size_t i = from; i < to; ++i) {
    out.push_back(t[i]);
    for (std::size_t s = 0; s < signals; ++s) out.push_back(values[s * n + i]);
  }
  return out;
}

// The first k samples of a signal-major trace.
RandomTrace prefix_of(const RandomTrace& tr, std::size_t k) {
  const std::size_t n = tr.t.size(), signals = tr.values.size() / n;
  RandomTrace p{{tr.t.begin(), tr.t.begin() + static_cast<std::ptrdiff_t>(k)}, {}};
  for (std::size_t s = 0; s < signals; ++s)
    p.values.insert(p.values.end(), tr.values.begin() + static_cast<std::ptrdiff_t>(s * n),
                    tr.values.begin() + static_cast<std::ptrdiff_t>(s * n + k));
  return p;
}

// A random formula (random_formula), half the time under a top temporal operator with a longer
// window, so that prefixes stay undecided for a while and samples are folded along the way.
std::string random_prefix_formula(std::mt19937_64& rng) {
  std::string inner = random_formula(rng, 1 + static_cast<int>(rng() % 4));
  if (rng() % 2) return inner;
  const int lo = static_cast<int>(rng() % 8), hi = lo + static_cast<int>(rng() % 40);
  const std::string interval = "[" + std::to_string(lo * 0.25) + "," + std::to_string(hi * 0.25) + "]";
  switch (rng() % 4) {
    case 0: return "always" + interval + " " + inner;
    case 1: return "eventually" + interval + " " + inner;
    case 2: return "(" + inner + ") until" + interval + " (" + random_formula(rng, 2) + ")";
    default: return "not always" + interval + " " + inner + " -> eventually" + interval + " (a > b)";
  }
}

TEST(PrefixRobustness, IncrementalEqualsOfflineIntervalOnEveryPrefix) {
  std::mt19937_64 rng(seed_or(7));
  const std::vector<std::string> names{"a", "b"};
  const int formulas = scaled(1500);
  long prefixes = 0, decided = 0, folding = 0;
  for (int k = 0; k < formulas; ++k) {
    const Formula f = parse_requirement(random_prefix_formula(rng), names);
    const RandomTrace tr = random_trace(rng, 1 + rng() % 100);
    const std::size_t n = tr.t.size();
    PrefixMonitor prefix(f);
    OfflineMonitor offline(f);
    std::vector<double> state, child, before_last;
    prefix.initial_state(state);
    for (std::size_t done = 0; done < n;) {
      const std::size_t next = std::min(n, done + 1 + rng() % 20);
      const std::vector<double> chunk = rows_of(tr.t, tr.values, done, next);
      const PrefixBounds got = prefix.extend(state, chunk, false, child);
      const RandomTrace p = prefix_of(tr, next);
      const Interval want = offline.robustness_interval({p.t, p.values}, false);
      ASSERT_EQ(got.lower, want.lower) << to_string(f) << " after " << next << " of " << n;
      ASSERT_EQ(got.upper, want.upper) << to_string(f) << " after " << next << " of " << n;
      EXPECT_EQ(got.complete, got.lower == got.upper);
      EXPECT_EQ(got.samples, static_cast<std::int64_t>(next));
      EXPECT_EQ(got.time, tr.t[next - 1]);
      if (next == n) {  // the same last chunk again, as the trace's end
        const PrefixBounds end = prefix.extend(state, chunk, true, before_last);
        const double r = offline.robustness({tr.t, tr.values});
        ASSERT_EQ(end.lower, r) << to_string(f);
        ASSERT_EQ(end.upper, r) << to_string(f);
        EXPECT_TRUE(end.complete);
      }
      decided += got.complete;
      // Undecided, and some samples already folded away: the accumulators are at work.
      folding += !got.complete && child.size() < prefix.header_size() + 3 * next;
      ++prefixes;
      std::swap(state, child);
      done = next;
    }
    // Ending a trace with no new sample gives its robustness too.
    const PrefixBounds end = prefix.extend(state, {}, true, child);
    ASSERT_EQ(end.lower, offline.robustness({tr.t, tr.values})) << to_string(f);
    ASSERT_EQ(end.upper, end.lower);
  }
  EXPECT_GT(folding, prefixes / 20);
  std::printf("[ prefix ] %d formulas, %ld prefixes equal to the offline interval (%ld already decided, %ld undecided "
              "with samples folded)\n", formulas, prefixes, decided, folding);
}

TEST(PrefixRobustness, PrefixBoundsContainEveryExtension) {
  std::mt19937_64 rng(seed_or(11));
  const std::vector<std::string> names{"a", "b"};
  const int formulas = scaled(1000);
  long extensions = 0, violated = 0, satisfied = 0;
  for (int k = 0; k < formulas; ++k) {
    const Formula f = parse_requirement(random_prefix_formula(rng), names);
    const RandomTrace head = random_trace(rng, 1 + rng() % 30);
    PrefixMonitor prefix(f);
    OfflineMonitor offline(f);
    std::vector<double> state, child;
    prefix.initial_state(state);
    const PrefixBounds b = prefix.extend(state, rows_of(head.t, head.values, 0, head.t.size()), false, child);
    violated += b.upper < 0;
    satisfied += b.lower > 0;
    for (int c = 0; c < 6; ++c) {
      // A continuation from the last time on (its first sample may share it: a jump).
      const RandomTrace tail = random_trace(rng, rng() % 30, head.t.back() + (rng() % 2 ? 0.0 : 0.1));
      const std::size_t n = head.t.size() + tail.t.size();
      std::vector<double> t = head.t, values;
      t.insert(t.end(), tail.t.begin(), tail.t.end());
      for (std::size_t s = 0; s < 2; ++s) {
        values.insert(values.end(), head.values.begin() + static_cast<std::ptrdiff_t>(s * head.t.size()),
                      head.values.begin() + static_cast<std::ptrdiff_t>((s + 1) * head.t.size()));
        values.insert(values.end(), tail.values.begin() + static_cast<std::ptrdiff_t>(s * tail.t.size()),
                      tail.values.begin() + static_cast<std::ptrdiff_t>((s + 1) * tail.t.size()));
      }
      const double r = offline.robustness({t, values});
      ASSERT_GE(r, b.lower) << to_string(f) << " prefix of " << head.t.size() << ", " << n << " samples";
      ASSERT_LE(r, b.upper) << to_string(f) << " prefix of " << head.t.size() << ", " << n << " samples";
      ++extensions;
    }
  }
  EXPECT_GT(violated, 0);
  EXPECT_GT(satisfied, 0);
  std::printf("[ prefix ] %ld extensions inside their prefix's bounds (%ld prefixes already violating, %ld satisfying)\n",
              extensions, violated, satisfied);
}

// A prefix closed at its last time (robustness_interval's closed_at_last_time: extensions add
// samples only after it, as FalStar's adaptive search judges a node's prefix) bounds every such
// extension, and its interval lies inside the open one; a window that ends exactly at the last
// time is decided.
TEST(PrefixRobustness, ClosedAtTheLastTimeBoundsEveryLaterExtension) {
  std::mt19937_64 rng(seed_or(13));
  const std::vector<std::string> names{"a", "b"};
  const int formulas = scaled(1000);
  long extensions = 0, tighter = 0;
  for (int k = 0; k < formulas; ++k) {
    const Formula f = parse_requirement(random_prefix_formula(rng), names);
    const RandomTrace head = random_trace(rng, 1 + rng() % 30);
    OfflineMonitor offline(f);
    const Interval open = offline.robustness_interval({head.t, head.values}, false);
    const Interval closed = offline.robustness_interval({head.t, head.values}, false, true);
    ASSERT_GE(closed.lower, open.lower) << to_string(f);
    ASSERT_LE(closed.upper, open.upper) << to_string(f);
    tighter += closed.lower > open.lower || closed.upper < open.upper;
    for (int c = 0; c < 6; ++c) {
      const RandomTrace tail = random_trace(rng, rng() % 30, head.t.back() + 0.1);  // strictly later
      std::vector<double> t = head.t, values;
      t.insert(t.end(), tail.t.begin(), tail.t.end());
      for (std::size_t s = 0; s < 2; ++s) {
        values.insert(values.end(), head.values.begin() + static_cast<std::ptrdiff_t>(s * head.t.size()),
                      head.values.begin() + static_cast<std::ptrdiff_t>((s + 1) * head.t.size()));
        values.insert(values.end(), tail.values.begin() + static_cast<std::ptrdiff_t>(s * tail.t.size()),
                      tail.values.begin() + static_cast<std::ptrdiff_t>((s + 1) * tail.t.size()));
      }
      const double r = offline.robustness({t, values});
      ASSERT_GE(r, closed.lower) << to_string(f);
      ASSERT_LE(r, closed.upper) << to_string(f);
      ++extensions;
    }
  }
  EXPECT_GT(tighter, 0);
  // always[0,20] over samples at 0..20: open, a jump at 20 could still break it; closed, decided.
  OfflineMonitor speed(parse_requirement("always[0,20] (a < 120)", names));
  std::vector<double> t, values;
  for (int i = 0; i <= 20; ++i) t.push_back(i);
  for (int i = 0; i <= 20; ++i) values.push_back(100.0 + (i % 5));
  values.resize(2 * t.size(), 0.0);
  EXPECT_EQ(speed.robustness_interval({t, values}, false).lower, -std::numeric_limits<double>::infinity());
  const Interval decided = speed.robustness_interval({t, values}, false, true);
  EXPECT_EQ(decided.lower, 16.0);
  EXPECT_EQ(decided.upper, 16.0);
  std::printf("[ prefix ] %ld later extensions inside their closed prefix's bounds (%ld of %d closed intervals tighter)\n",
              extensions, tighter, formulas);
}

// A requirement tightened by a margin m (with_margin) has robustness ρ + m on every trace, and
// prefix bounds moved by m, for every operator and relation (== and != included, under not and
// left of ->); its text parses back to the same robustness.
TEST(Margin, ShiftsRobustnessByTheMarginOnRandomFormulasAndTraces) {
  std::mt19937_64 rng(seed_or(17));
  const std::vector<std::string> names{"a", "b"};
  const int formulas = scaled(2000);
  for (int k = 0; k < formulas; ++k) {
    const Formula f = parse_requirement(random_formula(rng, 1 + static_cast<int>(rng() % 4)), names);
    const double m = (k % 3 == 0) ? 0.25 : 1.5 + static_cast<double>(rng() % 7);
    const Formula g = with_margin(f, m);
    const Formula reparsed = parse_requirement(g.text, names);
    const RandomTrace trace = random_trace(rng, 1 + rng() % 25);
    OfflineMonitor of(f), og(g), orp(reparsed);
    const double rf = of.robustness({trace.t, trace.values});
    const double rg = og.robustness({trace.t, trace.values});
    const double rr = orp.robustness({trace.t, trace.values});
    if (std::isfinite(rf)) {
      ASSERT_NEAR(rg, rf + m, 1e-9 * (1.0 + std::abs(rf))) << to_string(f) << " -> " << g.text;
      ASSERT_NEAR(rr, rg, 1e-9 * (1.0 + std::abs(rg))) << g.text;
    } else {
      ASSERT_EQ(rg, rf) << to_string(f);
    }
    const Interval bf = of.robustness_interval({trace.t, trace.values}, false);
    const Interval bg = og.robustness_interval({trace.t, trace.values}, false);
    if (std::isfinite(bf.lower)) ASSERT_NEAR(bg.lower, bf.lower + m, 1e-9 * (1.0 + std::abs(bf.lower))) << g.text;
    if (std::isfinite(bf.upper)) ASSERT_NEAR(bg.upper, bf.upper + m, 1e-9 * (1.0 + std::abs(bf.upper))) << g.text;
  }
  // By hand: AT2's atom moves toward its violation; gear == 3 becomes a band.
  const std::vector<std::string> at{"y2", "y3"};
  EXPECT_EQ(with_margin(parse_requirement("always[0,10] (y2 < 4750)", at), 20).text, "(always[0,10] (y2 < (4750 + 20)))");
  EXPECT_EQ(with_margin(parse_requirement("not (y3 == 3)", at), 0.25).text,
            "(not (((y3 - 3) >= (-0.25)) and ((y3 - 3) <= 0.25)))");
}

// Feeds (time, y1) samples one by one, non-final; returns every step's bounds.
std::vector<PrefixBounds> feed(PrefixMonitor& m, const std::vector<std::pair<double, double>>& samples) {
  std::vector<double> state, child;
  m.initial_state(state);
  std::vector<PrefixBounds> out;
  for (const auto& [t, y] : samples) {
    std::vector<double> row{t, y};
    row.resize(1 + m.signals(), 0.0);
    out.push_back(m.extend(state, row, false, child));
    std::swap(state, child);
  }
  return out;
}

TEST(PrefixRobustness, HandCases) {
  const std::vector<std::string> y{"y1"};
  PrefixMonitor speed(parse_requirement("always[0,20] (y1 < 120)", y));
  const std::vector<PrefixBounds> violated = feed(speed, {{0, 100}, {1, 110}, {3, 130}});
  EXPECT_EQ(violated[0].lower, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(violated[0].upper, 20.0);
  EXPECT_EQ(violated[2].upper, -10.0);  // violated at t = 3: a counterexample already
  EXPECT_FALSE(violated[2].complete);
  EXPECT_EQ(violated[2].time, 3.0);
  EXPECT_EQ(violated[2].samples, 3);

  std::vector<std::pair<double, double>> below;
  for (int i = 0; i <= 25; ++i) below.push_back({i, 100.0 + (i % 5)});
  const std::vector<PrefixBounds> held = feed(speed, below);
  EXPECT_FALSE(held[20].complete);  // t = 20: a jump at 20 could still break it
  EXPECT_TRUE(held[21].complete);
  EXPECT_EQ(held[21].lower, 16.0);
  EXPECT_EQ(held[21].upper, 16.0);
  EXPECT_EQ(held[25].lower, 16.0);

  PrefixMonitor reach(parse_requirement("eventually[0,5] y1 > 1", y));
  const std::vector<PrefixBounds> reached = feed(reach, {{0, 0}, {1, 0.5}, {2, 3}, {2.5, 0}});
  EXPECT_EQ(reached[1].upper, std::numeric_limits<double>::infinity());
  EXPECT_EQ(reached[1].lower, -0.5);
  EXPECT_EQ(reached[2].lower, 2.0);  // satisfied at t = 2, whatever follows
  EXPECT_GT(reached[3].lower, 0.0);

  // A violated atom under `and` decides as soon as the other side's lower bound is above it.
  PrefixMonitor atom(parse_requirement("y1 > 1 and eventually y1 > -10", y));
  const std::vector<PrefixBounds> decided = feed(atom, {{0, 0}, {1, 5}});
  EXPECT_TRUE(decided[0].complete);
  EXPECT_EQ(decided[0].lower, -1.0);
  EXPECT_EQ(decided[0].upper, -1.0);
}

TEST(PrefixRobustness, StateStaysSmall) {
  PrefixMonitor m(parse_requirement("always[0,100] eventually[0,2] y1 > 0", std::vector<std::string>{"y1"}));
  std::vector<double> state, child;
  m.initial_state(state);
  const std::size_t header = m.header_size(), width = 1 + m.signals(), chunk = 10;
  std::size_t largest = 0;
  PrefixBounds b;
  for (int i = 0; i < 10000; i += static_cast<int>(chunk)) {
    std::vector<double> rows;
    for (int k = i; k < i + static_cast<int>(chunk); ++k) {
      rows.push_back(k * 0.01);
      rows.push_back(1.0 + std::sin(k * 0.001));
    }
    b = m.extend(state, rows, false, child);
    std::swap(state, child);
    largest = std::max(largest, state.size());
    // Pending: the samples within the operand's 2 s horizon of the last, and the new chunk.
    ASSERT_LE(state.size(), header + (201 + chunk + 3) * width) << "at sample " << i;
  }
  EXPECT_GT(largest, header + 150 * width);  // the 2 s are really kept
  EXPECT_FALSE(b.complete);                   // t = 99.99: the window [0, 100] is still open
  EXPECT_GT(b.upper, 0.0);
  std::printf("[ prefix ] largest state: %zu doubles (header %zu + %zu samples)\n", largest, header,
              (largest - header) / width);
}

TEST(PrefixRobustness, ExtendingACompleteStateChangesNothing) {
  PrefixMonitor m(parse_requirement("always[0,2] y1 < 5", std::vector<std::string>{"y1"}));
  std::vector<double> state, done, again;
  m.initial_state(state);
  const PrefixBounds b = m.extend(state, std::vector<double>{0, 1, 1, 2, 2, 3, 3, 4}, false, done);
  ASSERT_TRUE(b.complete);
  EXPECT_EQ(b.lower, 2.0);
  EXPECT_EQ(done.size(), m.header_size());  // nothing pending
  const PrefixBounds c = m.extend(done, std::vector<double>{4, 100, 5, -100}, false, again);
  EXPECT_EQ(again.size(), done.size());
  EXPECT_EQ(c.lower, 2.0);
  EXPECT_EQ(c.upper, 2.0);
  EXPECT_TRUE(c.complete);
  EXPECT_EQ(c.samples, 6);  // only the count and the time move on
  EXPECT_EQ(c.time, 5.0);
  EXPECT_EQ(m.extend(done, {}, true, again).upper, 2.0);
}

TEST(PrefixRobustness, RefusesMalformedSamples) {
  PrefixMonitor m(parse_requirement("always[0,2] y1 < 5", std::vector<std::string>{"y1", "y2"}));
  std::vector<double> state, child;
  m.initial_state(state);
  EXPECT_THROW(m.extend(state, std::vector<double>{0, 1}, false, child), std::invalid_argument);  // rows of 3
  EXPECT_THROW(m.extend(state, std::vector<double>{1, 0, 0, 0.5, 0, 0}, false, child), std::invalid_argument);
  EXPECT_THROW(m.extend(state, std::vector<double>{std::nan(""), 0, 0}, false, child), std::invalid_argument);
  EXPECT_THROW(m.extend(state, {}, true, child), std::invalid_argument);  // a trace without samples
  m.extend(state, std::vector<double>{1, 0, 0}, false, child);
  EXPECT_THROW(m.extend(child, std::vector<double>{0.5, 0, 0}, false, state), std::invalid_argument);  // back in time
  EXPECT_THROW(m.extend(std::vector<double>{1, 2}, {}, false, state), std::invalid_argument);
}

}  // namespace
}  // namespace hyfal::stl
