// Internal: what the OctoMap and elevation backends share around their ColumnMap.
#pragma once

#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ovpc/backends/column_map.h"
#include "ovpc/navigation/map_backend.h"

namespace ovpc::backends::internal {

/// The plane fit at each ground candidate reads the columns within normal_radius_m: beyond this
/// many columns of radius an update's cost grows without bound (the defaults are 2.5 and 5).
constexpr double kMaxNormalRadiusCells = 20.0;

/// A number as a person writes it (20, 0.2, 1e+06).
inline std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

/// @throws std::invalid_argument naming `section`.map.normal_radius_m when it spans more than
/// kMaxNormalRadiusCells columns of `resolution_m`.
inline void CheckNormalRadius(const ColumnMap::Config& map, double resolution_m, const std::string& section) {
  const double max_m = kMaxNormalRadiusCells * resolution_m;
  if (map.normal_radius_m <= max_m) return;
  throw std::invalid_argument(section + ".map.normal_radius_m must be at most " + Number(kMaxNormalRadiusCells) +
                              " cells (" + Number(max_m) + " m at resolution_m " + Number(resolution_m) + "), got " +
                              Number(map.normal_radius_m));
}

/// Where the vehicle stands, the per-update input of a column map.
inline planner::GroundContext GroundOf(const navigation::MapContext& context) {
  planner::GroundContext ground;
  ground.ground_reference_z_m = context.T_L_B.translation().z();
  ground.known_support = context.known_support;
  return ground;
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
