// A planner::PlanningMap on a planar grid of columns: what the OctoMap and the 2.5D elevation
// backends share. Each column holds its occupied samples (heights) and its ground candidates
// (heights of surfaces the vehicle could stand on); the map fits a ground plane around every
// candidate and judges it traversable from that plane's slope and from the height steps to the
// neighbouring columns, with the same alpha_max and delta_h_max as the OVPC faces.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/planner/vertex_cloud_map.h"
#include "ovpc/core/config_fields.h"
#include "ovpc/core/traversability.h"

namespace ovpc::backends {

/// The columns of a map, as a backend fills them. Column (ix, iy) covers
/// [origin_x_m + ix res, origin_x_m + (ix + 1) res) x [origin_y_m + iy res, ...); its index is
/// iy * nx + ix. Per column, `*_begin[c] .. *_begin[c + 1]` index its entries, sorted by height.
struct ColumnGrid {
  double resolution_m = 0.1;
  double origin_x_m = 0.0, origin_y_m = 0.0;
  int nx = 0, ny = 0;
  /// Ground candidates: the height of a surface with known free space above it (OctoMap: the top of
  /// a run of occupied voxels whose next voxel up is free; elevation map: the cell's height).
  std::vector<std::uint32_t> ground_begin;  ///< nx * ny + 1 offsets
  std::vector<float> ground_z;
  /// Occupied samples: heights of what the box must not hold (OctoMap: occupied voxel centres;
  /// elevation map: the cell's height), with the index of the ground candidate that tops each
  /// sample's run (-1: none, the sample is no ground), for the footprint test.
  std::vector<std::uint32_t> sample_begin;  ///< nx * ny + 1 offsets
  std::vector<float> sample_z;
  std::vector<std::int32_t> sample_ground;
  /// true: a sample is the top of a solid column reaching down without end (a 2.5D cell: all below
  /// its height is taken as filled). false: a sample is one voxel, a point at its centre.
  bool solid_below = false;

  /// An empty grid of nx x ny columns (offsets all zero).
  void Reset(double resolution, double origin_x, double origin_y, int columns_x, int columns_y);
  std::size_t num_columns() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  double CentreX(int ix) const { return origin_x_m + (ix + 0.5) * resolution_m; }
  double CentreY(int iy) const { return origin_y_m + (iy + 0.5) * resolution_m; }
};

/// The PlanningMap on a ColumnGrid. A pose is projected onto the ground candidate of the nearest
/// column (in the plane, within max_projection_distance_m) that has one, the candidate nearest the
/// vehicle's ground height where a column has several (a roof seen from above over the ground
/// under it); nothing within that distance is unknown, never free. The box collides with an
/// occupied sample inside it above the ground clearance (a solid column: any part of it), and the
/// VehicleBox footprint rules (all_points, wheels with wheel_support_m and edge_tolerance_m, the
/// known support) hold as for VertexCloudMap, with the ground candidates as the visible points.
class ColumnMap final : public planner::PlanningMap {
 public:
  struct Config {
    /// Planar distance from a pose to the nearest column with ground beyond which the pose is
    /// outside known space.
    double max_projection_distance_m = 0.75;
    /// The ground plane at a candidate is fitted through the candidates of the columns within this
    /// planar distance and height difference (at least three, spanning a plane; otherwise level).
    double normal_radius_m = 0.5;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, max_projection_distance_m), "m", "farther from a column with ground a pose is unknown");
      v.Field(OVPC_FIELD(c, normal_radius_m), "m", "the ground plane is fitted over the columns within this");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// Fits the ground planes and judges every candidate.
  /// @throws std::invalid_argument for an invalid config or grid (sizes that do not match).
  /// A candidate is traversable when its plane tilts less than `faces.alpha_max_rad` from level
  /// and no neighbouring column's nearest candidate differs in height by more than
  /// `faces.delta_h_max_m` (the OVPC face test's thresholds). `ground`, as for VertexCloudMap: the
  /// vehicle's ground height in the map frame (picks among a column's candidates) and the ground
  /// it stands on unseen.
  ColumnMap(ColumnGrid grid, const Config& config, const planner::GroundContext& ground = {},
            const Traversability::Config& faces = {});

  std::optional<planner::GroundPose> Project(const planner::Pose2& pose) const override;
  planner::PoseCheck CheckBox(const planner::GroundPose& ground, const planner::VehicleBox& vehicle) const override;
  bool IsKnownFree(double x_m, double y_m) const override;
  /// The planar extent of the columns with occupied samples.
  planner::MapBounds Bounds() const override { return bounds_; }

  const ColumnGrid& grid() const { return grid_; }
  /// Per ground candidate (indices as ColumnGrid::ground_z): the fitted normal and the verdict.
  const std::vector<Vec3>& ground_normals() const { return normals_; }
  const std::vector<std::uint8_t>& ground_traversable() const { return traversable_; }
  /// The candidates as points (column centre, height), e.g. for pictures.
  std::vector<Vec3> GroundPoints() const;
  std::size_t num_ground() const { return grid_.ground_z.size(); }
  const Config& config() const { return config_; }

 private:
  struct Candidate {
    int index = -1;
    int ix = 0, iy = 0;
  };
  // The column's candidate nearest to height z, or -1.
  int NearestInColumn(std::size_t column, double z) const;
  // The nearest column (planar) within radius_m of (x, y) with a candidate, and its candidate
  // nearest to z.
  std::optional<Candidate> NearestGround(double x_m, double y_m, double z_m, double radius_m) const;
  // The candidate nearest in 3D to p within radius_m (-1 if none), and its distance.
  int Nearest3d(const Vec3& p, double radius_m, double* distance_m) const;
  bool SeenBeyond(const Vec3& contact, double radius_m) const;
  Vec3 GroundPoint(int index) const;
  void Judge();

  ColumnGrid grid_;
  Config config_;
  planner::GroundContext ground_;
  Traversability::Config faces_;
  std::vector<int> ground_column_;  // per candidate: its column
  std::vector<Vec3> normals_;
  std::vector<std::uint8_t> traversable_;
  double support_cos_ = 1.0, support_sin_ = 0.0;
  planner::MapBounds bounds_;
};

}  // namespace ovpc::backends
