// PlanningMap on the OVPC vertex cloud (core's TraversabilityCloud).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "ovpc/core/vertex_cloud.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

/// Ground known to carry the vehicle without being seen: the vehicle's own footprint (the sensor
/// never sees the ground it stands on). A rectangle in the map's xy plane: `pose` (origin and
/// heading), x from `min_x_m` to `max_x_m` along the heading, y within +-`half_width_m`. With
/// FootprintCheck::kWheels, a wheel whose contact point lies in it is supported whatever the
/// nearest visible point is; the box test for obstacles is unchanged. Empty (the default) when
/// max_x_m <= min_x_m.
struct SupportRegion {
  Pose2 pose;
  double min_x_m = 0.0, max_x_m = 0.0, half_width_m = 0.0;
  /// A wheel in the region farther along than this (ahead of the vehicle's front wheels) is still
  /// refused on seen non-traversable ground (its nearest visible point within its support) and
  /// still gets the crest test (VehicleBox::crest_margin_m): under the nose the vehicle does not stand.
  double crest_from_x_m = std::numeric_limits<double>::infinity();
  bool empty() const { return !(max_x_m > min_x_m) || !(half_width_m > 0.0); }
  bool Contains(double x_m, double y_m) const;
};

/// Ground seen at earlier map updates, in the map frame, with each point's traversability: where
/// the present map has no visible point within a wheel's support, the remembered points judge it
/// (Carries; GroundContext::remembered). The tilted,
/// spinning sensor never sees the ground within about 1.1 m of its own mast (its steepest beam is
/// 60 degrees down), and the vehicle's footprint covers only part of that: behind the rear bumper,
/// the ground the vehicle came over or saw from farther away is unseen for as long as it stays.
class RememberedGround {
 public:
  RememberedGround() = default;
  /// @throws std::invalid_argument if a point is not finite or the sizes differ.
  RememberedGround(const std::vector<Vec3>& points_L, const std::vector<std::uint8_t>& traversable);
  /// Whether remembered ground carries a wheel at `p`: some remembered point lies within
  /// `radius_m` of it, the nearest (in space) within `dz_m` of its height, and every remembered
  /// point within `radius_m` is traversable (a lip, with its wall remembered below it, carries no
  /// wheel from memory).
  bool Carries(const Vec3& p, double radius_m, double dz_m) const;
  bool empty() const { return points_.empty(); }
  std::size_t size() const { return points_.size(); }

 private:
  static constexpr double kCellM = 0.5;
  double origin_x_m_ = 0.0, origin_y_m_ = 0.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_begin_;  // nx * ny + 1 offsets into points_ and traversable_
  std::vector<Vec3> points_;
  std::vector<std::uint8_t> traversable_;
};

/// Where the vehicle stands in the map frame, given per update (not a setting).
struct GroundContext {
  /// Height of the ground near the vehicle in the map frame. The nearest-point search starts at
  /// this height and is repeated once at the height found, so that it follows slopes and picks
  /// the ground under a roof rather than the roof. With the mapper's frame (viewpoint at the
  /// origin) it is minus the sensor height above the ground (-1.88 m on the paper's robot).
  double ground_reference_z_m = 0.0;
  SupportRegion known_support;
  /// Ground seen at earlier updates (none by default). It judges only a wheel with no visible
  /// point within its support (kUnseenGround unless it carries the wheel); a wheel with a visible
  /// point near it is judged by the present map alone, and the crest and box tests use only it.
  std::shared_ptr<const RememberedGround> remembered;
  /// @throws std::invalid_argument if a value is not finite.
  void Validate() const;
};

/// The paper's rule on the OVPC map: a planar pose is projected onto the nearest visible point (k-d
/// tree), the vehicle box is aligned to that point's normal with the heading kept, and the box is
/// free when no visible point lies inside it and no non-traversable point lies under its footprint.
/// Because the map is 3D, a roof and the ground under it are both in it: the projection searches
/// from the vehicle's ground height, and a roof lower than the box top collides, a higher one not.
class VertexCloudMap final : public PlanningMap {
 public:
  struct Config {
    /// A pose farther than this from its nearest visible point is outside known free space.
    double max_projection_distance_m = 0.75;
    /// The pose's ground plane passes through the nearest visible point. With `normal_neighbours`
    /// > 1 its normal is that of the least-squares plane through the nearest point and those of its
    /// `normal_neighbours` nearest within `normal_radius_m` of it (when they span a plane); with 1,
    /// the nearest point's own vertex normal (the paper's rule). Range noise tilts the small faces of
    /// measured ground and with them the vertex normals (by up to ~20 degrees on flat ground), and
    /// over the 3 m box such a tilt lifts flat ground near the box's ends above the ground
    /// clearance: a false collision. The fitted plane averages the noise out over the neighbours.
    int normal_neighbours = 1;
    double normal_radius_m = 0.5;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, max_projection_distance_m), "m", "farther from its nearest visible point a pose is unknown");
      v.Field(OVPC_FIELD(c, normal_neighbours), "points", "1: the nearest point's vertex normal (paper)");
      v.Field(OVPC_FIELD(c, normal_radius_m), "m", "the fitted plane's neighbours lie within this");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument for an invalid config, or a cloud with a non-finite point or
  /// normal (naming its index; OvpcMapper never makes one).
  VertexCloudMap(TraversabilityCloud cloud, const Config& config, const GroundContext& ground = {});

  std::optional<GroundPose> Project(const Pose2& pose) const override;
  std::optional<GroundPose> ProjectForBox(const Pose2& pose) const override;
  PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const override;
  bool IsKnownFree(double x_m, double y_m) const override;
  /// The planar bounding box of all visible points (the local mesh extent).
  MapBounds Bounds() const override { return bounds_; }

  const TraversabilityCloud& cloud() const { return cloud_; }
  const Config& config() const { return config_; }

 private:
  // The nearest visible point to the pose (see Project), if within max_projection_distance_m.
  std::optional<int> NearestIndex(const Pose2& pose) const;
  // The pose on the plane through point `index` with `normal` (level and not traversable if the
  // normal is too steep to stand on).
  GroundPose OnPlane(const Pose2& pose, int index, Vec3 normal) const;
  // A traversable visible point within `radius_m` of `contact` at least as far from the viewpoint
  // (in the plane) as the contact (VehicleBox::edge_tolerance_m).
  bool SeenBeyond(const Vec3& contact, double radius_m) const;
  // Visible point `index` carries a wheel that stands on it: traversable, or a foot
  // (TraversabilityCloud::IsFoot).
  bool CarriesWheel(int index) const;
  // The crest test (VehicleBox::crest_margin_m) for one wheel's contact on the ground of `ground`:
  // true if a ray went under the place beyond the wheel and no seen ground carries it.
  bool OverUnseenDrop(const GroundPose& ground, const Vec3& contact, const VehicleBox& vehicle) const;
  // Calls visit(point, traversable) for the grid's points in the planar box [lo_x, hi_x] x [lo_y,
  // hi_y] (by cells: points a little outside it are visited too) with a height in [lo_z, hi_z], until
  // it returns true; returns whether it did.
  template <class Visit>
  bool AnyInCells(double lo_x, double hi_x, double lo_y, double hi_y, double lo_z, double hi_z, Visit&& visit) const;
  // The normal of the plane fitted around point `index` (see Config::normal_neighbours).
  Vec3 FittedNormal(int index) const;
  // The box test runs for every state the planner checks, so the points are also kept in a planar
  // grid of cells (counting-sorted copies, contiguous per cell, sorted by height within a cell); the
  // test visits the cells under the box, only the run of each cell's points that can lie in the
  // box's height band, and stops at the first colliding point. Same answer as
  // TraversabilityCloud::InBox.
  struct Grid {
    double origin_x_m = 0.0, origin_y_m = 0.0, cell_m = 1.0;
    int nx = 0, ny = 0;
    std::vector<std::uint32_t> cell_begin;  // nx * ny + 1 offsets into points / traversable
    std::vector<Vec3> points;
    std::vector<std::uint8_t> traversable;
  };

  TraversabilityCloud cloud_;
  // Fitted normals, per point, made on first use: the planner projects many poses onto the same
  // points. Safe from concurrent const calls: a slot is written only by the thread that claimed it
  // (state 0 -> 1), and read once its state is 2; a thread that finds it claimed fits on its own.
  struct FitCache {
    explicit FitCache(std::size_t n) : state(new std::atomic<std::uint8_t>[n]()), normal(n) {}
    std::unique_ptr<std::atomic<std::uint8_t>[]> state;
    std::vector<Vec3> normal;
  };
  std::shared_ptr<FitCache> fits_;
  Config config_;
  GroundContext ground_;
  // The known support region's heading, for the box test's wheel checks (made once per map).
  double support_cos_ = 1.0, support_sin_ = 0.0;
  MapBounds bounds_;
  Grid grid_;
};

}  // namespace ovpc::planner
