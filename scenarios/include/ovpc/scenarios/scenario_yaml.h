// Scenario files: YAML (yaml-cpp) into Scenario, strictly. The schema is in scenarios/README.md.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "ovpc/scenarios/scenario.h"

namespace ovpc::scenarios {

/// A malformed scenario: unknown key, wrong type, missing field, bad value. what() is one line,
/// "FILE:LINE: ..." naming the key.
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a scenario file. `settings` are "dotted.key=value" overrides applied to the YAML before it
/// is read (`ovpc run --set`, `ovpc suite --sweep`), e.g. "params.mapper.gamma=-0.02".
/// @throws ScenarioError.
Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings = {});

/// The same from YAML text (tests); `name_for_errors` stands for the file in messages.
Scenario ParseScenario(const std::string& yaml_text, const std::string& name_for_errors,
                       const std::vector<std::string>& settings = {});

}  // namespace ovpc::scenarios
