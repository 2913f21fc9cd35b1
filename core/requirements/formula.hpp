// Signal Temporal Logic requirements in the ARCH-COMP notation (../shared/arch/requirements.md):
//
//   φ ::= e ~ e  |  not φ  |  φ and φ  |  φ or φ  |  φ -> φ  |  (φ)
//       |  always[a,b] φ  |  eventually[a,b] φ  |  φ until[a,b] φ
//       |  always φ  |  eventually φ  |  φ until φ              (no interval: [0, ∞))
//   e ::= number | signal | e + e | e - e | -e | number * e | e * number | e / number | abs(e) | (e)
//   ~ ::= <  <=  >  >=  ==  !=
//
// Precedence, loosest first: `->` (right-associative), `or`, `and`, `until` (left), the prefix
// operators `not`, `always`, `eventually` (they bind as far right as an `and` would stop them:
// `always[0,1] a < 1 and b < 2` is `(always[0,1] a < 1) and b < 2`). Expressions are affine in the
// signals except for `abs` (a signal times a signal is refused). Signal names are the suite's
// declared outputs and inputs; times are seconds of the trace's clock. `&&`, `||`, `!` and `=>`
// are accepted for `and`, `or`, `not` and `->`.
//
// A formula is a flat array of nodes in which every child precedes its parent (the parser makes
// them bottom-up), so a monitor evaluates it in one forward pass over the array.
#pragma once
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/error.hpp"

namespace hyfal::stl {

// A refused requirement: `column` is 1-based, in the text given to parse_requirement; what() reads
// "column 17: expected ']'".
class RequirementError : public InputError {
 public:
  RequirementError(int column, const std::string& message);
  // The same refusal led by where the formula came from: "requirement: column 17: expected ']'".
  RequirementError(std::string_view context, const RequirementError& error);
  int column() const { return column_; }
  const char* name() const noexcept override { return "RequirementError"; }

 private:
  int column_;
};

// One node of an expression (e above).
struct ExpressionNode {
  enum class Kind : std::uint8_t { constant, signal, add, subtract, negate, scale, abs } kind;
  int left = -1, right = -1;  // operands (expression node indices); scale: left only
  double value = 0.0;         // constant's value; scale's factor
  int signal = -1;            // signal's index into Formula::signals
};

enum class Relation : std::uint8_t { less, less_equal, greater, greater_equal, equal, not_equal };

enum class Operator : std::uint8_t {
  compare,
  negation,
  conjunction,
  disjunction,
  implication,
  always,
  eventually,
  until
};

struct FormulaNode {
  Operator op;
  int left = -1, right = -1;  // subformulas (node indices); unary operators use left
  double lo = 0.0, hi = 0.0;  // temporal operators' interval [lo, hi]; hi = +inf when unbounded
  // compare: lhs and rhs expressions (expression node indices) and the relation
  int lhs = -1, rhs = -1;
  Relation relation = Relation::less;
};

struct Formula {
  std::vector<std::string> signals;  // the names a parse accepted, in the caller's order
  std::vector<ExpressionNode> expressions;
  std::vector<FormulaNode> nodes;  // children before parents; the root is last
  std::string text;                // as given

  int root() const { return static_cast<int>(nodes.size()) - 1; }
  // How far past its start a trace must reach for every window to be inside it (the sum of the
  // interval ends along the deepest path; +inf with an unbounded operator).
  double horizon() const;
  // The same for the subformula at node `node`: how far past a sample its value looks.
  double horizon(int node) const;
  // The number of temporal operators (always, eventually, until).
  int temporal_operators() const;
};

// The deepest nesting of parentheses and operators a requirement may have.
inline constexpr int kMaxRequirementDepth = 256;

// Parses `text` over the given signal names. Throws RequirementError (with its column) on
// anything else: a syntax error, an unknown signal, a non-affine product, an interval that is
// reversed, negative or not finite, a constant that is NaN or infinite, nesting deeper than
// kMaxRequirementDepth.
Formula parse_requirement(std::string_view text, std::span<const std::string> signals);

// The formula written back in the notation above, fully parenthesized (parse(print(f)) == f).
std::string to_string(const Formula& f);

// φ tightened by `margin` m: a formula whose robustness is ρ(φ) + m on every trace, so that it is
// violated exactly where φ's robustness is below −m (the option `margin`: a witness that survives
// a re-simulation a little off). Each comparison moves by m toward its violation, in the direction
// its polarity asks (under `not` or left of `->` the other way): e1 < e2 becomes e1 < e2 + m, and
// an equality e1 == e2, whose robustness 0.5 − |e1 − e2| is min(d + 0.5, 0.5 − d) with d = e1 − e2,
// becomes (d >= −(0.5 + m)) and (d <= 0.5 + m); e1 != e2 likewise. min, max and the temporal
// operators commute with adding a constant, so the shift reaches the root unchanged. text is
// to_string of the result.
Formula with_margin(const Formula& f, double margin);

// The scale of a requirement's thresholds: the largest |constant| in its comparisons (AT2's 4750
// rpm, CC1's 40 m; 0 when it has none). A witness whose robustness lies within 1 % of it is one a
// simulator a little off could refute (the league's "near the threshold" count).
double threshold_scale(const Formula& f);

}  // namespace hyfal::stl
