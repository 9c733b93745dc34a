#include "ovpc/scenarios/pass_rate.h"

#include <string>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

JudgedRun Judged(const std::string& name, Value v, Expectation e, Verdict verdict) { return {{{name, v}}, e, verdict}; }

Parameter Uniform(double lo, double hi) {
  Parameter p{"roof_m", {}, 1};
  p.distribution.lo = lo, p.distribution.hi = hi;
  return p;
}

TEST(PassRateTest, ContinuousParametersGetFiveEqualBinsOverTheirRange) {
  const Parameter p = Uniform(1.5, 3.5);
  const std::vector<JudgedRun> runs = {
      Judged("roof_m", Value::Number(1.5), Expectation::kRefuse, Verdict::kOk),
      Judged("roof_m", Value::Number(1.6), Expectation::kRefuse, Verdict::kViolated),
      Judged("roof_m", Value::Number(2.3), Expectation::kAny, Verdict::kNotCounted),
      Judged("roof_m", Value::Number(2.5), Expectation::kPass, Verdict::kOk),
      Judged("roof_m", Value::Number(2.69), Expectation::kPass, Verdict::kError),
      Judged("roof_m", Value::Number(3.5), Expectation::kPass, Verdict::kOk),  // the top edge is in the last bin
  };
  const PassRateTable t = TabulatePassRate(p, runs);
  EXPECT_TRUE(t.binned);
  EXPECT_EQ(t.kind, "uniform");
  ASSERT_EQ(t.rows.size(), 5u);
  EXPECT_EQ(t.rows[0].label, "[1.5, 1.9)");
  EXPECT_EQ(t.rows[4].label, "[3.1, 3.5]");
  EXPECT_DOUBLE_EQ(t.rows[2].lo, 2.3);
  EXPECT_EQ(t.rows[0].refuse_runs, 2u);
  EXPECT_EQ(t.rows[0].refuse_ok, 1u);
  EXPECT_EQ(t.rows[2].any_runs, 1u);
  EXPECT_EQ(t.rows[2].pass_runs, 2u);
  EXPECT_EQ(t.rows[2].pass_ok, 1u) << "a run with an error is not ok";
  EXPECT_EQ(t.rows[4].pass_ok, 1u);
  EXPECT_EQ(t.rows[1].pass_runs + t.rows[1].refuse_runs + t.rows[3].pass_runs, 0u);

  const std::string text = FormatPassRateTable("roofs", t);
  EXPECT_NE(text.find("roofs: pass rate against roof_m (uniform, 5 bins)"), std::string::npos) << text;
  EXPECT_NE(text.find("[1.5, 1.9)             -                  1/2 (50%)          0"), std::string::npos) << text;
  const std::string csv = PassRateCsv({t});
  EXPECT_EQ(csv.rfind("parameter,bin,lo,hi,pass_ok,pass_runs,refuse_ok,refuse_runs,any_runs\n"
                      "roof_m,\"[1.5, 1.9)\",1.5,1.9,0,0,1,2,0\n", 0), 0u) << csv;
}

TEST(PassRateTest, FewValuesGetARowEach) {
  Parameter kind{"kind", {}, 1};
  kind.distribution.kind = Distribution::Kind::kChoice;
  kind.distribution.values = {Value::Word("flat"), Value::Word("ramp")};
  const PassRateTable t = TabulatePassRate(kind, {Judged("kind", Value::Word("ramp"), Expectation::kPass, Verdict::kOk),
                                                  Judged("kind", Value::Word("ramp"), Expectation::kPass, Verdict::kViolated)});
  EXPECT_FALSE(t.binned);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].pass_runs, 0u);
  EXPECT_EQ(t.rows[1].label, "ramp");
  EXPECT_EQ(t.rows[1].pass_ok, 1u);
  EXPECT_EQ(t.rows[1].pass_runs, 2u);

  Parameter seed{"seed", {}, 1};
  seed.distribution.kind = Distribution::Kind::kInteger;
  seed.distribution.lo = 1, seed.distribution.hi = 3;
  EXPECT_EQ(TabulatePassRate(seed, {}).rows.size(), 3u);
  seed.distribution.hi = 1000;  // many values: bins
  const PassRateTable many = TabulatePassRate(seed, {Judged("seed", Value::Number(1000), Expectation::kPass, Verdict::kOk)});
  EXPECT_TRUE(many.binned);
  EXPECT_EQ(many.rows.back().pass_runs, 1u);

  // An unclipped normal is binned over the drawn values' span.
  Parameter normal{"n", {}, 1};
  normal.distribution.kind = Distribution::Kind::kNormal;
  const PassRateTable n = TabulatePassRate(normal, {Judged("n", Value::Number(-1), Expectation::kPass, Verdict::kOk),
                                                    Judged("n", Value::Number(4), Expectation::kPass, Verdict::kOk)});
  EXPECT_DOUBLE_EQ(n.rows.front().lo, -1.0);
  EXPECT_DOUBLE_EQ(n.rows.back().hi, 4.0);
  EXPECT_EQ(n.rows.front().pass_runs + n.rows.back().pass_runs, 2u);
}

TEST(PassRateTest, SvgHasAxesLabelsAndCounts) {
  const PassRateTable t = TabulatePassRate(Uniform(1.5, 3.5), {Judged("roof_m", Value::Number(2.5), Expectation::kPass, Verdict::kOk),
                                                              Judged("roof_m", Value::Number(1.6), Expectation::kRefuse, Verdict::kViolated),
                                                              Judged("roof_m", Value::Number(2.3), Expectation::kAny, Verdict::kNotCounted)});
  const std::string svg = PassRateSvg("roofs & more", t);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_NE(svg.find("roofs &amp; more: pass rate against roof_m"), std::string::npos);
  EXPECT_NE(svg.find(">roof_m (uniform, bins)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">100%</text>"), std::string::npos);
  EXPECT_NE(svg.find(">[2.3, 2.7)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">1/1</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0/1</text>"), std::string::npos);
  EXPECT_NE(svg.find("1 runs expected 'any' (not counted)"), std::string::npos);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

}  // namespace
}  // namespace ovpc::scenarios
