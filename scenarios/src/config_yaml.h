// Reading YAML into Configs: a map reader that names file, line and key in every error, and the
// visitors that walk each Config's own declaration of its fields (VisitFields, see
// ovpc/core/config_fields.h) to read and write them.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <initializer_list>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "format.h"
#include "ovpc/core/config_fields.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios::internal {

inline std::string Where(const std::string& file, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return file + " (--set)";
  return file + ":" + std::to_string(mark.line + 1);
}

/// The node under `section` that a Validate() message names: its leading dotted key ("ramp.angle_deg
/// must be ...", "TerrainConfig: ramp.angle_deg ...", "route[3] lies ..."), or the longest tail of
/// that key found there ("World: boxes[0].length_m" finds `length_m`); nullopt when none is there.
inline std::optional<YAML::Node> NodeNamedBy(const YAML::Node& section, const std::string& message) {
  std::size_t start = 0;
  const std::size_t colon = message.find(": ");
  if (colon != std::string::npos && message.find(' ') > colon) start = colon + 2;  // "TerrainConfig: ..."
  std::vector<std::string> parts(1);
  for (std::size_t i = start; i < message.size(); ++i) {
    const char c = message[i];
    if (c == '.' || c == '[') parts.emplace_back();
    else if (std::isalnum(static_cast<unsigned char>(c)) || c == '_') parts.back() += c;
    else if (c != ']') break;
  }
  for (std::size_t first = 0; first < parts.size(); ++first) {
    YAML::Node node = section;
    std::size_t k = first;
    for (; k < parts.size() && !parts[k].empty(); ++k) {
      const std::string& part = parts[k];
      const bool index = part.size() < 9 && std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; });
      const YAML::Node& here = node;  // const lookups never add keys
      const YAML::Node next = here.IsMap() ? here[part]
                              : here.IsSequence() && index && std::stoul(part) < here.size() ? here[std::stoul(part)]
                                                                                              : YAML::Node(YAML::NodeType::Undefined);
      if (!next.IsDefined()) break;
      node.reset(next);  // (assignment would copy the value into the document)
    }
    if (k == parts.size() && k > first) return node;
  }
  return std::nullopt;
}

/// Runs a Config's `validate()`; what it refuses becomes a ScenarioError at the line of the key the
/// message names within `section` (else at the section's), "FILE:LINE: in 'CONTEXT': message".
template <class F>
void ValidateAt(const std::string& file, const YAML::Node& section, const std::string& context, F validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    const std::optional<YAML::Node> at = NodeNamedBy(section, e.what());
    throw ScenarioError(Where(file, at ? *at : section) + ": in '" + context + "': " + e.what());
  }
}

template <class T>
inline const char* TypeName() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  else if constexpr (std::is_integral_v<T>) return "a whole number";
  else if constexpr (std::is_floating_point_v<T>) return "a number";
  else return "a string";
}

// Reads one YAML map: every key it is asked for is marked used, and Finish() reports the rest as
// unknown. Errors name the file, the line and the dotted key.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string context, const std::string& file)
      : node_(node), context_(std::move(context)), file_(file) {
    if (!node_.IsMap()) Fail(node_, "'" + context_ + "' must be a mapping of keys to values");
    // YAML says a key appears once in a mapping; yaml-cpp keeps both and reads the first.
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      if (kv.first.IsScalar() && !seen.insert(kv.first.Scalar()).second) {
        Fail(kv.first, "duplicate key '" + Key(kv.first.Scalar().c_str()) + "'");
      }
    }
  }

  template <class T>
  void Get(const char* key, T* out) {
    const YAML::Node value = Take(key);
    if (value) *out = Convert<T>(value, key);
  }
  template <class T>
  void GetOptional(const char* key, std::optional<T>* out) {
    const YAML::Node value = Take(key);
    if (value) *out = Convert<T>(value, key);
  }
  template <class T>
  void Required(const char* key, T* out) {
    const YAML::Node value = Take(key);
    if (!value) Fail(node_, "'" + Key(key) + "' is required");
    *out = Convert<T>(value, key);
  }
  /// A key whose value is one of `choices` (name, value); anything else fails naming them.
  template <class T>
  void GetChoice(const char* key, std::initializer_list<std::pair<const char*, T>> choices, T* out) {
    const YAML::Node value = Take(key);
    if (!value) return;
    const std::string text = value.IsScalar() ? value.Scalar() : "";
    std::string names;
    for (const auto& [name, choice] : choices) {
      if (text == name) {
        *out = choice;
        return;
      }
      names += (names.empty() ? "" : " or ") + std::string(name);
    }
    Fail(value, "'" + Key(key) + "' must be " + names + ", got '" + text + "'");
  }
  void GetDegrees(const char* key, double* out_rad) {
    const YAML::Node value = Take(key);
    if (value) *out_rad = DegToRad(Convert<double>(value, key));
  }
  Eigen::Vector2d GetXY(const YAML::Node& value, const std::string& key) const {
    if (!value.IsSequence() || value.size() != 2) Fail(value, "'" + key + "' must be [x, y]");
    return Eigen::Vector2d(ConvertAt<double>(value[0], key), ConvertAt<double>(value[1], key));
  }
  YAML::Node Child(const char* key) { return Take(key); }
  std::string Key(const char* key) const { return context_.empty() ? key : context_ + "." + key; }
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

  void Finish() const {
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) Fail(kv.first, "a key in '" + context_ + "' is not a word");
      const std::string key = kv.first.as<std::string>();
      if (!used_.count(key)) Fail(kv.first, "unknown key '" + Key(key.c_str()) + "'");
    }
  }

  [[noreturn]] void Fail(const YAML::Node& at, const std::string& what) const {
    throw ScenarioError(Where(file_, at) + ": " + what);
  }

  template <class T>
  T ConvertAt(const YAML::Node& value, const std::string& key) const {
    if (!value.IsScalar()) Fail(value, "'" + key + "' must be " + TypeName<T>());
    try {
      const T converted = value.as<T>();
      if constexpr (std::is_floating_point_v<T>) {
        if (std::isnan(converted)) Fail(value, "'" + key + "' must be a number, got '" + value.Scalar() + "'");
      }
      return converted;
    } catch (const YAML::BadConversion&) {
      Fail(value, "'" + key + "' must be " + TypeName<T>() + ", got '" + value.Scalar() + "'");
    }
  }

 private:
  YAML::Node Take(const char* key) {
    used_.insert(key);
    const YAML::Node& node = node_;  // const lookup never inserts the key
    return node[key];
  }
  template <class T>
  T Convert(const YAML::Node& value, const char* key) const {
    return ConvertAt<T>(value, Key(key));
  }

  YAML::Node node_;
  std::string context_;
  const std::string& file_;
  std::set<std::string> used_;
};

template <class C, class = void>
struct HasValidate : std::false_type {};
template <class C>
struct HasValidate<C, std::void_t<decltype(std::declval<const C&>().Validate())>> : std::true_type {};

/// Reads a Config's fields from a YAML map (keys are the fields' names; unknown keys fail). Each
/// section is validated as soon as it is read, so that a bad value is reported at its section's
/// line, in the file it came from.
class ConfigReader {
 public:
  explicit ConfigReader(MapReader& r) : r_(r) {}
  template <class T>
  void Field(const char* key, T& value, const char* /*unit*/, const char* /*why*/) {
    r_.Get(key, &value);
  }
  void Field(const char* key, std::vector<double>& value, const char* /*unit*/, const char* /*why*/) {
    const YAML::Node list = r_.Child(key);
    if (!list) return;
    if (!list.IsSequence()) r_.Fail(list, "'" + r_.Key(key) + "' must be a list of numbers");
    value.clear();
    for (const auto& item : list) value.push_back(r_.ConvertAt<double>(item, r_.Key(key)));
  }
  template <class E>
  void Choice(const char* key, E& value, Choices<E> choices, const char* /*why*/) {
    r_.GetChoice(key, choices, &value);
  }
  template <class C>
  void Section(const char* key, C& config, const char* /*why*/) {
    const YAML::Node node = r_.Child(key);
    if (!node) return;
    MapReader m(node, r_.Key(key), r_.file());
    ConfigReader sub(m);
    ovpc::VisitFields(config, sub);
    m.Finish();
    if constexpr (HasValidate<C>::value) ValidateAt(r_.file(), node, r_.Key(key), [&config] { config.Validate(); });
  }

 private:
  MapReader& r_;
};

/// Writes a Config as block-style YAML, keys in the order of its declaration.
class YamlWriter {
 public:
  explicit YamlWriter(int indent = 0) : indent_(indent) {}
  template <class T>
  void Field(const char* key, const T& value, const char* /*unit*/, const char* /*why*/) {
    Line(key) << Scalar(value) << "\n";
  }
  void Field(const char* key, const std::vector<double>& value, const char* /*unit*/, const char* /*why*/) {
    Line(key) << "[";
    for (std::size_t i = 0; i < value.size(); ++i) out_ << (i ? ", " : "") << FormatNumber(value[i]);
    out_ << "]\n";
  }
  template <class E>
  void Choice(const char* key, const E& value, Choices<E> choices, const char* /*why*/) {
    for (const auto& [name, choice] : choices) {
      if (choice == value) Line(key) << name << "\n";
    }
  }
  template <class C>
  void Section(const char* key, const C& config, const char* /*why*/) {
    out_ << std::string(indent_, ' ') << key << ":\n";
    indent_ += 2;
    ovpc::VisitFields(config, *this);
    indent_ -= 2;
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostream& Line(const char* key) { return out_ << std::string(indent_, ' ') << key << ": "; }
  static std::string Scalar(bool v) { return v ? "true" : "false"; }
  static std::string Scalar(double v) { return FormatNumber(v); }
  template <class T>
  static std::string Scalar(T v) {
    return std::to_string(v);
  }
  int indent_;
  std::ostringstream out_;
};

/// Writes a Config as a JSON object (infinite numbers as the strings "inf" and "-inf").
class JsonWriter {
 public:
  template <class T>
  void Field(const char* key, const T& value, const char* /*unit*/, const char* /*why*/) {
    if constexpr (std::is_floating_point_v<T>) {
      if (std::isinf(value)) {
        json_[key] = value > 0 ? "inf" : "-inf";
        return;
      }
    }
    json_[key] = value;
  }
  template <class E>
  void Choice(const char* key, const E& value, Choices<E> choices, const char* /*why*/) {
    for (const auto& [name, choice] : choices) {
      if (choice == value) json_[key] = name;
    }
  }
  template <class C>
  void Section(const char* key, const C& config, const char* /*why*/) {
    JsonWriter sub;
    ovpc::VisitFields(config, sub);
    json_[key] = sub.json_;
  }
  const nlohmann::json& json() const { return json_; }

 private:
  nlohmann::json json_ = nlohmann::json::object();
};

}  // namespace ovpc::scenarios::internal
