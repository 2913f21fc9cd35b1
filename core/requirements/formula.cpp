// The requirement parser: a tokenizer that matches parentheses first, then recursive descent
// with one token of lookahead. Whether a '(' opens a formula or an expression is decided by the
// token after its matching ')': a relation or an arithmetic operator there makes it an
// expression ("(y5 - y4) <= 40"), anything else a formula ("(y5 - y4 <= 40) and ..."). So the
// parser never backtracks, and its work is linear in the text.
#include "core/requirements/formula.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace hyfal::stl {

RequirementError::RequirementError(int column, const std::string& message)
    : InputError(fmt::format("column {}: {}", column, message)), column_(column) {}

RequirementError::RequirementError(std::string_view context, const RequirementError& error)
    : InputError(fmt::format("{}: {}", context, error.what())), column_(error.column()) {}

namespace {

enum class Tok : std::uint8_t {
  end,
  number,
  name,
  lparen,
  rparen,
  lbracket,
  rbracket,
  comma,
  plus,
  minus,
  star,
  slash,
  less,
  less_equal,
  greater,
  greater_equal,
  equal,
  not_equal,
  implies,
  and_,
  or_,
  not_,
};

struct Token {
  Tok kind;
  int column;  // 1-based
  std::string_view text;
  double number = 0.0;
  int match = -1;  // lparen: the index of its rparen
};

bool is_name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_name_char(char c) { return is_name_start(c) || (c >= '0' && c <= '9'); }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::vector<Token> tokenize(std::string_view s) {
  std::vector<Token> out;
  std::vector<std::size_t> open;  // unmatched '(' tokens
  std::size_t i = 0;
  const auto col = [&](std::size_t at) { return static_cast<int>(at) + 1; };
  while (i < s.size()) {
    const char c = s[i];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    auto two = [&](char next) { return i < s.size() && s[i] == next; };  // i is past c here
    Token t{Tok::end, col(start), {}};
    if (is_digit(c) || (c == '.' && i + 1 < s.size() && is_digit(s[i + 1]))) {
      while (i < s.size() && (is_digit(s[i]) || s[i] == '.')) ++i;
      if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        std::size_t j = i + 1;
        if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
        if (j < s.size() && is_digit(s[j])) {
          i = j;
          while (i < s.size() && is_digit(s[i])) ++i;
        }
      }
      if (i < s.size() && is_name_char(s[i]))
        throw RequirementError(col(start), fmt::format("malformed number '{}'", s.substr(start, i + 1 - start)));
      t.kind = Tok::number;
      t.text = s.substr(start, i - start);
      const auto [end, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), t.number);
      if (ec == std::errc::result_out_of_range || (ec == std::errc() && !std::isfinite(t.number)))
        throw RequirementError(col(start), fmt::format("number '{}' is out of range", t.text));
      if (ec != std::errc() || end != t.text.data() + t.text.size())
        throw RequirementError(col(start), fmt::format("malformed number '{}'", t.text));
    } else if (is_name_start(c)) {
      while (i < s.size() && is_name_char(s[i])) ++i;
      t.text = s.substr(start, i - start);
      t.kind = t.text == "and" ? Tok::and_ : t.text == "or" ? Tok::or_ : t.text == "not" ? Tok::not_ : Tok::name;
    } else {
      ++i;
      switch (c) {
        case '(':
          t.kind = Tok::lparen;
          break;
        case ')':
          t.kind = Tok::rparen;
          break;
        case '[':
          t.kind = Tok::lbracket;
          break;
        case ']':
          t.kind = Tok::rbracket;
          break;
        case ',':
          t.kind = Tok::comma;
          break;
        case '+':
          t.kind = Tok::plus;
          break;
        case '*':
          t.kind = Tok::star;
          break;
        case '/':
          t.kind = Tok::slash;
          break;
        case '-':
          if (two('>'))
            ++i, t.kind = Tok::implies;
          else
            t.kind = Tok::minus;
          break;
        case '=':
          if (two('='))
            ++i, t.kind = Tok::equal;
          else if (two('>'))
            ++i, t.kind = Tok::implies;
          else
            throw RequirementError(col(start), "'=' is not an operator (equality is '==')");
          break;
        case '<':
          if (two('='))
            ++i, t.kind = Tok::less_equal;
          else
            t.kind = Tok::less;
          break;
        case '>':
          if (two('='))
            ++i, t.kind = Tok::greater_equal;
          else
            t.kind = Tok::greater;
          break;
        case '!':
          if (two('='))
            ++i, t.kind = Tok::not_equal;
          else
            t.kind = Tok::not_;
          break;
        case '&':
          if (!two('&')) throw RequirementError(col(start), "'&' is not an operator (conjunction is 'and' or '&&')");
          ++i, t.kind = Tok::and_;
          break;
        case '|':
          if (!two('|')) throw RequirementError(col(start), "'|' is not an operator (disjunction is 'or' or '||')");
          ++i, t.kind = Tok::or_;
          break;
        default: {
          const unsigned char u = static_cast<unsigned char>(c);
          if (u >= 0x80 || u < 0x20) throw RequirementError(col(start), fmt::format("unexpected byte 0x{:02x}", u));
          throw RequirementError(col(start), fmt::format("unexpected character '{}'", c));
        }
      }
      t.text = s.substr(start, i - start);
    }
    if (t.kind == Tok::lparen) open.push_back(out.size());
    if (t.kind == Tok::rparen) {
      if (open.empty()) throw RequirementError(t.column, "')' without a matching '('");
      out[open.back()].match = static_cast<int>(out.size());
      open.pop_back();
    }
    out.push_back(t);
  }
  if (!open.empty()) throw RequirementError(out[open.back()].column, "'(' is never closed");
  out.push_back({Tok::end, col(s.size()), {}});
  return out;
}

bool is_relation(Tok k) {
  return k == Tok::less || k == Tok::less_equal || k == Tok::greater || k == Tok::greater_equal || k == Tok::equal ||
         k == Tok::not_equal;
}
bool is_arithmetic(Tok k) { return k == Tok::plus || k == Tok::minus || k == Tok::star || k == Tok::slash; }

std::string describe(const Token& t) {
  if (t.kind == Tok::end) return "the end";
  return fmt::format("'{}'", t.text);
}

class Parser {
 public:
  Parser(std::string_view text, std::span<const std::string> signals) : tokens_(tokenize(text)) {
    f_.signals.assign(signals.begin(), signals.end());
    f_.text = std::string(text);
  }

  Formula parse() {
    if (peek().kind == Tok::end) throw RequirementError(peek().column, "empty requirement");
    implication();
    if (peek().kind != Tok::end) throw RequirementError(peek().column, fmt::format("unexpected {}", describe(peek())));
    return std::move(f_);
  }

 private:
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next() { return tokens_[pos_++]; }
  bool accept(Tok k) {
    if (peek().kind != k) return false;
    ++pos_;
    return true;
  }
  void expect(Tok k, const char* what) {
    if (peek().kind != k)
      throw RequirementError(peek().column, fmt::format("expected {}, found {}", what, describe(peek())));
    ++pos_;
  }

  // Nesting guard: every recursive production enters one.
  struct Depth {
    Parser& p;
    explicit Depth(Parser& parser) : p(parser) {
      if (++p.depth_ > kMaxRequirementDepth)
        throw RequirementError(p.peek().column, fmt::format("nested deeper than {} levels", kMaxRequirementDepth));
    }
    ~Depth() { --p.depth_; }
  };

  int add(FormulaNode n) {
    f_.nodes.push_back(n);
    return static_cast<int>(f_.nodes.size()) - 1;
  }
  int add(ExpressionNode n) {
    f_.expressions.push_back(n);
    return static_cast<int>(f_.expressions.size()) - 1;
  }

  int implication() {
    const Depth d(*this);
    const int l = disjunction();
    if (!accept(Tok::implies)) return l;
    const int r = implication();
    return add(FormulaNode{Operator::implication, l, r});
  }
  // A left-associative chain: operand (op operand)*.
  template <int (Parser::*Operand)()>
  int chain(Tok op, Operator node) {
    int l = (this->*Operand)();
    while (accept(op)) {
      const int r = (this->*Operand)();
      l = add(FormulaNode{node, l, r});
    }
    return l;
  }
  int disjunction() { return chain<&Parser::conjunction>(Tok::or_, Operator::disjunction); }
  int conjunction() { return chain<&Parser::until>(Tok::and_, Operator::conjunction); }
  int until() {
    int l = unary();
    while (peek().kind == Tok::name && peek().text == "until") {
      ++pos_;
      const auto [lo, hi] = interval();
      const int r = unary();
      FormulaNode n{Operator::until, l, r, lo, hi};
      l = add(n);
    }
    return l;
  }
  int unary() {
    const Depth d(*this);
    if (accept(Tok::not_)) {
      const int c = unary();
      return add(FormulaNode{Operator::negation, c});
    }
    if (peek().kind == Tok::name && (peek().text == "always" || peek().text == "eventually")) {
      const Operator op = next().text == "always" ? Operator::always : Operator::eventually;
      const auto [lo, hi] = interval();
      const int c = unary();
      return add(FormulaNode{op, c, -1, lo, hi});
    }
    if (peek().kind == Tok::lparen && !opens_expression()) {
      ++pos_;
      const int inner = implication();
      expect(Tok::rparen, "')'");
      return inner;
    }
    return comparison();
  }
  // A '(' whose matching ')' is followed by a relation or an arithmetic operator opens an
  // expression.
  bool opens_expression() const {
    const Tok after = tokens_[static_cast<std::size_t>(peek().match) + 1].kind;
    return is_relation(after) || is_arithmetic(after);
  }
  // An optional [lo, hi] after a temporal operator; none means [0, +inf).
  std::pair<double, double> interval() {
    if (!accept(Tok::lbracket)) return {0.0, std::numeric_limits<double>::infinity()};
    const Token& open = tokens_[pos_ - 1];
    const double lo = bound("the interval's start");
    expect(Tok::comma, "','");
    const double hi = bound("the interval's end");
    expect(Tok::rbracket, "']'");
    if (hi < lo) throw RequirementError(open.column, fmt::format("reversed interval [{}, {}]", lo, hi));
    return {lo, hi};
  }
  double bound(const char* what) {
    const Token& t = peek();
    if (t.kind == Tok::minus) throw RequirementError(t.column, fmt::format("{} must be >= 0", what));
    if (t.kind != Tok::number)
      throw RequirementError(t.column, fmt::format("expected a number for {}, found {}", what, describe(t)));
    ++pos_;
    return t.number;
  }

  int comparison() {
    const int lhs = expression();
    const Token& t = peek();
    if (!is_relation(t.kind))
      throw RequirementError(t.column,
                             fmt::format("expected a comparison (<, <=, >, >=, ==, !=), found {}", describe(t)));
    ++pos_;
    const int rhs = expression();
    FormulaNode n{Operator::compare};
    n.lhs = lhs;
    n.rhs = rhs;
    n.relation = t.kind == Tok::less            ? Relation::less
                 : t.kind == Tok::less_equal    ? Relation::less_equal
                 : t.kind == Tok::greater       ? Relation::greater
                 : t.kind == Tok::greater_equal ? Relation::greater_equal
                 : t.kind == Tok::equal         ? Relation::equal
                                                : Relation::not_equal;
    return add(n);
  }

  bool constant(int e) const { return f_.expressions[e].kind == ExpressionNode::Kind::constant; }
  double value(int e) const { return f_.expressions[e].value; }
  int make_constant(double v, int column) {
    if (!std::isfinite(v)) throw RequirementError(column, "the constant overflows");
    return add(ExpressionNode{ExpressionNode::Kind::constant, -1, -1, v});
  }

  int expression() {
    int l = term();
    for (;;) {
      const Token& t = peek();
      if (t.kind != Tok::plus && t.kind != Tok::minus) return l;
      ++pos_;
      const int r = term();
      const bool plus = t.kind == Tok::plus;
      if (constant(l) && constant(r))
        l = make_constant(plus ? value(l) + value(r) : value(l) - value(r), t.column);
      else
        l = add(ExpressionNode{plus ? ExpressionNode::Kind::add : ExpressionNode::Kind::subtract, l, r});
    }
  }
  int term() {
    int l = factor();
    for (;;) {
      const Token& t = peek();
      if (t.kind != Tok::star && t.kind != Tok::slash) return l;
      ++pos_;
      const int r = factor();
      if (t.kind == Tok::slash) {
        if (!constant(r)) throw RequirementError(t.column, "division by a signal is not affine");
        if (value(r) == 0.0) throw RequirementError(t.column, "division by zero");
        l = scale(l, 1.0 / value(r), t.column);
      } else if (constant(r)) {
        l = scale(l, value(r), t.column);
      } else if (constant(l)) {
        l = scale(r, value(l), t.column);
      } else {
        throw RequirementError(t.column, "a product of two signals is not affine");
      }
    }
  }
  int scale(int e, double k, int column) {
    if (constant(e)) return make_constant(value(e) * k, column);
    return add(ExpressionNode{ExpressionNode::Kind::scale, e, -1, k});
  }
  int factor() {
    const Depth d(*this);
    const Token& t = next();
    switch (t.kind) {
      case Tok::minus: {
        const int e = factor();
        if (constant(e)) return make_constant(-value(e), t.column);
        return add(ExpressionNode{ExpressionNode::Kind::negate, e});
      }
      case Tok::plus:
        return factor();
      case Tok::number:
        return make_constant(t.number, t.column);
      case Tok::lparen: {
        const int e = expression();
        expect(Tok::rparen, "')'");
        return e;
      }
      case Tok::name: {
        if (t.text == "abs") {
          expect(Tok::lparen, "'(' after abs");
          const int e = expression();
          expect(Tok::rparen, "')'");
          if (constant(e)) return make_constant(std::abs(value(e)), t.column);
          return add(ExpressionNode{ExpressionNode::Kind::abs, e});
        }
        const auto it = std::find(f_.signals.begin(), f_.signals.end(), t.text);
        if (it == f_.signals.end()) {
          if (t.text == "always" || t.text == "eventually" || t.text == "until")
            throw RequirementError(t.column, fmt::format("'{}' needs a formula, not a value, here", t.text));
          std::string known;
          for (const auto& s : f_.signals) known += (known.empty() ? "" : ", ") + s;
          throw RequirementError(
              t.column, fmt::format("unknown signal '{}' (signals: {})", t.text, known.empty() ? "none" : known));
        }
        ExpressionNode n{ExpressionNode::Kind::signal};
        n.signal = static_cast<int>(it - f_.signals.begin());
        return add(n);
      }
      default:
        throw RequirementError(t.column, fmt::format("expected a signal, a number or '(', found {}", describe(t)));
    }
  }

  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  Formula f_;
};

std::string number_text(double v) { return fmt::format("{}", v); }  // shortest round-trip form

std::string expression_text(const Formula& f, int e) {
  const ExpressionNode& n = f.expressions[e];
  switch (n.kind) {
    case ExpressionNode::Kind::constant:
      return n.value < 0 ? "(" + number_text(n.value) + ")" : number_text(n.value);
    case ExpressionNode::Kind::signal:
      return f.signals[n.signal];
    case ExpressionNode::Kind::add:
      return "(" + expression_text(f, n.left) + " + " + expression_text(f, n.right) + ")";
    case ExpressionNode::Kind::subtract:
      return "(" + expression_text(f, n.left) + " - " + expression_text(f, n.right) + ")";
    case ExpressionNode::Kind::negate:
      return "(-" + expression_text(f, n.left) + ")";
    case ExpressionNode::Kind::scale:
      return "(" + number_text(n.value) + " * " + expression_text(f, n.left) + ")";
    case ExpressionNode::Kind::abs:
      return "abs(" + expression_text(f, n.left) + ")";
  }
  return {};
}

std::string interval_text(const FormulaNode& n) {
  if (n.lo == 0.0 && std::isinf(n.hi)) return "";
  return fmt::format("[{},{}]", number_text(n.lo), number_text(n.hi));
}

std::string formula_text(const Formula& f, int i) {
  const FormulaNode& n = f.nodes[i];
  static constexpr const char* kRelation[] = {"<", "<=", ">", ">=", "==", "!="};
  switch (n.op) {
    case Operator::compare:
      return "(" + expression_text(f, n.lhs) + " " + kRelation[static_cast<int>(n.relation)] + " " +
             expression_text(f, n.rhs) + ")";
    case Operator::negation:
      return "(not " + formula_text(f, n.left) + ")";
    case Operator::conjunction:
      return "(" + formula_text(f, n.left) + " and " + formula_text(f, n.right) + ")";
    case Operator::disjunction:
      return "(" + formula_text(f, n.left) + " or " + formula_text(f, n.right) + ")";
    case Operator::implication:
      return "(" + formula_text(f, n.left) + " -> " + formula_text(f, n.right) + ")";
    case Operator::always:
      return "(always" + interval_text(n) + " " + formula_text(f, n.left) + ")";
    case Operator::eventually:
      return "(eventually" + interval_text(n) + " " + formula_text(f, n.left) + ")";
    case Operator::until:
      return "(" + formula_text(f, n.left) + " until" + interval_text(n) + " " + formula_text(f, n.right) + ")";
  }
  return {};
}

double horizon_of(const Formula& f, int i) {
  const FormulaNode& n = f.nodes[i];
  double h = 0.0;
  if (n.op == Operator::compare) return 0.0;
  if (n.left >= 0) h = horizon_of(f, n.left);
  if (n.right >= 0) h = std::max(h, horizon_of(f, n.right));
  if (n.op == Operator::always || n.op == Operator::eventually || n.op == Operator::until) h += n.hi;
  return h;
}

}  // namespace

Formula parse_requirement(std::string_view text, std::span<const std::string> signals) {
  return Parser(text, signals).parse();
}

std::string to_string(const Formula& f) { return f.nodes.empty() ? std::string() : formula_text(f, f.root()); }

double threshold_scale(const Formula& f) {
  double scale = 0.0;
  for (const ExpressionNode& e : f.expressions)
    if (e.kind == ExpressionNode::Kind::constant) scale = std::max(scale, std::abs(e.value));
  return scale;
}

Formula with_margin(const Formula& f, double margin) {
  if (f.nodes.empty() || margin == 0.0) return f;
  // Polarity of each node: +1 where its robustness enters the root's with a + sign.
  std::vector<int> polarity(f.nodes.size(), 1);
  for (int i = f.root(); i >= 0; --i) {
    const FormulaNode& n = f.nodes[static_cast<std::size_t>(i)];
    const int p = polarity[static_cast<std::size_t>(i)];
    if (n.op == Operator::compare) continue;
    if (n.left >= 0)
      polarity[static_cast<std::size_t>(n.left)] = n.op == Operator::negation || n.op == Operator::implication ? -p : p;
    if (n.right >= 0) polarity[static_cast<std::size_t>(n.right)] = p;
  }
  Formula out;
  out.signals = f.signals;
  out.expressions = f.expressions;
  const auto constant = [&](double v) {
    out.expressions.push_back({ExpressionNode::Kind::constant, -1, -1, v, -1});
    return static_cast<int>(out.expressions.size()) - 1;
  };
  const auto binary = [&](ExpressionNode::Kind kind, int l, int r) {
    out.expressions.push_back({kind, l, r, 0.0, -1});
    return static_cast<int>(out.expressions.size()) - 1;
  };
  const auto push = [&](FormulaNode n) {
    out.nodes.push_back(n);
    return static_cast<int>(out.nodes.size()) - 1;
  };
  std::vector<int> moved(f.nodes.size(), -1);  // old node index -> new
  for (std::size_t i = 0; i < f.nodes.size(); ++i) {
    FormulaNode n = f.nodes[i];
    if (n.op != Operator::compare) {
      if (n.left >= 0) n.left = moved[static_cast<std::size_t>(n.left)];
      if (n.right >= 0) n.right = moved[static_cast<std::size_t>(n.right)];
      moved[i] = push(n);
      continue;
    }
    const double pm = polarity[i] * margin;
    const auto compare = [&](int lhs, Relation relation, int rhs) {
      FormulaNode c{Operator::compare};
      c.lhs = lhs;
      c.rhs = rhs;
      c.relation = relation;
      return push(c);
    };
    switch (n.relation) {
      case Relation::less:
      case Relation::less_equal:  // ρ = e2 − e1
        moved[i] = compare(n.lhs, n.relation, binary(ExpressionNode::Kind::add, n.rhs, constant(pm)));
        break;
      case Relation::greater:
      case Relation::greater_equal:  // ρ = e1 − e2
        moved[i] = compare(binary(ExpressionNode::Kind::add, n.lhs, constant(pm)), n.relation, n.rhs);
        break;
      case Relation::equal: {  // min(d + 0.5 + pm, 0.5 + pm − d)
        const int d = binary(ExpressionNode::Kind::subtract, n.lhs, n.rhs);
        const int a = compare(d, Relation::greater_equal, constant(-(0.5 + pm)));
        const int b = compare(d, Relation::less_equal, constant(0.5 + pm));
        FormulaNode both{Operator::conjunction};
        both.left = a;
        both.right = b;
        moved[i] = push(both);
        break;
      }
      case Relation::not_equal: {  // max(d − 0.5 + pm, −0.5 + pm − d)
        const int d = binary(ExpressionNode::Kind::subtract, n.lhs, n.rhs);
        const int a = compare(d, Relation::greater, constant(0.5 - pm));
        const int b = compare(d, Relation::less, constant(-0.5 + pm));
        FormulaNode either{Operator::disjunction};
        either.left = a;
        either.right = b;
        moved[i] = push(either);
        break;
      }
    }
  }
  out.text = to_string(out);
  return out;
}

double Formula::horizon() const { return nodes.empty() ? 0.0 : horizon_of(*this, root()); }

double Formula::horizon(int node) const { return horizon_of(*this, node); }

int Formula::temporal_operators() const {
  int k = 0;
  for (const FormulaNode& n : nodes)
    k += n.op == Operator::always || n.op == Operator::eventually || n.op == Operator::until;
  return k;
}

}  // namespace hyfal::stl
