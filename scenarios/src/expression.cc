#include "ovpc/scenarios/expression.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "format.h"

namespace ovpc::scenarios {

std::string Value::ToString() const { return is_number ? internal::FormatNumber(number) : word; }

struct Expression::Node {
  enum class Kind { kLiteral, kName, kUnary, kBinary, kCall };
  Kind kind = Kind::kLiteral;
  Value value;             // kLiteral
  std::string name;        // kName: the name; kUnary, kBinary: the operator; kCall: the function
  std::vector<std::shared_ptr<const Node>> args;
  int height = 1;          // levels of nodes down to the deepest leaf (at most kMaxDepth)
};

namespace {

using NodePtr = std::shared_ptr<const Expression::Node>;
using Kind = Expression::Node::Kind;

std::string Quoted(const std::string& text) { return "'" + internal::Abbreviated(text) + "'"; }

bool NameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool NameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }

// Recursive descent over the text, one method per grammar rule (expression.h). Each way the rules
// recurse (a parenthesis, a function's arguments, 'not', a sign) counts one level, and every node
// has its height; both are bounded by Expression::kMaxDepth, so neither the parser, the evaluator
// nor the tree's destructor recurses deeper than that.
class Parser {
 public:
  explicit Parser(const std::string& text) : s_(text) {}

  NodePtr Whole() {
    if (s_.size() > Expression::kMaxLength) {
      i_ = Expression::kMaxLength;
      Fail("the expression is " + std::to_string(s_.size()) + " characters long; the limit is " +
           std::to_string(Expression::kMaxLength));
    }
    NodePtr n = Or();
    Skip();
    if (i_ < s_.size() && s_[i_] == '=') Fail("unexpected '=' (compare with '==')");
    if (i_ < s_.size()) Fail("unexpected '" + s_.substr(i_, 1) + "'");
    return n;
  }
  std::vector<std::string> names;

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw ExpressionError("in " + Quoted(s_) + " at column " + std::to_string(i_ + 1) + ": " + what);
  }
  [[noreturn]] void FailTooDeep() const {
    Fail("nested more than " + std::to_string(Expression::kMaxDepth) +
         " levels deep (parentheses, signs, 'not', or operators in a row)");
  }
  // One level of a recursive rule, for as long as the rule runs.
  class Level {
   public:
    explicit Level(Parser* p) : p_(p) {
      if (p_->depth_ >= Expression::kMaxDepth) p_->FailTooDeep();
      ++p_->depth_;
    }
    ~Level() { --p_->depth_; }
    Level(const Level&) = delete;
    Level& operator=(const Level&) = delete;

   private:
    Parser* p_;
  };
  NodePtr Make(Kind kind, std::string name, std::vector<NodePtr> args, Value value = {}) const {
    auto n = std::make_shared<Expression::Node>();
    for (const NodePtr& a : args) n->height = std::max(n->height, a->height + 1);
    if (n->height > Expression::kMaxDepth) FailTooDeep();
    n->kind = kind;
    n->name = std::move(name);
    n->args = std::move(args);
    n->value = std::move(value);
    return n;
  }
  void Skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  // Takes `token` if it comes next (a keyword only as a whole word).
  bool Accept(const std::string& token) {
    Skip();
    if (s_.compare(i_, token.size(), token) != 0) return false;
    if (NameStart(token[0]) && i_ + token.size() < s_.size() && NameChar(s_[i_ + token.size()])) return false;
    i_ += token.size();
    return true;
  }
  NodePtr Or() {
    NodePtr n = And();
    while (Accept("or")) n = Make(Kind::kBinary, "or", {n, And()});
    return n;
  }
  NodePtr And() {
    NodePtr n = Not();
    while (Accept("and")) n = Make(Kind::kBinary, "and", {n, Not()});
    return n;
  }
  NodePtr Not() {
    if (!Accept("not")) return Compare();
    const Level level(this);
    return Make(Kind::kUnary, "not", {Not()});
  }
  NodePtr Compare() {
    NodePtr n = Sum();
    for (const char* op : {"<=", ">=", "==", "!=", "<", ">"}) {
      if (Accept(op)) return Make(Kind::kBinary, op, {n, Sum()});
    }
    return n;
  }
  NodePtr Sum() {
    NodePtr n = Product();
    for (;;) {
      if (Accept("+")) n = Make(Kind::kBinary, "+", {n, Product()});
      else if (Accept("-")) n = Make(Kind::kBinary, "-", {n, Product()});
      else return n;
    }
  }
  NodePtr Product() {
    NodePtr n = Unary();
    for (;;) {
      if (Accept("*")) n = Make(Kind::kBinary, "*", {n, Unary()});
      else if (Accept("/")) n = Make(Kind::kBinary, "/", {n, Unary()});
      else return n;
    }
  }
  NodePtr Unary() {
    const bool minus = Accept("-");
    if (!minus && !Accept("+")) return Primary();
    const Level level(this);
    return minus ? Make(Kind::kUnary, "-", {Unary()}) : Unary();
  }
  NodePtr Primary() {
    Skip();
    if (i_ >= s_.size()) Fail("expected a number, a name or '(' but the expression ends");
    const char c = s_[i_];
    if (Accept("(")) {
      const Level level(this);
      NodePtr n = Or();
      if (!Accept(")")) Fail("expected ')'");
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return Number();
    if (c == '\'' || c == '"') return Word(c);
    if (NameStart(c)) return NameOrCall();
    Fail("expected a number, a name or '(' but found '" + std::string(1, c) + "'");
  }
  NodePtr Number() {
    const char* begin = s_.c_str() + i_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) Fail("malformed number");
    i_ += static_cast<std::size_t>(end - begin);
    return Make(Kind::kLiteral, "", {}, Value::Number(v));
  }
  NodePtr Word(char quote) {
    const std::size_t close = s_.find(quote, i_ + 1);
    if (close == std::string::npos) Fail("unterminated quoted word");
    const std::string word = s_.substr(i_ + 1, close - i_ - 1);
    i_ = close + 1;
    return Make(Kind::kLiteral, "", {}, Value::Word(word));
  }
  NodePtr NameOrCall() {
    const std::size_t start = i_;
    while (i_ < s_.size() && NameChar(s_[i_])) ++i_;
    const std::string name = s_.substr(start, i_ - start);
    if (name == "and" || name == "or" || name == "not") Fail("'" + name + "' needs a value before it");
    if (!Accept("(")) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      return Make(Kind::kName, name, {});
    }
    static const std::vector<std::string> kOne = {"sin", "cos", "tan", "sqrt", "abs", "deg2rad"};
    const bool one = std::find(kOne.begin(), kOne.end(), name) != kOne.end();
    if (!one && name != "min" && name != "max") {
      i_ = start;
      Fail("unknown function '" + name + "' (sin, cos, tan, sqrt, abs, deg2rad, min, max)");
    }
    const Level level(this);
    std::vector<NodePtr> args = {Or()};
    while (Accept(",")) args.push_back(Or());
    if (!Accept(")")) Fail("expected ',' or ')'");
    if (one && args.size() != 1) Fail("'" + name + "' takes one argument");
    if (!one && args.size() < 2) Fail("'" + name + "' takes two or more arguments");
    return Make(Kind::kCall, name, std::move(args));
  }

  const std::string& s_;
  std::size_t i_ = 0;
  int depth_ = 0;
};

class Evaluator {
 public:
  Evaluator(const std::map<std::string, Value>& names, const std::string& text) : names_(names), text_(text) {}

  Value Eval(const Expression::Node& n) const {
    switch (n.kind) {
      case Kind::kLiteral: return n.value;
      case Kind::kName: {
        const auto it = names_.find(n.name);
        if (it == names_.end()) Fail("unknown name '" + n.name + "'");
        return it->second;
      }
      case Kind::kUnary:
        if (n.name == "not") return Value::Number(Truth(*n.args[0]) ? 0.0 : 1.0);
        return Value::Number(-Num(*n.args[0], "-"));
      case Kind::kBinary: return Binary(n);
      case Kind::kCall: return Call(n);
    }
    return {};
  }
  bool Truth(const Expression::Node& n) const { return Num(n, "a condition") != 0.0; }

 private:
  [[noreturn]] void Fail(const std::string& what) const { throw ExpressionError("in " + Quoted(text_) + ": " + what); }
  double Num(const Expression::Node& n, const std::string& where) const {
    const Value v = Eval(n);
    if (!v.is_number) Fail("'" + v.word + "' is a word, not a number (in " + where + ")");
    return v.number;
  }
  Value Binary(const Expression::Node& n) const {
    const std::string& op = n.name;
    const auto b = [](bool v) { return Value::Number(v ? 1.0 : 0.0); };
    if (op == "and") return b(Truth(*n.args[0]) && Truth(*n.args[1]));
    if (op == "or") return b(Truth(*n.args[0]) || Truth(*n.args[1]));
    if (op == "==" || op == "!=") {
      const Value l = Eval(*n.args[0]), r = Eval(*n.args[1]);
      if (l.is_number != r.is_number) Fail("'" + op + "' compares a word with a number");
      return b((l == r) == (op == "=="));
    }
    const double l = Num(*n.args[0], "'" + op + "'"), r = Num(*n.args[1], "'" + op + "'");
    if (op == "<") return b(l < r);
    if (op == "<=") return b(l <= r);
    if (op == ">") return b(l > r);
    if (op == ">=") return b(l >= r);
    if (op == "+") return Value::Number(l + r);
    if (op == "-") return Value::Number(l - r);
    if (op == "*") return Value::Number(l * r);
    if (r == 0.0) Fail("division by zero");
    return Value::Number(l / r);
  }
  Value Call(const Expression::Node& n) const {
    const std::string& f = n.name;
    const double x = Num(*n.args[0], f);
    if (f == "min" || f == "max") {
      double m = x;
      for (std::size_t k = 1; k < n.args.size(); ++k) {
        const double y = Num(*n.args[k], f);
        m = f == "min" ? std::min(m, y) : std::max(m, y);
      }
      return Value::Number(m);
    }
    if (f == "sqrt" && x < 0.0) Fail("sqrt of a negative number");
    if (f == "sqrt") return Value::Number(std::sqrt(x));
    if (f == "sin") return Value::Number(std::sin(x));
    if (f == "cos") return Value::Number(std::cos(x));
    if (f == "tan") return Value::Number(std::tan(x));
    if (f == "abs") return Value::Number(std::abs(x));
    return Value::Number(x * M_PI / 180.0);  // deg2rad
  }

  const std::map<std::string, Value>& names_;
  const std::string& text_;
};

}  // namespace

Expression Expression::Parse(const std::string& text) {
  Parser parser(text);
  Expression e;
  e.text_ = text;
  e.root_ = parser.Whole();
  e.names_ = parser.names;
  return e;
}

Value Expression::Evaluate(const std::map<std::string, Value>& names) const {
  const Value v = Evaluator(names, text_).Eval(*root_);
  if (v.is_number && !std::isfinite(v.number)) throw ExpressionError("in " + Quoted(text_) + ": the result is not a finite number");
  return v;
}

bool Expression::Test(const std::map<std::string, Value>& names) const { return Evaluator(names, text_).Truth(*root_); }

}  // namespace ovpc::scenarios
