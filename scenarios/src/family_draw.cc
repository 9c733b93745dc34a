// Drawing a scenario family: values from (seed, draw index, parameter name), the expect rule that
// matches, and the plain scenario file with the values in.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "config_yaml.h"
#include "ovpc/core/internal/hash.h"
#include "family_yaml.h"
#include "ovpc/scenarios/family.h"
#include "scenario_node.h"

namespace ovpc::scenarios {
namespace {

namespace fs = std::filesystem;
using internal::Where;
using Values = std::map<std::string, Value>;

constexpr std::uint64_t kGolden = ovpc::internal::kGoldenGamma;
constexpr std::size_t kMaxDraws = 10000;

// splitmix64's output function.
using ovpc::internal::MixBits;

std::uint64_t Fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001B3ULL;
  return h;
}

// A splitmix64 stream of its own for each (seed, draw index, parameter name): a value does not
// depend on the other parameters, their order or the number of draws.
class Random {
 public:
  Random(std::uint64_t seed, std::size_t index, const std::string& name)
      : state_(MixBits(MixBits(MixBits(seed + kGolden) ^ ((index + 1) * kGolden)) ^ Fnv1a(name))) {}
  std::uint64_t Next() { return MixBits(state_ += kGolden); }
  /// [0, 1) with the 53 bits of a double's mantissa.
  double Uniform01() { return ovpc::internal::ToUnitInterval(Next()); }
  /// [0, n), n >= 1, without modulo bias (rejection).
  std::uint64_t Below(std::uint64_t n) {
    const std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
    const std::uint64_t limit = max - max % n;
    std::uint64_t x = Next();
    while (x >= limit) x = Next();
    return x % n;
  }
  /// Standard normal (Box-Muller, the cosine half).
  double Normal() {
    const double u1 = 1.0 - Uniform01(), u2 = Uniform01();  // u1 in (0, 1]
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::uint64_t state_;
};

std::string Joined(const std::vector<std::pair<std::string, Value>>& values, const char* sep) {
  std::string s;
  for (const auto& [name, v] : values) s += (s.empty() ? "" : sep) + name + "=" + v.ToString();
  return s;
}

// Grid values of grid point `g` (the last grid parameter varies fastest), random ones for the rest.
std::vector<std::pair<std::string, Value>> DrawValues(const Family& f, std::size_t g, std::size_t index, std::uint64_t seed) {
  std::vector<std::pair<std::string, Value>> values(f.parameters.size());
  for (std::size_t k = f.parameters.size(); k-- > 0;) {
    const Parameter& p = f.parameters[k];
    if (p.distribution.kind == Distribution::Kind::kGrid) {
      values[k] = {p.name, p.distribution.values[g % p.distribution.values.size()]};
      g /= p.distribution.values.size();
    } else {
      values[k] = {p.name, DrawValue(p, seed, index)};
    }
  }
  return values;
}

void MatchRule(const Family& f, const Values& env, Draw* d) {
  for (std::size_t i = 0; i < f.rules.size(); ++i) {
    const ExpectRule& rule = f.rules[i];
    try {
      if (rule.when && !rule.when->Test(env)) continue;
    } catch (const ExpressionError& e) {
      throw ScenarioError(f.path + ":" + std::to_string(rule.line) + ": " + e.what() + " (draw " + std::to_string(d->index) +
                          ": " + Joined(d->values, " ") + ")");
    }
    d->rule = i;
    d->expectation = rule.then;
    d->reason = rule.reason;
    return;
  }
  throw ScenarioError(f.path + ":" + std::to_string(f.rules.front().line) + ": draw " + std::to_string(d->index) + " (" +
                      Joined(d->values, " ") + ") matches no rule of 'expect' (end it with a rule without 'when')");
}

// The refuse rule's own regions join criteria.forbidden.
void AddRuleRegions(YAML::Node root, const Family& f, const Draw& d) {
  if (f.rules[d.rule].forbidden == 0) return;
  const YAML::Node regions = static_cast<const YAML::Node&>(root)["expect"][d.rule]["forbidden"];
  if (!root["criteria"]) root["criteria"] = YAML::Node(YAML::NodeType::Map);
  if (!root["criteria"].IsMap()) throw ScenarioError(Where(f.path, root["criteria"]) + ": 'criteria' must be a map");
  if (!root["criteria"]["forbidden"]) root["criteria"]["forbidden"] = YAML::Node(YAML::NodeType::Sequence);
  YAML::Node list = root["criteria"]["forbidden"];
  if (!list.IsSequence()) throw ScenarioError(Where(f.path, list) + ": 'criteria.forbidden' must be a list");
  for (const YAML::Node& region : regions) list.push_back(region);
}

// Values into the body: inline distributions and `$name` become the drawn values, `${expr}` its value
// (rounded to 6 significant digits unless whole). Returns the `name:` as the family wrote it, expanded.
std::string Substitute(YAML::Node root, const Family& f, const Values& env) {
  const auto name = [&](const std::string& n) { return env.at(n).ToString(); };
  const auto expr = [&](const std::string& text) {
    Value v = Expression::Parse(text).Evaluate(env);
    if (v.is_number && v.number != std::floor(v.number)) v.number = RoundSignificant(v.number, 6);
    return v.ToString();
  };
  std::string title;
  internal::WalkBody(
      root, [&](YAML::Node n, const std::string& path) { n = env.at(path).ToString(); },
      [&](YAML::Node n, const std::string& path) {
        try {
          if (const auto text = internal::ExpandScalar(n.Scalar(), name, expr)) n = *text;
        } catch (const ExpressionError& e) {
          throw ScenarioError(Where(f.path, n) + ": " + e.what());
        }
        if (path == "name") title = n.Scalar();
      });
  return title;
}

std::string Header(const Family& f, const Draw& d, std::uint64_t seed, const std::string& title) {
  const ExpectRule& rule = f.rules[d.rule];
  std::string h = "# " + d.name + ": draw " + std::to_string(d.index) + " of the scenario family " + f.name + " (" + f.path +
                  "), seed " + std::to_string(seed) + ".\n";
  if (title != f.name && title != d.name) h += "# The family's name for it: " + title + "\n";
  h += "# Re-run it: ovpc run <this file> [--seed K]\n# Drawn values:\n";
  for (const auto& [name, v] : d.values) h += "#   " + name + " = " + v.ToString() + "\n";
  h += "# Expectation: " + std::string(ExpectationName(d.expectation)) + " (expect rule " + std::to_string(d.rule + 1) +
       ", line " + std::to_string(rule.line) + (rule.when ? ": " + rule.when->text() : std::string()) + ")";
  if (d.expectation == Expectation::kPass) h += ": every criterion must be met.\n";
  if (d.expectation == Expectation::kRefuse) {
    h += ":\n# the goal is not required; the run must never collide and never enter a forbidden region\n"
         "# (ovpc run may report the goal's criteria failed while the expectation holds).\n";
  }
  if (d.expectation == Expectation::kAny) h += ": not judged, " + d.reason + ".\n";
  return h;
}

std::string MakeYaml(const Family& f, const Draw& d, const Values& env, std::uint64_t seed, const Preset& preset) {
  YAML::Node root = YAML::Load(f.text);
  AddRuleRegions(root, f, d);
  root.remove("parameters");
  root.remove("expect");
  const std::string title = Substitute(root, f, env);
  root["name"] = d.name;
  try {
    internal::ParseScenarioNode(root, f.path, preset);
  } catch (const ScenarioError& e) {
    throw ScenarioError(std::string(e.what()) + " (draw " + std::to_string(d.index) + ": " + Joined(d.values, " ") + ")");
  }
  YAML::Emitter out;
  out << root;
  if (!out.good()) throw ScenarioError(f.path + ": draw " + std::to_string(d.index) + " cannot be written: " + out.GetLastError());
  return Header(f, d, seed, title) + out.c_str() + "\n";
}

}  // namespace

double RoundSignificant(double v, int digits) {
  if (v == 0.0 || !std::isfinite(v)) return v;
  char text[64];
  std::snprintf(text, sizeof(text), "%.*e", digits - 1, v);
  return std::strtod(text, nullptr);
}

Value DrawValue(const Parameter& p, std::uint64_t seed, std::size_t index) {
  const Distribution& d = p.distribution;
  Random random(seed, index, p.name);
  const auto rounded = [&](double v) { return std::clamp(RoundSignificant(v, 4), d.lo, d.hi); };
  switch (d.kind) {
    case Distribution::Kind::kUniform: return Value::Number(rounded(d.lo + (d.hi - d.lo) * random.Uniform01()));
    case Distribution::Kind::kNormal: {
      const double v = d.mean + d.sigma * random.Normal();
      return Value::Number(d.clipped ? rounded(std::clamp(v, d.lo, d.hi)) : RoundSignificant(v, 4));
    }
    case Distribution::Kind::kInteger: {
      const auto n = static_cast<std::uint64_t>(d.hi - d.lo) + 1;
      return Value::Number(d.lo + static_cast<double>(random.Below(n)));
    }
    case Distribution::Kind::kChoice: return d.values[random.Below(d.values.size())];
    case Distribution::Kind::kGrid: break;
  }
  throw std::invalid_argument("DrawValue: '" + p.name + "' is a grid parameter: its values are the grid's");
}

std::size_t GridPoints(const Family& family) {
  // Saturates: 64 grid parameters of two values each wrapped to 0 grid points (no draws, silently).
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  std::size_t n = 1;
  for (const Parameter& p : family.parameters) {
    if (p.distribution.kind != Distribution::Kind::kGrid) continue;
    const std::size_t k = p.distribution.values.size();
    n = k != 0 && n > kMax / k ? kMax : n * k;
  }
  return n;
}

std::vector<Draw> DrawFamily(const Family& family, const DrawOptions& options, const Preset& preset) {
  if (options.samples < 1) throw ScenarioError(family.path + ": the number of samples must be at least 1");
  const std::size_t points = GridPoints(family);
  if (points > kMaxDraws || options.samples > kMaxDraws || points * options.samples > kMaxDraws) {
    throw ScenarioError(family.path + ": " + std::to_string(points) + " grid points × " + std::to_string(options.samples) +
                        " samples is more than " + std::to_string(kMaxDraws) + " draws");
  }
  std::vector<Draw> draws;
  for (std::size_t g = 0; g < points; ++g) {
    for (std::size_t k = 0; k < options.samples; ++k) {
      Draw d;
      d.index = g * options.samples + k;
      d.name = family.name + "_" + DrawFolder(d.index).substr(5);
      d.values = DrawValues(family, g, d.index, options.seed);
      const Values env(d.values.begin(), d.values.end());
      MatchRule(family, env, &d);
      d.yaml = MakeYaml(family, d, env, options.seed, preset);
      draws.push_back(std::move(d));
    }
  }
  return draws;
}

std::string DrawFolder(std::size_t index) {
  char text[32];
  std::snprintf(text, sizeof(text), "draw_%03zu", index);
  return text;
}

std::string DrawValuesLabel(const Draw& draw) { return Joined(draw.values, " "); }

namespace {

std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": cannot write it");
}

}  // namespace

std::vector<std::string> WriteDraws(const Family& family, const std::vector<Draw>& draws, const std::string& family_dir) {
  std::vector<std::string> paths;
  std::string csv = "draw,file,expectation,reason";
  for (const Parameter& p : family.parameters) csv += "," + CsvField(p.name);
  csv += "\n";
  for (const Draw& d : draws) {
    const fs::path dir = fs::path(family_dir) / DrawFolder(d.index);
    fs::create_directories(dir);
    WriteText(dir / "scenario.yaml", d.yaml);
    paths.push_back((dir / "scenario.yaml").string());
    csv += std::to_string(d.index) + "," + CsvField(paths.back()) + "," + ExpectationName(d.expectation) + "," + CsvField(d.reason);
    for (const auto& [name, v] : d.values) csv += "," + CsvField(v.ToString());
    csv += "\n";
  }
  WriteText(fs::path(family_dir) / "draws.csv", csv);
  return paths;
}

}  // namespace ovpc::scenarios
