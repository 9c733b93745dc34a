// Internal: what the OctoMap and elevation backends share around their ColumnMap.
#pragma once

#include <cstdint>
#include <vector>

#include "ovpc/backends/column_map.h"
#include "ovpc/navigation/map_backend.h"

namespace ovpc::backends::internal {

/// The per-update inputs of a column map.
inline ColumnMap::Config ColumnConfigFor(const ColumnMap::Config& config, const navigation::MapContext& context) {
  ColumnMap::Config c = config;
  c.ground_reference_z_m = context.T_L_B.translation().z();
  c.known_support = context.known_support;
  return c;
}

/// What a person looks at of a column map: its ground candidates with their verdicts.
inline void ViewOf(const ColumnMap& map, std::vector<Vec3>* points, std::vector<std::uint8_t>* traversable) {
  *points = map.GroundPoints();
  *traversable = map.ground_traversable();
}

/// The view of the points and flags kept by a column backend (empty before its first map).
inline navigation::MapView ViewOf(const std::vector<Vec3>& points, const std::vector<std::uint8_t>& traversable) {
  navigation::MapView view;
  if (points.empty()) return view;
  view.points_L = &points;
  view.traversable = &traversable;
  return view;
}

}  // namespace ovpc::backends::internal
