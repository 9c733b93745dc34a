// Reading a scenario from an already loaded YAML tree (the family reader checks its draws this way,
// so that errors name the family file's lines).
#pragma once

#include <string>

#include <yaml-cpp/yaml.h>

#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios::internal {

/// The scenario in `root` (a map) over `preset`; errors name `file` and the nodes' lines.
/// @throws ScenarioError.
Scenario ParseScenarioNode(const YAML::Node& root, const std::string& file, const Preset& preset);

}  // namespace ovpc::scenarios::internal
