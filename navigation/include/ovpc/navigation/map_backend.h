// The map-backend seam: what turns a prepared LiDAR cloud into the planner's map.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/types.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/planner/vertex_cloud_map.h"

namespace ovpc::navigation {

/// Ground the vehicle is known to stand on though the sensor never sees it (its own footprint).
using SupportRegion = planner::VertexCloudMap::Config::SupportRegion;

/// What a backend is told besides the cloud, all in the map frame L (origin at the viewpoint, axes
/// of the odometry frame O, z up).
struct MapContext {
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();  ///< the vehicle
  SupportRegion known_support;  ///< empty unless the navigator passes the vehicle's footprint
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
};

/// The OVPC Mesh map (the paper): GHPR visible set, free-space mesh, traversable vertex cloud, and
/// the planner's VertexCloudMap on it.
class OvpcMapBackend final : public MapBackend {
 public:
  struct Config {
    OvpcMapper::Config mapper;
    /// The planner's view of the vertex cloud. ground_reference_z_m and known_support are set per
    /// update from the MapContext.
    planner::VertexCloudMap::Config map;
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument for an invalid config.
  explicit OvpcMapBackend(const Config& config);

  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext& context) override;
  MapView View() const override;
  const char* name() const override { return "ovpc"; }

  /// The latest OVPC map (mesh, vertex cloud, stage timings); status not ok before the first update.
  const OvpcMap& latest() const { return latest_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  OvpcMapper mapper_;
  OvpcMap latest_;
};

}  // namespace ovpc::navigation
