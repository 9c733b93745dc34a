#include "ovpc/scenarios/expression.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

const std::map<std::string, Value> kNames = {{"roof_m", Value::Number(2.5)},
                                             {"kind", Value::Word("ramp")},
                                             {"objects.0.carport.x_m", Value::Number(12.0)}};

double Eval(const std::string& text) {
  const Value v = Expression::Parse(text).Evaluate(kNames);
  EXPECT_TRUE(v.is_number) << text;
  return v.number;
}

std::string ParseError(const std::string& text) {
  try {
    Expression::Parse(text);
  } catch (const ExpressionError& e) {
    return e.what();
  }
  return "";
}

std::string EvalError(const std::string& text) {
  try {
    Expression::Parse(text).Evaluate(kNames);
  } catch (const ExpressionError& e) {
    return e.what();
  }
  return "";
}

TEST(ExpressionTest, ArithmeticPrecedenceAndAssociativity) {
  EXPECT_DOUBLE_EQ(Eval("1 + 2 * 3"), 7.0);
  EXPECT_DOUBLE_EQ(Eval("(1 + 2) * 3"), 9.0);
  EXPECT_DOUBLE_EQ(Eval("2 - 3 - 4"), -5.0);
  EXPECT_DOUBLE_EQ(Eval("8 / 4 / 2"), 1.0);
  EXPECT_DOUBLE_EQ(Eval("-2 * 3"), -6.0);
  EXPECT_DOUBLE_EQ(Eval("2 - -3"), 5.0);
  EXPECT_DOUBLE_EQ(Eval("-(1 + 2) * +2"), -6.0);
  EXPECT_DOUBLE_EQ(Eval("1.5e1 + .5"), 15.5);
  EXPECT_DOUBLE_EQ(Eval("roof_m * 2 + objects.0.carport.x_m"), 17.0);
}

TEST(ExpressionTest, FunctionsComparisonsAndLogic) {
  EXPECT_NEAR(Eval("deg2rad(180)"), M_PI, 1e-15);
  EXPECT_NEAR(Eval("sin(deg2rad(30))"), 0.5, 1e-15);
  EXPECT_NEAR(Eval("cos(0) + tan(0)"), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(Eval("sqrt(16) + abs(-2)"), 6.0);
  EXPECT_DOUBLE_EQ(Eval("min(3, 1, 2) + max(3, roof_m)"), 4.0);
  EXPECT_DOUBLE_EQ(Eval("roof_m >= 2.5"), 1.0);
  EXPECT_DOUBLE_EQ(Eval("roof_m < 2.5"), 0.0);
  EXPECT_DOUBLE_EQ(Eval("1 + 1 == 2"), 1.0);  // arithmetic binds tighter than comparison
  EXPECT_DOUBLE_EQ(Eval("1 or 0 and 0"), 1.0);  // and binds tighter than or
  EXPECT_DOUBLE_EQ(Eval("not 1 or 1"), 1.0);  // not binds tighter than or
  EXPECT_DOUBLE_EQ(Eval("not (1 or 1)"), 0.0);
  EXPECT_DOUBLE_EQ(Eval("not roof_m > 3 and kind == 'ramp'"), 1.0);
  EXPECT_DOUBLE_EQ(Eval("kind != \"flat\""), 1.0);
  EXPECT_TRUE(Expression::Parse("roof_m >= 2.4").Test(kNames));
  const Value word = Expression::Parse("kind").Evaluate(kNames);
  EXPECT_FALSE(word.is_number);
  EXPECT_EQ(word.word, "ramp");
  // 'order' and 'note' are names, not the keywords they start with.
  EXPECT_EQ(Expression::Parse("order + note").names(), (std::vector<std::string>{"order", "note"}));
  EXPECT_EQ(Expression::Parse("roof_m + roof_m * x").names(), (std::vector<std::string>{"roof_m", "x"}));
}

TEST(ExpressionTest, SyntaxErrorsNameTheColumn) {
  EXPECT_EQ(ParseError("1 +"), "in '1 +' at column 4: expected a number, a name or '(' but the expression ends");
  EXPECT_EQ(ParseError("(1 + 2"), "in '(1 + 2' at column 7: expected ')'");
  EXPECT_EQ(ParseError("2 $ 3"), "in '2 $ 3' at column 3: unexpected '$'");
  EXPECT_NE(ParseError("roof_m = 2").find("column 8: unexpected '=' (compare with '==')"), std::string::npos);
  EXPECT_NE(ParseError("cosh(1)").find("column 1: unknown function 'cosh'"), std::string::npos);
  EXPECT_NE(ParseError("sin(1, 2)").find("'sin' takes one argument"), std::string::npos);
  EXPECT_NE(ParseError("max(1)").find("'max' takes two or more arguments"), std::string::npos);
  EXPECT_NE(ParseError("1 < 2 < 3").find("unexpected '<'"), std::string::npos);
  EXPECT_NE(ParseError("'ramp").find("unterminated"), std::string::npos);
  EXPECT_NE(ParseError("and 1").find("'and' needs a value before it"), std::string::npos);
  EXPECT_NE(ParseError("").find("the expression ends"), std::string::npos);
}

TEST(ExpressionTest, EvaluationErrors) {
  EXPECT_EQ(EvalError("1 / (roof_m - 2.5)"), "in '1 / (roof_m - 2.5)': division by zero");
  EXPECT_NE(EvalError("sqrt(-1)").find("sqrt of a negative number"), std::string::npos);
  EXPECT_NE(EvalError("kind + 1").find("'ramp' is a word, not a number"), std::string::npos);
  EXPECT_NE(EvalError("kind == 1").find("compares a word with a number"), std::string::npos);
  EXPECT_NE(EvalError("height_m").find("unknown name 'height_m'"), std::string::npos);
  EXPECT_NE(EvalError("1e308 * 10").find("not a finite number"), std::string::npos);
}

std::string Repeat(const std::string& unit, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += unit;
  return s;
}

// Inputs that once overflowed the stack (SIGSEGV) in the parser, the evaluator or the destructor of
// the tree: each is refused with an ExpressionError naming the column, or evaluated when within the
// limits.
TEST(ExpressionTest, DeepOrLongInputsAreRefusedNotACrash) {
  const std::size_t depth = Expression::kMaxDepth;
  EXPECT_DOUBLE_EQ(Eval(Repeat("(", depth) + "1" + Repeat(")", depth)), 1.0);
  EXPECT_DOUBLE_EQ(Eval(Repeat("-", depth - 2) + "1"), 1.0);  // 98 signs: 99 nodes deep
  EXPECT_DOUBLE_EQ(Eval("1" + Repeat("+1", depth - 1)), static_cast<double>(depth));
  EXPECT_DOUBLE_EQ(Eval("max(0" + Repeat(",1", 1000) + ")"), 1.0);  // arguments are not levels
  const std::string too_deep = "nested more than 100 levels deep";
  EXPECT_NE(ParseError(Repeat("(", depth + 1) + "1" + Repeat(")", depth + 1)).find("at column 102: " + too_deep), std::string::npos);
  EXPECT_NE(ParseError(Repeat("(", 5000) + "1" + Repeat(")", 5000)).find("the limit is 4096"), std::string::npos);
  EXPECT_NE(ParseError(Repeat("(", 2000) + "1" + Repeat(")", 2000)).find(too_deep), std::string::npos);
  EXPECT_NE(ParseError("1" + Repeat("+1", depth)).find(too_deep), std::string::npos);
  EXPECT_NE(ParseError("1" + Repeat("+1", 2000)).find(too_deep), std::string::npos);
  EXPECT_NE(ParseError("1" + Repeat("*1", 2000)).find(too_deep), std::string::npos);
  EXPECT_NE(ParseError("1" + Repeat(" or 1", 800)).find(too_deep), std::string::npos);
  EXPECT_NE(ParseError(Repeat("-", 4000) + "1").find(too_deep), std::string::npos);
  EXPECT_NE(ParseError(Repeat("+", 4000) + "1").find(too_deep), std::string::npos);
  EXPECT_NE(ParseError(Repeat("not ", 1000) + "1").find(too_deep), std::string::npos);
  EXPECT_NE(ParseError(Repeat("abs(", 500) + "1" + Repeat(")", 500)).find(too_deep), std::string::npos);
  // The inputs of the report: 30,000 terms, 100,000 signs: refused by their length, in one short line.
  const std::string sum = ParseError("1" + Repeat("+1", 29999));
  EXPECT_NE(sum.find("at column 4097: the expression is 59999 characters long; the limit is 4096"), std::string::npos) << sum;
  EXPECT_LT(sum.size(), 200u);
  EXPECT_NE(ParseError(Repeat("-", 100000) + "1").find("the limit is 4096"), std::string::npos);
}

}  // namespace
}  // namespace ovpc::scenarios
