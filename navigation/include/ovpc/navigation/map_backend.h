// The map-backend seam: what turns a prepared LiDAR cloud into the planner's map.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/backends/column_map.h"
#include "ovpc/backends/octomap_columns.h"
#include "ovpc/baselines/elevation_map.h"
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
  /// sanitize, transform, hull, mesh, traversability, vertex_cloud (OvpcMapper's StageTimings) and
  /// planning_map (the VertexCloudMap's grid).
  std::vector<MapStageTime> StageTimes() const override;

  /// The latest OVPC map (mesh, vertex cloud, stage timings); status not ok before the first update.
  const OvpcMap& latest() const { return latest_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  OvpcMapper mapper_;
  OvpcMap latest_;
  double planning_map_ms_ = 0.0;
};

/// OctoMap (Debian's liboctomap) as the map: per update a fresh octomap::OcTree from the buffered
/// cloud, inserted as one scan from the viewpoint (OcTree::insertPointCloud, OctoMap's default sensor
/// model), read into columns (backends::OctoMapColumns) and answered by a backends::ColumnMap. The
/// tree is rebuilt from the buffer each update rather than kept: the buffer already fuses the last
/// scans by odometry, as it does for OVPC, so both maps see the same points; a kept tree would also
/// keep what odometry drift smeared.
class OctoMapBackend final : public MapBackend {
 public:
  struct Config {
    double resolution_m = 0.2;  ///< voxel edge
    /// The planner's view. Its alpha_max_rad and delta_h_max_m are the OVPC face test's
    /// (Navigator::Config::Derived copies them); ground_reference_z_m and known_support are set per
    /// update.
    backends::ColumnMap::Config map;
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
  explicit OctoMapBackend(const Config& config);
  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext& context) override;
  MapView View() const override;
  const char* name() const override { return "octomap"; }
  /// insert (the OcTree), columns (reading it), traversability (ColumnMap: planes, steps).
  std::vector<MapStageTime> StageTimes() const override { return stages_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  backends::OctoMapColumns tree_;
  std::vector<MapStageTime> stages_;
  std::vector<Vec3> view_points_;
  std::vector<std::uint8_t> view_traversable_;
};

/// The project's 2.5D elevation map (baselines::ElevationMap) as the map: per update the grid is
/// cleared and the buffered cloud fused into it (the vehicle's ground height as the robot base), its
/// cells read into columns (backends::ElevationColumns) and answered by a backends::ColumnMap. One
/// height per cell: a roof over a cell is that cell's height (the 2.5D limitation, kept as it is).
class ElevationMapBackend final : public MapBackend {
 public:
  struct Config {
    baselines::ElevationMap::Config grid;
    /// As OctoMapBackend::Config::map.
    backends::ColumnMap::Config map;
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
  explicit ElevationMapBackend(const Config& config);
  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext& context) override;
  MapView View() const override;
  const char* name() const override { return "elevation"; }
  /// fuse (the height grid), columns (reading it), traversability (ColumnMap: planes, steps).
  std::vector<MapStageTime> StageTimes() const override { return stages_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  baselines::ElevationMap grid_;
  std::vector<MapStageTime> stages_;
  std::vector<Vec3> view_points_;
  std::vector<std::uint8_t> view_traversable_;
};

}  // namespace ovpc::navigation
