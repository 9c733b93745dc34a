// The map-backend seam: what turns a prepared LiDAR cloud into the planner's map. The interface
// alone: the default backend is OvpcMapBackend (ovpc_map_backend.h); the comparison backends
// (OctoMap, a 2.5D elevation map) live in backends/, outside the robot's library.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/types.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/planner/vertex_cloud_map.h"

namespace ovpc::navigation {

/// Ground the vehicle is known to stand on though the sensor never sees it (its own footprint).
using SupportRegion = planner::SupportRegion;

/// What a backend is told besides the cloud, all in the map frame L (origin at the viewpoint, axes
/// of the odometry frame O, z up).
struct MapContext {
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();  ///< the vehicle
  SupportRegion known_support;  ///< empty unless the navigator passes the vehicle's footprint
  Vec3 L_in_O = Vec3::Zero();   ///< frame L's origin in the odometry frame O (L is O shifted)
  double time_s = 0.0;          ///< the update's time (simulated or robot time)
};

/// What the latest map shows a person: its points with a traversability flag and, for a mesh map,
/// the mesh with vertex normals. Pointers into the backend, valid until its next Update; null where
/// the backend has nothing of the kind.
struct MapView {
  const std::vector<Vec3>* points_L = nullptr;
  const std::vector<std::uint8_t>* traversable = nullptr;
  const FreeSpaceMesh* mesh_L = nullptr;
  const std::vector<Vec3>* normals_L = nullptr;
};

/// Wall-clock milliseconds of one stage of the latest update (for reports; nothing depends on them).
struct MapStageTime {
  std::string name;
  double ms = 0.0;
};

/// One narrow job: build a PlanningMap from the buffered, prepared cloud. The navigator owns the
/// buffer and the preparation; a backend sees the cloud in frame L with the viewpoint at the origin.
/// Implementations must be deterministic.
class MapBackend {
 public:
  virtual ~MapBackend() = default;
  /// The map for this cloud, or null when the cloud gives none (too few points, degenerate); the
  /// navigator then keeps its current path and plans nothing this cycle. Never throws on bad data.
  virtual std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext& context) = 0;
  /// The latest map for pictures and logs (see MapView).
  virtual MapView View() const { return {}; }
  /// A short name for logs ("ovpc", "octomap", ...).
  virtual const char* name() const = 0;
  /// The latest update's stages in their order, timed (empty when the backend does not time them).
  virtual std::vector<MapStageTime> StageTimes() const { return {}; }
};

}  // namespace ovpc::navigation
