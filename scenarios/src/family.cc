// Reading and checking a scenario family; judging a run against its draw's expectation.
#include "ovpc/scenarios/family.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <sstream>

#include "config_yaml.h"
#include "family_yaml.h"

namespace ovpc::scenarios {
namespace {

using internal::MapReader;
using internal::Where;

[[noreturn]] void Fail(const std::string& file, const YAML::Node& at, const std::string& what) {
  throw ScenarioError(Where(file, at) + ": " + what);
}

bool IsParameterName(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::string Known(const std::set<std::string>& defined) {
  std::string s;
  for (const auto& n : defined) s += (s.empty() ? "" : ", ") + n;
  return " (parameters: " + (s.empty() ? "none" : s) + ")";
}

void ReadParameters(const YAML::Node& node, const std::string& file, Family* f) {
  if (!node.IsMap() || node.size() == 0) {
    Fail(file, node, "'parameters' must map names to distributions, e.g. roof_m: {uniform: [1.5, 3.5]}");
  }
  MapReader duplicates(node, "parameters", file);  // fails on a name given twice
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    if (!IsParameterName(name)) Fail(file, kv.first, "parameter name '" + name + "' must be letters, digits and '_'");
    if (!kv.second.IsMap()) {
      Fail(file, kv.second, "'parameters." + name + "' must be a distribution: {uniform: [lo, hi]}, {normal: [mean, sigma]}, "
                            "{choice: [...]}, {grid: [...]} or {integer: [lo, hi]}");
    }
    f->parameters.push_back({name, internal::ReadDistribution(kv.second, "parameters." + name, file), kv.first.Mark().line + 1});
  }
}

// Every `$name` and `${expr}` of a scalar must parse and refer to parameters.
void CheckScalar(const YAML::Node& n, const std::set<std::string>& defined, const std::string& file) {
  const auto check_name = [&](const std::string& name) {
    if (!defined.count(name)) throw ExpressionError("'$" + name + "' is not a parameter" + Known(defined));
    return std::string();
  };
  const auto check_expr = [&](const std::string& text) {
    const Expression e = Expression::Parse(text);
    for (const std::string& name : e.names()) {
      if (!defined.count(name)) throw ExpressionError("'" + name + "' in '${" + text + "}' is not a parameter" + Known(defined));
    }
    return std::string();
  };
  try {
    internal::ExpandScalar(n.Scalar(), check_name, check_expr);
  } catch (const ExpressionError& e) {
    Fail(file, n, e.what());
  }
}

// A rule's regions: `$name` and `${expr}` of the parameters, no distributions of their own.
void CheckScalars(const YAML::Node& n, const std::set<std::string>& defined, const std::string& file) {
  if (internal::IsDistributionMap(n)) Fail(file, n, "a distribution in an expect rule: give it a name under 'parameters:' and use $name");
  if (n.IsScalar()) CheckScalar(n, defined, file);
  if (n.IsSequence()) for (const YAML::Node& item : n) CheckScalars(item, defined, file);
  if (n.IsMap()) for (const auto& kv : n) CheckScalars(kv.second, defined, file);
}

// Inline distributions become parameters named by their path; then every scalar is checked.
std::set<std::string> ReadBody(const YAML::Node& root, const std::string& file, Family* f) {
  std::set<std::string> defined;
  for (const Parameter& p : f->parameters) defined.insert(p.name);
  std::vector<YAML::Node> scalars;
  internal::WalkBody(
      root,
      [&](YAML::Node n, const std::string& path) {
        if (!defined.insert(path).second) Fail(file, n, "inline distribution '" + path + "' has the name of a parameter");
        f->parameters.push_back({path, internal::ReadDistribution(n, path, file), n.Mark().line + 1});
      },
      [&](YAML::Node n, const std::string&) { scalars.push_back(n); });
  for (const YAML::Node& n : scalars) CheckScalar(n, defined, file);
  return defined;
}

Expectation ReadThen(MapReader& r, const YAML::Node& rule) {
  const YAML::Node then = r.Child("then");
  if (!then) r.Fail(rule, "'" + r.Key("then") + "' is required: pass, refuse or any");
  const std::string text = then.IsScalar() ? then.Scalar() : "";
  if (text == "pass") return Expectation::kPass;
  if (text == "refuse") return Expectation::kRefuse;
  if (text == "any") return Expectation::kAny;
  r.Fail(then, "'" + r.Key("then") + "' must be pass, refuse or any, got '" + text + "'");
}

ExpectRule ReadRule(const YAML::Node& node, const std::string& ctx, const std::set<std::string>& defined,
                    const std::string& file) {
  MapReader r(node, ctx, file);
  ExpectRule rule;
  rule.line = node.Mark().line + 1;
  if (const YAML::Node when = r.Child("when")) {
    const std::string text = r.ConvertAt<std::string>(when, r.Key("when"));
    try {
      rule.when = Expression::Parse(text);
    } catch (const ExpressionError& e) {
      r.Fail(when, "'" + r.Key("when") + "' " + e.what());
    }
    for (const std::string& name : rule.when->names()) {
      if (!defined.count(name)) r.Fail(when, "'" + name + "' in '" + r.Key("when") + "' is not a parameter" + Known(defined));
    }
  }
  rule.then = ReadThen(r, node);
  r.Get("reason", &rule.reason);
  const YAML::Node list = r.Child("forbidden");
  r.Finish();
  if (rule.then == Expectation::kAny && rule.reason.empty()) r.Fail(node, "'" + ctx + "': 'then: any' needs a 'reason'");
  if (list) {
    if (rule.then != Expectation::kRefuse) r.Fail(list, "'" + r.Key("forbidden") + "' is for 'then: refuse' rules only");
    if (!list.IsSequence() || list.size() == 0) r.Fail(list, "'" + r.Key("forbidden") + "' must be a list of {name, min_m, max_m}");
    CheckScalars(list, defined, file);
    rule.forbidden = list.size();
  }
  return rule;
}

void ReadRules(const YAML::Node& root, const std::set<std::string>& defined, const std::string& file, Family* f) {
  const YAML::Node list = root["expect"];
  if (!list) Fail(file, root, "a family needs 'expect:', a list of rules like {when: \"roof_m >= 2.4\", then: pass}");
  if (!list.IsSequence() || list.size() == 0) Fail(file, list, "'expect' must be a list of rules {when, then, reason}");
  // (A missing node's type cannot be asked: test that it is there first.)
  const YAML::Node criteria = root["criteria"];
  const YAML::Node regions = criteria && criteria.IsMap() ? criteria["forbidden"] : YAML::Node();
  const bool body_forbidden = regions && regions.IsSequence() && regions.size() > 0;
  // A refuse draw is judged on collisions and forbidden regions: one of them must be asked for.
  const YAML::Node no_collision = criteria && criteria.IsMap() ? criteria["no_collision"] : YAML::Node();
  const bool collisions_judged = no_collision && no_collision.IsScalar() && no_collision.Scalar() == "true";
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string ctx = "expect[" + std::to_string(i) + "]";
    f->rules.push_back(ReadRule(list[i], ctx, defined, file));
    if (f->rules.back().then == Expectation::kRefuse && f->rules.back().forbidden == 0 && !body_forbidden && !collisions_judged) {
      Fail(file, list[i], "'" + ctx + "': a refuse rule needs something to hold (the goal is not required): "
                          "give the rule 'forbidden: [{name, min_m: [x, y], max_m: [x, y]}]', the family 'criteria.forbidden' "
                          "or 'criteria.no_collision: true'");
    }
  }
}

// The `name:`, or the file's stem when the name holds `$`; a name either way (scenario_yaml.h).
std::string FamilyName(const YAML::Node& root, const std::string& file) {
  const YAML::Node name = root["name"];
  if (!name) Fail(file, root, "'name' is required");
  if (!name.IsScalar() || name.Scalar().empty()) Fail(file, name, "'name' must be a word");
  const std::string text = name.Scalar();
  if (text.find('$') == std::string::npos) {
    ValidateName(file, name.Mark().line + 1, text, kMaxFamilyNameBytes);
    return text;
  }
  const std::string stem = std::filesystem::path(file).stem().string();
  const std::string problem = NameProblem(stem, kMaxFamilyNameBytes);
  if (!problem.empty()) {
    Fail(file, name, "the name holds '$', so the family is named by its file, but '" + stem + "' " + problem +
                         ": give the family a 'name:' of letters, digits, '_', '-' and '.'");
  }
  return stem;
}

}  // namespace

const char* DistributionName(Distribution::Kind kind) {
  switch (kind) {
    case Distribution::Kind::kUniform: return "uniform";
    case Distribution::Kind::kNormal: return "normal";
    case Distribution::Kind::kChoice: return "choice";
    case Distribution::Kind::kGrid: return "grid";
    case Distribution::Kind::kInteger: return "integer";
  }
  return "";
}

const char* ExpectationName(Expectation e) {
  return e == Expectation::kPass ? "pass" : e == Expectation::kRefuse ? "refuse" : "any";
}

const char* VerdictName(Verdict v) {
  switch (v) {
    case Verdict::kOk: return "ok";
    case Verdict::kViolated: return "violated";
    case Verdict::kNotCounted: return "not counted";
    case Verdict::kError: return "error";
  }
  return "";
}

bool IsFamilyText(const std::string& yaml_text) {
  try {
    const YAML::Node root = YAML::Load(yaml_text);
    return root.IsMap() && root["parameters"];
  } catch (const YAML::Exception&) {
    return false;
  }
}

bool IsFamilyFile(const std::string& path) {
  std::string text;
  try {
    text = ReadSmallRegularFile(path, "scenario file");
  } catch (const ScenarioError&) {
    return false;  // the scenario reader says what is wrong with it
  }
  return IsFamilyText(text);
}

Family ParseFamily(const std::string& yaml_text, const std::string& file) {
  YAML::Node loaded;
  try {
    loaded = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  const YAML::Node& root = loaded;  // const lookups never add keys
  if (!root.IsMap() || !root["parameters"]) throw ScenarioError(file + ": a family is a scenario file with 'parameters:' and 'expect:'");
  for (const auto& kv : root) {
    if (!kv.first.IsScalar() || kv.first.Scalar() != "navigator") continue;
    Fail(file, kv.first, "a family must not have a 'navigator:' section: the robot's settings are not part of the world "
                         "(give them with --preset or --set)");
  }
  Family f;
  f.path = file;
  f.text = yaml_text;
  f.name = FamilyName(root, file);
  ReadParameters(root["parameters"], file, &f);
  const std::set<std::string> defined = ReadBody(root, file, &f);
  ReadRules(root, defined, file, &f);
  return f;
}

Family LoadFamily(const std::string& path) { return ParseFamily(ReadSmallRegularFile(path, "family file"), path); }

RunOutcome OutcomeOf(bool passed, std::size_t collision_steps, const std::vector<CriterionResult>& criteria) {
  RunOutcome o;
  o.passed = passed;
  o.collision_steps = collision_steps;
  for (const CriterionResult& c : criteria) o.entered_forbidden |= c.name.rfind("never_enter:", 0) == 0 && !c.passed;
  return o;
}

RunOutcome OutcomeOf(const RunResult& result) { return OutcomeOf(result.passed, result.collision_steps, result.criteria); }

Verdict Judge(Expectation expectation, const RunOutcome& outcome) {
  switch (expectation) {
    case Expectation::kPass: return outcome.passed ? Verdict::kOk : Verdict::kViolated;
    case Expectation::kRefuse:
      return outcome.collision_steps == 0 && !outcome.entered_forbidden ? Verdict::kOk : Verdict::kViolated;
    case Expectation::kAny: return Verdict::kNotCounted;
  }
  return Verdict::kError;
}

}  // namespace ovpc::scenarios
