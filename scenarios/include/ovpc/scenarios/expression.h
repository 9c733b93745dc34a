// Small arithmetic and logical expressions over named values, for scenario families (family.h):
// `${roof_m + 0.1}` in a scenario body and `when: "roof_m >= 2.3 and not kind == 'ramp'"` in an
// expect rule. A hand-written recursive-descent parser; no dependency.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace ovpc::scenarios {

/// A value of a family parameter or of an expression: a number or a word (e.g. a terrain kind).
struct Value {
  bool is_number = true;
  double number = 0.0;
  std::string word;  ///< when !is_number

  static Value Number(double v) { return Value{true, v, {}}; }
  static Value Word(std::string w) { return Value{false, 0.0, std::move(w)}; }
  /// The shortest decimal that reads back as the same double, or the word.
  std::string ToString() const;
  bool operator==(const Value& o) const {
    return is_number == o.is_number && (is_number ? number == o.number : word == o.word);
  }
};

/// A malformed expression, or one that cannot be evaluated (division by zero, an unknown name, a
/// word in arithmetic). what() is one line naming the problem and, for syntax, the column.
class ExpressionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Grammar, loosest binding first:
///   or: and ('or' and)* · and: not ('and' not)* · not: 'not' not | compare
///   compare: sum (('<'|'<='|'>'|'>='|'=='|'!=') sum)? · sum: product (('+'|'-') product)*
///   product: unary (('*'|'/') unary)* · unary: ('-'|'+') unary | primary
///   primary: number | 'word' | "word" | name | function '(' or (',' or)* ')' | '(' or ')'
/// Functions: sin cos tan (radians) sqrt abs deg2rad (one argument), min max (two or more). Names
/// start with a letter or '_' and may hold letters, digits, '_' and '.' (an inline distribution's
/// dotted path). Comparisons and logic give 1 or 0; a number is true when it is not 0.
///
/// Limits, so that no text makes the parser, the evaluator or the tree recurse without bound: at
/// most kMaxLength characters, and at most kMaxDepth levels of nesting, counted over parentheses,
/// function calls, signs, `not` and operators in a row (a chain `a + b + ...` has at most kMaxDepth
/// terms; `min` and `max` take any number of arguments).
class Expression {
 public:
  static constexpr std::size_t kMaxLength = 4096;
  static constexpr int kMaxDepth = 100;

  /// @throws ExpressionError naming the column of a syntax error or of a limit exceeded.
  static Expression Parse(const std::string& text);

  /// @throws ExpressionError (unknown name, division by zero, sqrt of a negative number, a word
  /// where a number is needed, a result that is not finite).
  Value Evaluate(const std::map<std::string, Value>& names) const;
  /// Evaluate() as a condition: a number, true when not 0.
  bool Test(const std::map<std::string, Value>& names) const;

  /// The names it refers to (each once, in the order they appear).
  const std::vector<std::string>& names() const { return names_; }
  const std::string& text() const { return text_; }

  struct Node;

 private:
  std::string text_;
  std::shared_ptr<const Node> root_;
  std::vector<std::string> names_;
};

}  // namespace ovpc::scenarios
