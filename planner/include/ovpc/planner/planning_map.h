// The narrow map interface the planner sees, the vehicle box, and the state validity rule.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>

#include <Eigen/Geometry>

#include "ovpc/core/vehicle_model.h"
#include "ovpc/planner/path.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

/// The rules of the vehicle box check: settings only. The box's size comes from the vehicle model
/// (VehicleBox::Of).
struct BoxRules {
  double margin_m = 0.1;             ///< added to every side and to the top
  double ground_clearance_m = 0.2;   ///< the box bottom, above the ground at the pose
  double footprint_depth_m = 0.5;    ///< non-traversable points down to this depth below the ground
                                     ///< under the footprint also block the pose (kAllPoints)
  /// What must hold for the ground under the box, below the ground clearance.
  enum class FootprintCheck {
    kAllPoints,  ///< no non-traversable point under the footprint (strict: a shadow's rim blocks)
    kWheels,     ///< each wheel's contact point lies within wheel_support_m of a traversable visible
                 ///< point; low non-traversable points between the wheels pass under the chassis
  };
  FootprintCheck footprint_check = FootprintCheck::kAllPoints;
  double wheel_support_m = 0.5;      ///< farthest a wheel may be from its nearest visible point (kWheels)
  /// kWheels: the support radius grows with the wheel's distance from the sensor (the map frame's
  /// origin, in the plane), as the spacing of the visible points does: min(wheel_support_m,
  /// max(wheel_support_near_m, wheel_support_per_m x distance)). Near the sensor, where the points
  /// are dense, a wheel half a metre past the last seen ground (over the edge of a ditch or a drop)
  /// is not supported. 0: wheel_support_m everywhere (the library's rule).
  double wheel_support_per_m = 0.0;
  double wheel_support_near_m = 0.2;  ///< the support radius close to the sensor (wheel_support_per_m)
  /// kWheels: a wheel whose nearest visible point is farther than this must also have traversable
  /// seen ground beyond it, as seen from the sensor (a point within wheel_support_m at least as far
  /// from the viewpoint, in the plane): a wheel may not stand past the last seen ground, over an
  /// edge or a ditch the sensor has not seen into. Infinite: no such test (wheel_support_m alone).
  double edge_tolerance_m = std::numeric_limits<double>::infinity();
  /// kWheels: the crest test. Take the place crest_margin_m beyond a wheel's contact point, away
  /// from the sensor (the map frame's origin) on the pose's ground plane. If a sensor ray passed
  /// more than crest_drop_m below it (a visible point lies beyond it, within 3 m along and 0.3 m
  /// aside, whose ray is that low there), the ground falls away there: past a ditch's lip, a drop or
  /// a crest. The place must then have seen traversable ground at or beyond it, within
  /// wheel_support_m in the plane and within crest_step_m in height plus what a slope of
  /// max_tilt_deg gains over the distance, or the pose is refused; ground in the map's known support
  /// (the footprint prior's, never seen) does not count. Where no ray went under the ground the test
  /// asks nothing. Negative: no such test.
  double crest_margin_m = -1.0;
  double crest_drop_m = 0.1;   ///< a ray this far below the wheel's ground shows a drop
  double crest_step_m = 0.25;  ///< seen ground at most this far below (or above) the wheel carries it
  /// How the box is placed on the ground.
  enum class Placement {
    kNearestPoint,   ///< the paper's rule: on the tangent plane of the visible point nearest the pose
    kWheelContacts,  ///< on the plane through the ground under the four wheels (each wheel projected
                     ///< like the pose), as the suspended vehicle sits where the slope changes: at a
                     ///< ramp's foot the front axle is already up the ramp
  };
  Placement placement = Placement::kNearestPoint;
  /// kWheelContacts: the plane through the wheels may tilt at most this much from level (the face
  /// test's alpha_max); a steeper placement is not traversable.
  double max_tilt_deg = 30.0;
  /// The placed box may roll (its y axis rise from level) at most this much, whatever the placement:
  /// across a slope within alpha_max the vehicle can still roll further than it safely may. 90: no
  /// limit (the paper's rule).
  double max_roll_deg = 90.0;
  /// The placed box's nose may point down a slope (its x axis sink below level) at most this much,
  /// whatever the placement: a vehicle braked and driven by its rear wheels alone, facing down a
  /// slope, carries its weight on the front wheels and can neither hold its speed going down nor
  /// back up: atan(mu b / (L + mu h)) for friction mu, the centre of mass b behind the front axle and
  /// h above the ground, wheelbase L. Facing up the same slope it can do both (it backs down). 90: no
  /// limit (the paper's rule).
  double max_nose_down_deg = 90.0;
  template <class C, class V>
  static void VisitFields(C& c, V& v) {
    v.Field(OVPC_FIELD(c, margin_m), "m", "added to every side and to the top");
    v.Field(OVPC_FIELD(c, ground_clearance_m), "m", "the box bottom above the ground at the pose");
    v.Field(OVPC_FIELD(c, footprint_depth_m), "m", "all_points: lower points under the footprint block too");
    v.Choice(OVPC_FIELD(c, footprint_check),
             Choices<FootprintCheck>{{"all_points", FootprintCheck::kAllPoints}, {"wheels", FootprintCheck::kWheels}},
             "what must hold for the ground under the box; all_points: paper");
    v.Field(OVPC_FIELD(c, wheel_support_m), "m", "wheels: farthest a wheel may be from a visible point");
    v.Field(OVPC_FIELD(c, wheel_support_per_m), "m/m", "wheels: the support radius per metre from the sensor; 0: off");
    v.Field(OVPC_FIELD(c, wheel_support_near_m), "m", "wheels: ... and at least this");
    v.Field(OVPC_FIELD(c, edge_tolerance_m), "m", "wheels: farther needs seen ground beyond; inf: off");
    v.Field(OVPC_FIELD(c, crest_margin_m), "m", "wheels: where a ray went under the ground, seen ground this far beyond each wheel; < 0: off");
    v.Field(OVPC_FIELD(c, crest_drop_m), "m", "wheels: a ray this far below the ground shows a drop");
    v.Field(OVPC_FIELD(c, crest_step_m), "m", "wheels: seen ground this far below the wheel still carries it");
    v.Choice(OVPC_FIELD(c, placement),
             Choices<Placement>{{"nearest_point", Placement::kNearestPoint}, {"wheel_contacts", Placement::kWheelContacts}},
             "how the box is placed on the ground; nearest_point: paper");
    v.Field(OVPC_FIELD(c, max_tilt_deg), "deg", "wheel_contacts: steepest plane through the wheels");
    v.Field(OVPC_FIELD(c, max_roll_deg), "deg", "the placed box's roll; 90: no limit (paper)");
    v.Field(OVPC_FIELD(c, max_nose_down_deg), "deg", "the placed box's nose-down pitch; 90: no limit (paper)");
  }
  /// The support radius of a wheel whose contact point lies `distance_m` from the sensor in the plane.
  double WheelSupportAt(double distance_m) const {
    if (!(wheel_support_per_m > 0.0)) return wheel_support_m;
    return std::min(wheel_support_m, std::max(wheel_support_near_m, wheel_support_per_m * distance_m));
  }
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// The vehicle as the collision check sees it: an oriented box around the body and the sensor mast,
/// its size from a VehicleModel, checked by the BoxRules. The defaults are the vehicle model's
/// (ovpc/core/vehicle_model.h, the paper's Gator TE) with the default rules.
struct VehicleBox : BoxRules {
  double length_m = VehicleModel{}.length_m;
  double width_m = VehicleModel{}.width_m;
  double height_m = VehicleModel{}.height_m;  ///< ground to the top of the sensor mast
  /// Box centre ahead of the pose origin (the rear axle).
  double centre_ahead_m = 0.5 * VehicleModel{}.length_m - VehicleModel{}.rear_overhang_m;
  double wheelbase_m = VehicleModel{}.wheelbase_m;  ///< front axle ahead of the pose origin (kWheels)
  double track_m = VehicleModel{}.track_m;  ///< wheel centre to wheel centre across (kWheels)

  /// The box of `vehicle` checked by `rules`.
  static VehicleBox Of(const VehicleModel& vehicle, const BoxRules& rules = {});
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// A pose placed on the ground: frame B has its origin on the local ground surface below the planar
/// pose, z along the surface normal and x along the heading projected onto the surface (the vehicle
/// aligned to the normal with its heading kept).
struct GroundPose {
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();
  bool traversable = false;  ///< the surface point the pose was projected onto is traversable
  Vec3 surface_point = Vec3::Zero();  ///< that point, in the map frame
};

/// Axis-aligned planar extent of a map, the planner's sampling bounds.
struct MapBounds {
  double min_x_m = 0.0;
  double max_x_m = 0.0;
  double min_y_m = 0.0;
  double max_y_m = 0.0;
  bool Contains(double x_m, double y_m) const {
    return x_m >= min_x_m && x_m <= max_x_m && y_m >= min_y_m && y_m <= max_y_m;
  }
};

/// Outcome of the validity check of one pose, in the order the checks run.
enum class PoseCheck {
  kValid,
  kOutsideMap,      ///< outside the bounds or no map point close enough below the pose
  kNotTraversable,  ///< projected onto a non-traversable point
  kCollision,       ///< a map point inside the box, above the ground clearance
  kGroundUnderFootprint,  ///< a non-traversable point under the footprint or a wheel (a steep face)
  /// A wheel without seen traversable ground: none within its support, or none at or beyond it
  /// from the viewpoint (an edge, a shadow, ground not yet seen).
  kUnseenGround,
  /// The crest test (VehicleBox::crest_margin_m): the ground a wheel stands on falls out of sight
  /// just beyond it, with no seen ground there to carry it.
  kCrest,
  /// The box placed on the ground tilts past max_tilt_deg, rolls past max_roll_deg or points its
  /// nose down past max_nose_down_deg (a cross slope, a turn on a ramp's face).
  kTiltsTooFar,
};
inline constexpr std::size_t kNumPoseChecks = 8;

/// The checks that find the ground under the wheels wanting (not traversable, unseen, a crest),
/// as against an obstacle in the box or a pose off the map.
inline bool IsGroundCheck(PoseCheck check) {
  return check == PoseCheck::kGroundUnderFootprint || check == PoseCheck::kUnseenGround || check == PoseCheck::kCrest;
}

/// What the planner needs from a map. Implemented for the OVPC vertex cloud (VertexCloudMap); an
/// OctoMap or a 2.5D grid can implement it too, for closed-loop comparisons. Implementations must be
/// deterministic and safe to call concurrently from const methods.
class PlanningMap {
 public:
  virtual ~PlanningMap() = default;
  /// Places the planar pose on the ground, or nothing when the place is outside known free space.
  virtual std::optional<GroundPose> Project(const Pose2& pose) const = 0;
  /// Project for the vehicle box placed on the nearest point (VehicleBox::Placement::kNearestPoint):
  /// the same place and traversability, on a ground plane the map may estimate over more than the
  /// one point (VertexCloudMap::Config::normal_neighbours). By default, Project.
  virtual std::optional<GroundPose> ProjectForBox(const Pose2& pose) const { return Project(pose); }
  /// kValid if the vehicle box at `ground` holds no map point above the ground clearance
  /// (kCollision otherwise) and no non-traversable point lies under its footprint
  /// (kGroundUnderFootprint otherwise); with the wheel checks, each wheel on seen traversable ground
  /// (kGroundUnderFootprint, kUnseenGround or kCrest otherwise). When several hold, the collision is
  /// reported.
  virtual PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const = 0;
  bool IsBoxFree(const GroundPose& ground, const VehicleBox& vehicle) const {
    return CheckBox(ground, vehicle) == PoseCheck::kValid;
  }
  /// True if (x, y) is inside known free space on traversable ground.
  virtual bool IsKnownFree(double x_m, double y_m) const = 0;
  virtual MapBounds Bounds() const = 0;
};

const char* PoseCheckName(PoseCheck check);

/// The planar pose placed on the plane through `point` with unit `normal` (normal.z() > 0): origin
/// dropped vertically onto the plane, x the heading tilted in its vertical plane onto the plane (the
/// yaw is kept exactly), z the normal.
GroundPose PoseOnPlane(const Pose2& pose, const Vec3& point, const Vec3& normal, bool traversable);

/// The ground pose of the vehicle on its four wheels (Placement::kWheelContacts): each wheel's contact
/// point, placed from `projected` (the pose projected by the map), is projected onto the ground like
/// a pose, and the box stands on the least-squares plane through the four contacts with the heading
/// kept and its origin below the planar pose. Nothing if a wheel is outside known space.
std::optional<GroundPose> PlaceOnWheels(const PlanningMap& map, const VehicleBox& vehicle, const Pose2& pose,
                                        const GroundPose& projected);

/// The vehicle box and the slab under its footprint in frame B of a ground pose (x along the heading
/// from the rear axle, z along the ground normal from the ground plane), and the planar bounding box
/// of its eight corners in the map frame: what a CheckBox implementation tests against.
struct BoxExtent {
  double min_x_m = 0.0, max_x_m = 0.0;  ///< along the heading, margins included
  double half_width_m = 0.0;
  double top_m = 0.0;                   ///< the box's top, margin included
  double bottom_m = 0.0;                ///< the slab's bottom (-footprint_depth_m)
  MapBounds planar;
};
BoxExtent BoxExtentAt(const GroundPose& ground, const VehicleBox& vehicle);

/// The planner's state validity rule: project, require traversable ground, place the vehicle
/// (VehicleBox::placement), then a free box.
PoseCheck CheckPose(const PlanningMap& map, const VehicleBox& vehicle, const Pose2& pose);

}  // namespace ovpc::planner
