// What the family reader (family.cc) and the drawing (family_draw.cc) share: the walk over a family's
// body, inline distributions and the `$name` / `${expr}` scalars.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "ovpc/scenarios/family.h"

namespace ovpc::scenarios::internal {

/// Top-level keys of a family that are not part of its scenario body.
inline bool IsFamilyKey(const std::string& key) { return key == "parameters" || key == "expect"; }

/// A map whose one key is a distribution keyword (uniform, normal, choice, grid, integer), with at
/// most `clip` beside it.
bool IsDistributionMap(const YAML::Node& node);

/// Reads a distribution map; errors name `file`, the line and `context` (e.g. "parameters.roof_m").
/// @throws ScenarioError.
Distribution ReadDistribution(const YAML::Node& node, const std::string& context, const std::string& file);

using NodeVisitor = std::function<void(YAML::Node node, const std::string& path)>;
/// Visits the family's scenario body (every top-level key but parameters and expect): each inline
/// distribution and each scalar, with its dotted path ("objects.0.carport.roof_height_m").
void WalkBody(const YAML::Node& root, const NodeVisitor& on_distribution, const NodeVisitor& on_scalar);

/// A scalar's text with `$name` (the whole scalar) or each `${expr}` replaced by what `name` and
/// `expr` return; nullopt when it holds neither.
/// @throws ExpressionError for a `${` without its `}`.
std::optional<std::string> ExpandScalar(const std::string& text, const std::function<std::string(const std::string&)>& name,
                                        const std::function<std::string(const std::string&)>& expr);

}  // namespace ovpc::scenarios::internal
