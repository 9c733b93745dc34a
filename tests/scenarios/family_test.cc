// Scenario families: reading, drawing, writing and judging. Nothing here runs the closed loop.
#include "ovpc/scenarios/family.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

namespace fs = std::filesystem;

// A small family: a named parameter used twice (roof and a post), an expression, an inline
// distribution, a word choice and rules of all three kinds.
const char* kFamily = R"(name: roofs
time_limit_s: 20
parameters:
  roof_m: {uniform: [1.5, 3.5]}
  side: {choice: [left, right]}
terrain: {kind: flat, size_m: [40, 20]}
objects:
  - carport: {x_m: 10.0, y_m: 0.0, roof_height_m: $roof_m}
  - cylinder: {x_m: 5.0, y_m: 3.0, height_m: "${roof_m + 0.25}"}
  - box: {x_m: 15.0, y_m: {normal: [0, 1], clip: [-2, 2]}}
route: [[0, 0], [16, 0]]
criteria:
  goal: {x_m: 16.0, y_m: 0.0}
expect:
  - {when: "roof_m >= 2.4", then: pass}
  - when: "roof_m < 2.2 and side == 'left'"
    then: refuse
    forbidden: [{name: under, min_m: [8, -2], max_m: [12, 2]}]
  - {when: "roof_m < 2.2", then: refuse, forbidden: [{name: under, min_m: [8, "${-roof_m}"], max_m: [12, 2]}]}
  - {then: any, reason: tight}
)";

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The error of reading and drawing a family ("" if none).
std::string FamilyErrorOf(const std::string& text, std::size_t samples = 8) {
  try {
    DrawFamily(ParseFamily(text, "fam.yaml"), {samples, 1});
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

class FamilyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ovpc_family_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(FamilyTest, ReadsParametersInlineDistributionsAndRules) {
  const Family f = ParseFamily(kFamily, "fam.yaml");
  EXPECT_EQ(f.name, "roofs");
  ASSERT_EQ(f.parameters.size(), 3u);
  EXPECT_EQ(f.parameters[0].name, "roof_m");
  EXPECT_EQ(f.parameters[0].line, 4);
  EXPECT_EQ(f.parameters[1].distribution.kind, Distribution::Kind::kChoice);
  EXPECT_EQ(f.parameters[1].distribution.values[1].word, "right");
  EXPECT_EQ(f.parameters[2].name, "objects.2.box.y_m");
  EXPECT_TRUE(f.parameters[2].distribution.clipped);
  ASSERT_EQ(f.rules.size(), 4u);
  EXPECT_EQ(f.rules[1].then, Expectation::kRefuse);
  EXPECT_EQ(f.rules[1].forbidden, 1u);
  EXPECT_EQ(f.rules[1].line, 16);
  EXPECT_FALSE(f.rules[3].when.has_value());
  EXPECT_EQ(f.rules[3].reason, "tight");
  EXPECT_TRUE(IsFamilyText(kFamily));
  EXPECT_FALSE(IsFamilyText("name: x\ntime_limit_s: 3\n"));
  EXPECT_FALSE(IsFamilyText("name: [unclosed\n"));
}

TEST_F(FamilyTest, DrawsAreDeterministicPerSeed) {
  const Family f = ParseFamily(kFamily, "fam.yaml");
  const auto a = DrawFamily(f, {6, 1}), b = DrawFamily(f, {6, 1}), c = DrawFamily(f, {6, 2});
  ASSERT_EQ(a.size(), 6u);
  std::size_t different = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].yaml, b[i].yaml);
    EXPECT_EQ(a[i].name, "roofs_00" + std::to_string(i));
    different += a[i].yaml != c[i].yaml;
  }
  EXPECT_EQ(different, a.size());
  // A draw's value depends on (seed, index, name) only: more samples keep the first ones.
  const auto more = DrawFamily(f, {9, 1});
  EXPECT_EQ(more[5].yaml, a[5].yaml);
  // Written files are the same too.
  WriteDraws(f, a, (dir_ / "one").string());
  WriteDraws(f, b, (dir_ / "two").string());
  for (const char* file : {"draw_000/scenario.yaml", "draw_005/scenario.yaml", "draws.csv"}) {
    std::ifstream x(dir_ / "one" / file), y(dir_ / "two" / file);
    std::stringstream sx, sy;
    sx << x.rdbuf();
    sy << y.rdbuf();
    EXPECT_FALSE(sx.str().empty()) << file;
    if (std::string(file) == "draws.csv") continue;  // names its own folder
    EXPECT_EQ(sx.str(), sy.str()) << file;
  }
}

TEST_F(FamilyTest, DistributionsHaveTheirRangesAndMoments) {
  const auto draw_many = [](const Parameter& p, std::vector<double>* out) {
    for (std::size_t i = 0; i < 10000; ++i) out->push_back(DrawValue(p, 7, i).number);
  };
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return s / v.size();
  };
  Parameter uniform{"u", {}, 0};
  uniform.distribution.lo = 1.0, uniform.distribution.hi = 3.0;
  std::vector<double> u;
  draw_many(uniform, &u);
  for (double x : u) ASSERT_TRUE(x >= 1.0 && x <= 3.0) << x;
  EXPECT_NEAR(mean(u), 2.0, 0.02 * 2.0);
  for (double x : u) ASSERT_EQ(x, RoundSignificant(x, 4)) << "4 significant digits";

  Parameter normal{"n", {}, 0};
  normal.distribution.kind = Distribution::Kind::kNormal;
  normal.distribution.mean = 5.0, normal.distribution.sigma = 2.0;
  std::vector<double> n;
  draw_many(normal, &n);
  const double m = mean(n);
  double var = 0.0;
  for (double x : n) var += (x - m) * (x - m) / n.size();
  EXPECT_NEAR(m, 5.0, 0.02 * 5.0);
  EXPECT_NEAR(std::sqrt(var), 2.0, 0.05 * 2.0);
  normal.distribution.clipped = true, normal.distribution.lo = 4.0, normal.distribution.hi = 6.0;
  std::vector<double> clipped;
  draw_many(normal, &clipped);
  for (double x : clipped) ASSERT_TRUE(x >= 4.0 && x <= 6.0) << x;

  Parameter integer{"i", {}, 0};
  integer.distribution.kind = Distribution::Kind::kInteger;
  integer.distribution.lo = 1.0, integer.distribution.hi = 6.0;
  std::vector<double> k;
  draw_many(integer, &k);
  std::map<double, int> counts;
  for (double x : k) ++counts[x];
  ASSERT_EQ(counts.size(), 6u);
  for (const auto& [value, count] : counts) {
    EXPECT_EQ(value, std::floor(value));
    EXPECT_NEAR(count, 10000 / 6.0, 0.1 * 10000 / 6.0) << value;
  }

  Parameter choice{"c", {}, 0};
  choice.distribution.kind = Distribution::Kind::kChoice;
  choice.distribution.values = {Value::Word("a"), Value::Word("b"), Value::Number(3)};
  std::map<std::string, int> picked;
  for (std::size_t i = 0; i < 3000; ++i) ++picked[DrawValue(choice, 1, i).ToString()];
  EXPECT_EQ(picked.size(), 3u);
  for (const auto& [value, count] : picked) EXPECT_NEAR(count, 1000, 100) << value;
}

TEST_F(FamilyTest, GridIsTheProductOfTheGridParametersTimesTheSamples) {
  const std::string text = Replaced(Replaced(kFamily, "side: {choice: [left, right]}", "side: {grid: [left, right, middle]}"),
                                    "  roof_m: {uniform: [1.5, 3.5]}", "  roof_m: {grid: [1.8, 2.6]}\n  seed_k: {integer: [1, 9]}");
  const Family f = ParseFamily(text, "fam.yaml");
  EXPECT_EQ(GridPoints(f), 6u);
  const auto draws = DrawFamily(f, {2, 1});
  ASSERT_EQ(draws.size(), 12u);
  std::map<std::string, int> points;
  for (const Draw& d : draws) ++points[d.values[0].second.ToString() + "/" + d.values[2].second.ToString()];
  EXPECT_EQ(points.size(), 6u);
  for (const auto& [point, count] : points) EXPECT_EQ(count, 2) << point;
  EXPECT_EQ(draws[11].index, 11u);
  EXPECT_EQ(DrawFolder(draws[11].index), "draw_011");
}

TEST_F(FamilyTest, ASubnormalValueIsDrawnAndWrittenNotAnAbort) {
  // Found by fuzzing: a grid value of 1e-320 made the number formatting throw out of the draw
  // (std::stod reports the underflow of a subnormal as out of range) and the program aborted.
  const std::string text = Replaced(kFamily, "  roof_m: {uniform: [1.5, 3.5]}", "  roof_m: {grid: [1e-320, 2.6]}");
  const Family f = ParseFamily(text, "fam.yaml");
  const auto draws = DrawFamily(f, {1, 1});
  ASSERT_EQ(draws.size(), 2u);
  EXPECT_EQ(draws[0].values[0].second.number, 1e-320);
  EXPECT_EQ(std::strtod(draws[0].values[0].second.ToString().c_str(), nullptr), 1e-320);
  WriteDraws(f, draws, (dir_ / "subnormal").string());
}

TEST_F(FamilyTest, AGridTooLargeToCountIsRefusedNotWrapped) {
  // 64 grid parameters of two values: 2^64 grid points wrapped to 0 and the family drew nothing.
  std::string grid;
  for (int i = 0; i < 64; ++i) grid += "  g" + std::to_string(i) + ": {grid: [1, 2]}\n";
  const std::string text = Replaced(kFamily, "  side: {choice: [left, right]}\n", "  side: {choice: [left, right]}\n" + grid);
  const Family f = ParseFamily(text, "fam.yaml");
  EXPECT_EQ(GridPoints(f), std::numeric_limits<std::size_t>::max());
  EXPECT_NE(FamilyErrorOf(text, 1).find("draws"), std::string::npos) << FamilyErrorOf(text, 1);
  // Two grid points times a huge sample count wrapped to 2 draws' worth and drew for ever; refused.
  const std::string two = Replaced(kFamily, "side: {choice: [left, right]}", "side: {grid: [left, right]}");
  EXPECT_NE(FamilyErrorOf(two, std::numeric_limits<std::size_t>::max() / 2 + 2).find("draws"), std::string::npos);
}

TEST_F(FamilyTest, AWrittenDrawReloadsWithTheDrawnValues) {
  const Family f = ParseFamily(kFamily, "fam.yaml");
  const auto draws = DrawFamily(f, {6, 3});
  const auto paths = WriteDraws(f, draws, (dir_ / "roofs").string());
  ASSERT_EQ(paths.size(), draws.size());
  for (std::size_t i = 0; i < draws.size(); ++i) {
    const Scenario s = LoadScenario(paths[i]);
    const Draw& d = draws[i];
    const double roof = d.values[0].second.number, y = d.values[2].second.number;
    EXPECT_EQ(s.name, d.name);
    ASSERT_EQ(s.sim.world.carports.size(), 1u);
    EXPECT_EQ(s.sim.world.carports[0].roof_height_m, roof);
    EXPECT_EQ(s.sim.world.cylinders[0].height_m, RoundSignificant(roof + 0.25, 6));
    EXPECT_EQ(s.sim.world.boxes[0].y_m, y);
    // The header names the family, the draw, the seed, the values and the expectation.
    EXPECT_NE(d.yaml.find("draw " + std::to_string(i) + " of the scenario family roofs (fam.yaml), seed 3"), std::string::npos);
    EXPECT_NE(d.yaml.find("#   roof_m = " + d.values[0].second.ToString() + "\n"), std::string::npos) << d.yaml;
    EXPECT_NE(d.yaml.find("# Expectation: " + std::string(ExpectationName(d.expectation))), std::string::npos);
    EXPECT_EQ(d.yaml.find("parameters"), std::string::npos);
    EXPECT_EQ(d.yaml.find("expect:"), std::string::npos);
    // The first match wins; a refuse rule adds its own region.
    const std::string side = d.values[1].second.word;
    const Expectation want = roof >= 2.4 ? Expectation::kPass : roof < 2.2 ? Expectation::kRefuse : Expectation::kAny;
    EXPECT_EQ(d.expectation, want) << roof;
    EXPECT_EQ(d.rule, roof >= 2.4 ? 0u : roof < 2.2 ? (side == "left" ? 1u : 2u) : 3u);
    ASSERT_EQ(s.criteria.forbidden.size(), want == Expectation::kRefuse ? 1u : 0u);
    if (d.rule == 2) {
      EXPECT_EQ(s.criteria.forbidden[0].min_m.y(), -roof);
    }
  }
  std::ifstream csv(dir_ / "roofs" / "draws.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "draw,file,expectation,reason,roof_m,side,objects.2.box.y_m");
}

TEST_F(FamilyTest, TheCarportExampleDrawsItsThreeExpectations) {
  const Family f = LoadFamily(std::string(OVPC_SOURCE_DIR) + "/scenarios/families/carport_height.yaml");
  EXPECT_EQ(f.name, "carport_height");
  const auto draws = DrawFamily(f, {24, 1});
  std::set<Expectation> seen;
  for (const Draw& d : draws) {
    const double roof = d.values.at(0).second.number;
    ASSERT_TRUE(roof >= 1.5 && roof <= 3.5) << roof;
    seen.insert(d.expectation);
    EXPECT_EQ(d.expectation, roof >= 2.4 ? Expectation::kPass : roof < 2.2 ? Expectation::kRefuse : Expectation::kAny);
    EXPECT_EQ(d.yaml.find("under_the_roof") != std::string::npos, d.expectation == Expectation::kRefuse) << d.yaml;
    if (d.expectation == Expectation::kAny) {
      EXPECT_EQ(d.reason, "the mast (2.2 m) fits with little margin");
    }
  }
  EXPECT_EQ(seen.size(), 3u);
}

TEST_F(FamilyTest, JudgesARunAgainstItsExpectation) {
  RunResult r;
  r.criteria = {{"goal_reached", "", "no", false}, {"no_collision", "", "none", true},
                {"never_enter:under", "never entered", "never entered", true}};
  r.passed = false;
  EXPECT_EQ(Judge(Expectation::kPass, OutcomeOf(r)), Verdict::kViolated);
  EXPECT_EQ(Judge(Expectation::kRefuse, OutcomeOf(r)), Verdict::kOk) << "the goal is not required";
  EXPECT_EQ(Judge(Expectation::kAny, OutcomeOf(r)), Verdict::kNotCounted);
  r.criteria[2].passed = false;
  EXPECT_TRUE(OutcomeOf(r).entered_forbidden);
  EXPECT_EQ(Judge(Expectation::kRefuse, OutcomeOf(r)), Verdict::kViolated);
  r.criteria[2].passed = true;
  r.collision_steps = 3;
  EXPECT_EQ(Judge(Expectation::kRefuse, OutcomeOf(r)), Verdict::kViolated);
  r = RunResult();
  r.passed = true;
  EXPECT_EQ(Judge(Expectation::kPass, OutcomeOf(r)), Verdict::kOk);
  EXPECT_EQ(Judge(Expectation::kRefuse, OutcomeOf(r)), Verdict::kOk) << "reaching the goal is fine too";
  EXPECT_STREQ(VerdictName(Verdict::kViolated), "violated");
}

TEST_F(FamilyTest, ATemplatedNameGivesTheFileStemAndTheDrawsNumberedNames) {
  const Family f = ParseFamily(Replaced(kFamily, "name: roofs", "name: roof_${roof_m}"), "dir/low_roofs.yaml");
  EXPECT_EQ(f.name, "low_roofs");
  const Draw d = DrawFamily(f, {1, 1}).front();
  EXPECT_EQ(d.name, "low_roofs_000");
  EXPECT_NE(d.yaml.find("# The family's name for it: roof_" + d.values[0].second.ToString()), std::string::npos) << d.yaml;
}

TEST_F(FamilyTest, AFamilyNameIsANameNeverAPath) {
  const auto starts = [](const std::string& error, const std::string& prefix) { return error.rfind(prefix, 0) == 0; };
  std::string e = FamilyErrorOf(Replaced(kFamily, "name: roofs", "name: \"..\""));
  EXPECT_TRUE(starts(e, "fam.yaml:1: name '..' starts with '.'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "name: roofs", "name: \".\""));
  EXPECT_TRUE(starts(e, "fam.yaml:1: name '.' starts with '.'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "name: roofs", "name: /home/user"));
  EXPECT_TRUE(starts(e, "fam.yaml:1: name '/home/user' holds '/'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "name: roofs", "name: \"a,b\""));
  EXPECT_TRUE(starts(e, "fam.yaml:1: name 'a,b' holds ','")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "name: roofs", "name: " + std::string(kMaxFamilyNameBytes + 1, 'f')));
  EXPECT_NE(e.find("bytes long (at most 64)"), std::string::npos) << e;
  // Named by its file when the name holds '$': the file's stem must be a name too.
  const std::string templated = Replaced(kFamily, "name: roofs", "name: roof_${roof_m}");
  try {
    ParseFamily(templated, "dir/...yaml");
    FAIL() << "a family named '..' by its file was read";
  } catch (const ScenarioError& error) {
    EXPECT_TRUE(starts(error.what(), "dir/...yaml:1: the name holds '$', so the family is named by its file, but '..' starts with '.'"))
        << error.what();
  }
  // The longest family name gives draws whose names are names.
  const std::string longest(kMaxFamilyNameBytes, 'f');
  const Draw d = DrawFamily(ParseFamily(Replaced(kFamily, "name: roofs", "name: " + longest), "fam.yaml"), {2, 1}).back();
  EXPECT_EQ(d.name, longest + "_001");
  EXPECT_EQ(NameProblem(d.name), "");
}

// Expressions deeper or longer than the parser's limits are refused naming the file, the line and
// the column (they once crashed the suite before any run).
TEST_F(FamilyTest, DeepExpressionsAreRefusedWithFileLineAndColumn) {
  const auto starts = [](const std::string& error, const std::string& prefix) { return error.rfind(prefix, 0) == 0; };
  std::string deep(5000, '(');
  deep += "roof_m" + std::string(5000, ')');
  std::string e = FamilyErrorOf(Replaced(kFamily, "${roof_m + 0.25}", "${" + deep + "}"));
  EXPECT_TRUE(starts(e, "fam.yaml:9: in '((((")) << e;
  EXPECT_NE(e.find("at column 4097: the expression is 10006 characters long; the limit is 4096"), std::string::npos) << e;
  std::string sum = "roof_m";
  for (int i = 0; i < 200; ++i) sum += "+1";
  e = FamilyErrorOf(Replaced(kFamily, "roof_m >= 2.4", sum + " >= 2.4"));
  EXPECT_TRUE(starts(e, "fam.yaml:15: 'expect[0].when' in 'roof_m+1+1")) << e;
  EXPECT_NE(e.find("nested more than 100 levels deep"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  EXPECT_LT(e.size(), 300u) << e;
}

// Every family of scenarios/families reads and draws (its draws' names are names).
TEST_F(FamilyTest, EveryBundledFamilyReadsAndDraws) {
  int families = 0;
  for (const auto& entry : fs::directory_iterator(std::string(OVPC_SOURCE_DIR) + "/scenarios/families")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    ASSERT_TRUE(IsFamilyFile(entry.path().string()));
    const Family f = LoadFamily(entry.path().string());
    for (const Draw& d : DrawFamily(f, {2, 1})) EXPECT_EQ(NameProblem(d.name), "") << d.name;
    ++families;
  }
  EXPECT_GE(families, 8);
}

TEST_F(FamilyTest, MalformedFamiliesNameFileLineAndProblem) {
  const auto starts = [](const std::string& error, const std::string& prefix) { return error.rfind(prefix, 0) == 0; };
  std::string e = FamilyErrorOf(Replaced(kFamily, "{uniform: [1.5, 3.5]}", "{gaussian: [1.5, 3.5]}"));
  EXPECT_TRUE(starts(e, "fam.yaml:4: 'parameters.roof_m': unknown distribution 'gaussian'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "roof_height_m: $roof_m", "roof_height_m: $roof"));
  EXPECT_TRUE(starts(e, "fam.yaml:8: '$roof' is not a parameter (parameters: ")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "${roof_m + 0.25}", "${roof + 0.25}"));
  EXPECT_TRUE(starts(e, "fam.yaml:9: 'roof' in '${roof + 0.25}' is not a parameter")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "${roof_m + 0.25}", "${roof_m +}"));
  EXPECT_TRUE(starts(e, "fam.yaml:9: in 'roof_m +' at column 9:")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "[1.5, 3.5]", "[3, 1]"));
  EXPECT_TRUE(starts(e, "fam.yaml:4: 'parameters.roof_m.uniform' must be [lo, hi] with lo < hi")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "[1.5, 3.5]", "[low, 3.5]"));
  EXPECT_TRUE(starts(e, "fam.yaml:4: 'parameters.roof_m.uniform' must be a number, got 'low'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "{normal: [0, 1], clip: [-2, 2]}", "{normal: [0, -1]}"));
  EXPECT_TRUE(starts(e, "fam.yaml:10: 'objects.2.box.y_m.normal' needs sigma > 0")) << e;
  e = FamilyErrorOf(Replaced(Replaced(kFamily, "  - {then: any, reason: tight}\n", ""), "roof_m >= 2.4", "roof_m >= 3.4"));
  EXPECT_TRUE(starts(e, "fam.yaml:15: draw ")) << e;
  EXPECT_NE(e.find("matches no rule of 'expect'"), std::string::npos) << e;
  e = FamilyErrorOf(Replaced(kFamily, "    forbidden: [{name: under, min_m: [8, -2], max_m: [12, 2]}]\n", ""));
  EXPECT_TRUE(starts(e, "fam.yaml:16: 'expect[1]': a refuse rule needs something to hold")) << e;
  // With criteria.no_collision the same rule holds something: the vehicle must not touch anything.
  EXPECT_EQ(FamilyErrorOf(Replaced(Replaced(kFamily, "    forbidden: [{name: under, min_m: [8, -2], max_m: [12, 2]}]\n", ""),
                                   "  goal: {x_m: 16.0, y_m: 0.0}\n", "  goal: {x_m: 16.0, y_m: 0.0}\n  no_collision: true\n")),
            "");
  e = FamilyErrorOf(Replaced(kFamily, "route:", "navigator:\n  local_goal: {mode: reachable}\nroute:"));
  EXPECT_TRUE(starts(e, "fam.yaml:11: a family must not have a 'navigator:' section")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "max_m: [12, 2]}]\n", "max_m: [12, {uniform: [1, 2]}]}]\n"));
  EXPECT_TRUE(starts(e, "fam.yaml:18: a distribution in an expect rule")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "then: pass}", "then: succeed}"));
  EXPECT_TRUE(starts(e, "fam.yaml:15: 'expect[0].then' must be pass, refuse or any, got 'succeed'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "reason: tight", "because: tight"));
  EXPECT_TRUE(starts(e, "fam.yaml:20: unknown key 'expect[3].because'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "roof_m >= 2.4", "height >= 2.4"));
  EXPECT_TRUE(starts(e, "fam.yaml:15: 'height' in 'expect[0].when' is not a parameter")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "roof_m >= 2.4", "roof_m >= side"));
  EXPECT_TRUE(starts(e, "fam.yaml:15: in 'roof_m >= side': '")) << e;
  EXPECT_NE(e.find("is a word, not a number"), std::string::npos) << e;
  // The body is checked as a scenario, with the family's lines.
  e = FamilyErrorOf(Replaced(kFamily, "roof_height_m: $roof_m", "roof_hieght_m: $roof_m"));
  EXPECT_TRUE(starts(e, "fam.yaml:8: unknown key 'objects[0].carport.roof_hieght_m'")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "x_m: 5.0, y_m: 3.0", "x_m: $side, y_m: 3.0"));
  EXPECT_TRUE(starts(e, "fam.yaml:9: 'objects[1].cylinder.x_m' must be a number, got '")) << e;
  e = FamilyErrorOf(Replaced(kFamily, "expect:", "expected:"));
  EXPECT_TRUE(starts(e, "fam.yaml:1: a family needs 'expect:'")) << e;
  EXPECT_TRUE(starts(FamilyErrorOf(kFamily, 0), "fam.yaml: the number of samples must be at least 1"));
}

}  // namespace
}  // namespace ovpc::scenarios
