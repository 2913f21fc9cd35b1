// STL requirements (core/requirements/): the parser on every ARCH-COMP requirement, its one-line
// errors with columns, absurd inputs (10^5-deep nesting, random bytes); the offline robustness
// against hand-computed values and against a brute-force O(n·w) evaluation written from the
// definitions, on thousands of random formulas and traces (seeded). As in test_fuzz:
// HYFAL_FUZZ_ITERATIONS scales both random tests' counts and HYFAL_FUZZ_SEED changes their seeds,
// for longer runs by hand.
#include <gtest/gtest.h>

#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/requirements/formula.hpp"
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
  m.robustness({t, values});
  const auto s = m.node_signal(m.formula().root());
  EXPECT_DOUBLE_EQ(s[1], -5.0);  // [1, 1] holds both sides of the jump
  EXPECT_DOUBLE_EQ(s[2], 5.0);
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
    const double r0 = m.robustness({t, values});
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

}  // namespace
}  // namespace hyfal::stl
