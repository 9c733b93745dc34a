#include "family_yaml.h"

#include <cctype>
#include <cmath>
#include <set>
#include <tuple>

#include "config_yaml.h"

namespace ovpc::scenarios::internal {
namespace {

const std::set<std::string> kKeywords = {"uniform", "normal", "choice", "grid", "integer"};

// A family value: a number unless quoted or not numeric.
Value ScalarValue(const YAML::Node& node) {
  if (node.Tag() != "!") {
    try {
      const double v = node.as<double>();
      if (std::isfinite(v)) return Value::Number(v);
    } catch (const YAML::BadConversion&) {
    }
  }
  return Value::Word(node.Scalar());
}

std::pair<double, double> ReadRange(MapReader& r, const YAML::Node& list, const std::string& key, const std::string& form) {
  if (!list.IsSequence() || list.size() != 2) r.Fail(list, "'" + key + "' must be " + form);
  const double a = r.ConvertAt<double>(list[0], key), b = r.ConvertAt<double>(list[1], key);
  if (!std::isfinite(a) || !std::isfinite(b)) r.Fail(list, "'" + key + "' must be finite");
  return {a, b};
}

std::vector<Value> ReadValues(MapReader& r, const YAML::Node& list, const std::string& key) {
  if (!list.IsSequence() || list.size() == 0) r.Fail(list, "'" + key + "' must be a list of one or more values");
  std::vector<Value> values;
  for (const YAML::Node& item : list) {
    if (!item.IsScalar()) r.Fail(item, "'" + key + "' must list numbers or words");
    values.push_back(ScalarValue(item));
  }
  return values;
}

void ReadNormal(MapReader& r, const YAML::Node& v, Distribution* d) {
  const std::string key = r.Key("normal");
  std::tie(d->mean, d->sigma) = ReadRange(r, v, key, "[mean, sigma]");
  if (!(d->sigma > 0.0)) r.Fail(v, "'" + key + "' needs sigma > 0, got " + FormatNumber(d->sigma));
  if (const YAML::Node clip = r.Child("clip")) {
    std::tie(d->lo, d->hi) = ReadRange(r, clip, r.Key("clip"), "[lo, hi]");
    if (!(d->lo < d->hi)) r.Fail(clip, "'" + r.Key("clip") + "' must be [lo, hi] with lo < hi");
    d->clipped = true;
  }
}

}  // namespace

bool IsDistributionMap(const YAML::Node& node) {
  if (!node.IsMap() || node.size() == 0 || node.size() > 2) return false;
  int keywords = 0, others = 0;
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "";
    if (kKeywords.count(key)) ++keywords;
    else if (key != "clip") ++others;
  }
  return keywords == 1 && others == 0;
}

Distribution ReadDistribution(const YAML::Node& node, const std::string& context, const std::string& file) {
  MapReader r(node, context, file);
  Distribution d;
  std::string kind;
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "";
    if (key == "clip") continue;
    if (!kKeywords.count(key) || !kind.empty()) {
      r.Fail(kv.first, "'" + context + "': unknown distribution '" + key + "' (one of uniform, normal, choice, grid, integer)");
    }
    kind = key;
  }
  if (kind.empty()) r.Fail(node, "'" + context + "' needs a distribution (uniform, normal, choice, grid or integer)");
  const YAML::Node v = r.Child(kind.c_str());
  const std::string key = r.Key(kind.c_str());
  if (kind == "uniform" || kind == "integer") {
    d.kind = kind == "uniform" ? Distribution::Kind::kUniform : Distribution::Kind::kInteger;
    std::tie(d.lo, d.hi) = ReadRange(r, v, key, "[lo, hi]");
    if (kind == "uniform" && !(d.lo < d.hi)) r.Fail(v, "'" + key + "' must be [lo, hi] with lo < hi");
    if (kind == "integer" && (d.lo != std::floor(d.lo) || d.hi != std::floor(d.hi) || d.lo > d.hi ||
                              std::abs(d.lo) > 9e15 || std::abs(d.hi) > 9e15)) {
      r.Fail(v, "'" + key + "' must be [lo, hi], whole numbers with lo <= hi");
    }
  } else if (kind == "normal") {
    d.kind = Distribution::Kind::kNormal;
    ReadNormal(r, v, &d);
  } else {
    d.kind = kind == "choice" ? Distribution::Kind::kChoice : Distribution::Kind::kGrid;
    d.values = ReadValues(r, v, key);
  }
  if (d.kind != Distribution::Kind::kNormal && r.Child("clip")) r.Fail(node["clip"], "'" + r.Key("clip") + "' applies to normal only");
  r.Finish();
  return d;
}

namespace {

void Walk(const YAML::Node& node, const std::string& path, const NodeVisitor& on_distribution, const NodeVisitor& on_scalar) {
  if (node.IsScalar()) {
    on_scalar(node, path);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) Walk(node[i], path + "." + std::to_string(i), on_distribution, on_scalar);
  } else if (IsDistributionMap(node)) {
    on_distribution(node, path);
  } else if (node.IsMap()) {
    for (const auto& kv : node) {
      if (kv.first.IsScalar()) Walk(kv.second, path + "." + kv.first.Scalar(), on_distribution, on_scalar);
    }
  }
}

bool IsName(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.')) return false;
  }
  return true;
}

}  // namespace

void WalkBody(const YAML::Node& root, const NodeVisitor& on_distribution, const NodeVisitor& on_scalar) {
  for (const auto& kv : root) {
    if (!kv.first.IsScalar() || IsFamilyKey(kv.first.Scalar())) continue;
    const std::string key = kv.first.Scalar();
    // A top-level scalar's path is its key (a leading '.' would come from the join below).
    if (kv.second.IsScalar()) on_scalar(kv.second, key);
    else if (IsDistributionMap(kv.second)) on_distribution(kv.second, key);
    else Walk(kv.second, key, on_distribution, on_scalar);
  }
}

std::optional<std::string> ExpandScalar(const std::string& text, const std::function<std::string(const std::string&)>& name,
                                        const std::function<std::string(const std::string&)>& expr) {
  if (text.size() > 1 && text[0] == '$' && IsName(text.substr(1))) return name(text.substr(1));
  if (text.find("${") == std::string::npos) return std::nullopt;
  std::string out;
  std::size_t pos = 0;
  for (std::size_t open; (open = text.find("${", pos)) != std::string::npos;) {
    const std::size_t close = text.find('}', open);
    if (close == std::string::npos) throw ExpressionError("in '" + Abbreviated(text) + "': '${' without its '}'");
    out += text.substr(pos, open - pos) + expr(text.substr(open + 2, close - open - 2));
    pos = close + 1;
  }
  return out + text.substr(pos);
}

}  // namespace ovpc::scenarios::internal
