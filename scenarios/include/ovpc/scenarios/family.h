// Scenario families: a scenario file whose values may be distributions (`parameters:`, `$name`,
// `${expr}`, inline `{uniform: [lo, hi]}`), with `expect:` rules saying what each draw must do. A
// family is drawn deterministically into plain scenario files, which `ovpc suite` runs and judges
// against their expectation. The format is in scenarios/README.md (Families).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/expression.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios {

struct Distribution {
  enum class Kind { kUniform, kNormal, kChoice, kGrid, kInteger };
  Kind kind = Kind::kUniform;
  double lo = 0.0, hi = 0.0;       ///< uniform, integer: the range, both ends included; normal: the clip range
  double mean = 0.0, sigma = 0.0;  ///< normal
  bool clipped = false;            ///< normal with `clip: [lo, hi]`: values beyond are set to the nearer end
  std::vector<Value> values;       ///< choice, grid
};

/// "uniform", "normal", "choice", "grid" or "integer".
const char* DistributionName(Distribution::Kind kind);

struct Parameter {
  std::string name;  ///< its key under `parameters:`, or an inline distribution's dotted path
  Distribution distribution;
  int line = 0;      ///< in the family file
};

/// What a draw must do. kPass: every criterion of the scenario met. kRefuse: the goal is not
/// required; never collide and never enter a forbidden region. kAny: not judged (with a reason).
enum class Expectation { kPass, kRefuse, kAny };
/// "pass", "refuse" or "any".
const char* ExpectationName(Expectation e);

struct ExpectRule {
  std::optional<Expression> when;  ///< none: the rule matches every draw
  Expectation then = Expectation::kPass;
  std::string reason;
  std::size_t forbidden = 0;       ///< regions the rule adds to its draws' criteria.forbidden
  int line = 0;
};

struct Family {
  std::string name;  ///< its `name:` (the file's stem when the name holds `${...}`)
  std::string path;
  std::string text;  ///< the file as read: every draw is made from it anew
  std::vector<Parameter> parameters;  ///< `parameters:` in order, then inline distributions in file order
  std::vector<ExpectRule> rules;      ///< first match wins
};

/// One concrete scenario drawn from a family.
struct Draw {
  std::size_t index = 0;
  std::string name;  ///< <family>_<iii>, its scenario name
  std::vector<std::pair<std::string, Value>> values;  ///< per parameter, in Family::parameters' order
  std::size_t rule = 0;  ///< the expect rule that matched (index)
  Expectation expectation = Expectation::kPass;
  std::string reason;
  std::string yaml;  ///< the plain scenario file: a header comment, then the body with the values in
};

struct DrawOptions {
  std::size_t samples = 6;  ///< random draws per grid point (the grid is the product of the grid parameters)
  std::uint64_t seed = 1;
};

/// True if the file (or text) is YAML whose top level has `parameters:`. False for anything else,
/// unreadable or malformed files included (those are reported by the scenario reader).
bool IsFamilyFile(const std::string& path);
bool IsFamilyText(const std::string& yaml_text);

/// Reads a family and checks its parameters, every `$name` and `${expr}`, and its rules.
/// @throws ScenarioError, one line "FILE:LINE: problem".
Family ParseFamily(const std::string& yaml_text, const std::string& file);
Family LoadFamily(const std::string& path);

/// Grid points: the product of the grid parameters' value counts (1 without grid parameters),
/// saturating at the largest std::size_t.
std::size_t GridPoints(const Family& family);

/// The value of a non-grid parameter in draw `index` of `seed`: a function of (seed, index, name)
/// alone. Floats are rounded to 4 significant digits (then kept within the range).
Value DrawValue(const Parameter& parameter, std::uint64_t seed, std::size_t index);
/// `v` rounded to `digits` significant decimal digits.
double RoundSignificant(double v, int digits);

/// GridPoints × samples draws, each with its values, its expectation and its scenario file text,
/// checked as a scenario over `preset`.
/// @throws ScenarioError "FILE:LINE: problem (draw i: values)": no rule matches, a rule or a value
/// cannot be evaluated, or the drawn scenario is malformed.
std::vector<Draw> DrawFamily(const Family& family, const DrawOptions& options, const Preset& preset = DefaultPreset());

/// "draw_003".
std::string DrawFolder(std::size_t index);
/// "roof_height_m=2.347 kind=ramp".
std::string DrawValuesLabel(const Draw& draw);
/// Writes family_dir/draw_<iii>/scenario.yaml for each draw and family_dir/draws.csv (index, file,
/// expectation, values); returns the scenario files' paths.
/// @throws std::runtime_error if a file cannot be written.
std::vector<std::string> WriteDraws(const Family& family, const std::vector<Draw>& draws, const std::string& family_dir);

/// A run judged against its draw's expectation. kNotCounted: expectation `any`. kError: the run left
/// no result (crashed, killed).
enum class Verdict { kOk, kViolated, kNotCounted, kError };
/// "ok", "violated", "not counted" or "error".
const char* VerdictName(Verdict v);

/// What the referee recorded of a run that the verdict needs.
struct RunOutcome {
  bool passed = false;             ///< every criterion met
  std::size_t collision_steps = 0; ///< physics steps with a body contact
  bool entered_forbidden = false;  ///< a never_enter:* criterion failed
};
RunOutcome OutcomeOf(bool passed, std::size_t collision_steps, const std::vector<CriterionResult>& criteria);
RunOutcome OutcomeOf(const RunResult& result);

/// kPass: ok iff passed. kRefuse: ok iff no collision and no forbidden region entered (reaching the
/// goal is fine too). kAny: not counted.
Verdict Judge(Expectation expectation, const RunOutcome& outcome);

}  // namespace ovpc::scenarios
