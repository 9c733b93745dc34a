// Scenario files: YAML (yaml-cpp) into Scenario, strictly. The schema is in scenarios/README.md.
#pragma once

#include <stdexcept>
#include <cstdint>
#include <string>
#include <vector>

#include "ovpc/scenarios/scenario.h"

namespace ovpc::scenarios {

/// A malformed scenario: unknown key, wrong type, missing field, bad value. what() is one line,
/// "FILE:LINE: ..." naming the key.
class ScenarioError : public std::runtime_error {
 public:
  /// Control characters in `what` (from a key or value of the file, or in yaml-cpp's own message,
  /// which can end in the raw character it could not read) are shown as \xHH, so what() is always
  /// one line.
  explicit ScenarioError(const std::string& what);
};

/// The robot's configuration a scenario starts from: YAML with a `navigator:` section (the keys of
/// navigation::VisitFields) and a `record:` section, and the file name that errors give.
struct Preset {
  std::string yaml;
  std::string file;
};

/// navigation/presets/default.yaml, the closed-loop defaults, as built into the program.
Preset DefaultPreset();
/// A preset file (a copy of the default one, edited).
/// @throws ScenarioError if it cannot be read.
Preset LoadPreset(const std::string& path);

/// Reads a scenario file over `preset`. `settings` are "dotted.key=value" overrides applied to the
/// scenario's YAML before it is read (`ovpc run --set`, `ovpc suite --sweep`), e.g.
/// "navigator.ovpc.mapper.ghpr.gamma=-0.02".
/// @throws ScenarioError (a malformed scenario or preset).
Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings = {},
                      const Preset& preset = DefaultPreset());

/// The same from YAML text (tests); `name_for_errors` stands for the file in messages.
Scenario ParseScenario(const std::string& yaml_text, const std::string& name_for_errors,
                       const std::vector<std::string>& settings = {}, const Preset& preset = DefaultPreset());

/// The effective configuration of a run of `scenario` with `seed` as YAML (`navigator:` and
/// `record:`, the preset's form): what `ovpc run --print-config` prints; a valid preset itself.
std::string FormatRunConfig(const Scenario& scenario, std::uint64_t seed);

}  // namespace ovpc::scenarios
