#include "ovpc/planner/planning_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ovpc::planner {
namespace {

void RequirePositive(double value, const char* field) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("VehicleBox: ") + field + " must be > 0, got " + std::to_string(value));
  }
}
void RequireNonNegative(double value, const char* field) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("VehicleBox: ") + field + " must be >= 0, got " +
                                std::to_string(value));
  }
}

}  // namespace

void BoxRules::Validate() const {
  RequireNonNegative(margin_m, "margin_m");
  RequireNonNegative(ground_clearance_m, "ground_clearance_m");
  RequireNonNegative(footprint_depth_m, "footprint_depth_m");
  RequirePositive(wheel_support_m, "wheel_support_m");
  RequireNonNegative(wheel_support_per_m, "wheel_support_per_m");
  RequirePositive(wheel_support_near_m, "wheel_support_near_m");
  if (!(edge_tolerance_m >= 0.0)) {
    throw std::invalid_argument("VehicleBox: edge_tolerance_m must be >= 0 (infinite: off), got " + std::to_string(edge_tolerance_m));
  }
  if (!std::isfinite(crest_margin_m)) throw std::invalid_argument("VehicleBox: crest_margin_m must be finite (negative: off)");
  RequirePositive(crest_drop_m, "crest_drop_m");
  RequirePositive(crest_step_m, "crest_step_m");
  if (!(max_tilt_deg > 0.0 && max_tilt_deg < 90.0)) {
    throw std::invalid_argument("VehicleBox: max_tilt_deg must be in (0, 90), got " + std::to_string(max_tilt_deg));
  }
  if (!(max_roll_deg > 0.0 && max_roll_deg <= 90.0)) {
    throw std::invalid_argument("VehicleBox: max_roll_deg must be in (0, 90], got " + std::to_string(max_roll_deg));
  }
  if (!(max_nose_down_deg > 0.0 && max_nose_down_deg <= 90.0)) {
    throw std::invalid_argument("VehicleBox: max_nose_down_deg must be in (0, 90], got " + std::to_string(max_nose_down_deg));
  }
}

VehicleBox VehicleBox::Of(const VehicleModel& vehicle, const BoxRules& rules) {
  VehicleBox box;
  static_cast<BoxRules&>(box) = rules;
  box.length_m = vehicle.length_m;
  box.width_m = vehicle.width_m;
  box.height_m = vehicle.height_m;
  box.centre_ahead_m = 0.5 * vehicle.length_m - vehicle.rear_overhang_m;
  box.wheelbase_m = vehicle.wheelbase_m;
  box.track_m = vehicle.track_m;
  return box;
}

void VehicleBox::Validate() const {
  BoxRules::Validate();
  RequirePositive(length_m, "length_m");
  RequirePositive(width_m, "width_m");
  RequirePositive(height_m, "height_m");
  RequirePositive(wheelbase_m, "wheelbase_m");
  RequirePositive(track_m, "track_m");
  if (!std::isfinite(centre_ahead_m)) throw std::invalid_argument("VehicleBox: centre_ahead_m must be finite");
  if (!(ground_clearance_m < height_m + margin_m)) {
    throw std::invalid_argument("VehicleBox: ground_clearance_m must be below the box top (height_m + margin_m)");
  }
}

const char* PoseCheckName(PoseCheck check) {
  switch (check) {
    case PoseCheck::kValid: return "valid";
    case PoseCheck::kOutsideMap: return "outside map";
    case PoseCheck::kNotTraversable: return "not traversable";
    case PoseCheck::kCollision: return "collision";
    case PoseCheck::kGroundUnderFootprint: return "ground under footprint";
    case PoseCheck::kUnseenGround: return "unseen ground";
    case PoseCheck::kCrest: return "crest";
    case PoseCheck::kTiltsTooFar: return "tilts too far";
  }
  return "unknown";
}

GroundPose PoseOnPlane(const Pose2& pose, const Vec3& point, const Vec3& normal, bool traversable) {
  const double z = point.z() - (normal.x() * (pose.x_m - point.x()) + normal.y() * (pose.y_m - point.y())) / normal.z();
  const Vec3 heading(std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), 0.0);
  const Vec3 x_axis = (heading - heading.dot(normal) / normal.z() * Vec3::UnitZ()).normalized();
  GroundPose ground;
  ground.traversable = traversable;
  ground.surface_point = point;
  Eigen::Matrix3d R_L_B;
  R_L_B.col(0) = x_axis;
  R_L_B.col(1) = normal.cross(x_axis);
  R_L_B.col(2) = normal;
  ground.T_L_B.linear() = R_L_B;
  ground.T_L_B.translation() = Vec3(pose.x_m, pose.y_m, z);
  return ground;
}

std::optional<GroundPose> PlaceOnWheels(const PlanningMap& map, const VehicleBox& vehicle, const Pose2& pose,
                                        const GroundPose& projected) {
  // Contacts: rear left, rear right, front left, front right.
  Vec3 contact[4];
  int k = 0;
  for (double x : {0.0, vehicle.wheelbase_m}) {
    for (double y : {0.5 * vehicle.track_m, -0.5 * vehicle.track_m}) {
      const Vec3 guess = projected.T_L_B * Vec3(x, y, 0.0);
      const std::optional<GroundPose> under = map.Project(Pose2{guess.x(), guess.y(), pose.yaw_rad});
      if (!under) return std::nullopt;
      contact[k++] = under->T_L_B.translation();
    }
  }
  // The least-squares plane through the four corners of a rectangle: it passes through their centroid
  // and spans the mean of the two axle directions and the mean of the two side directions.
  const Vec3 along = 0.5 * ((contact[2] - contact[0]) + (contact[3] - contact[1]));
  const Vec3 left = 0.5 * ((contact[0] - contact[1]) + (contact[2] - contact[3]));
  Vec3 normal = along.cross(left);
  if (!(normal.z() > 0.0) || !(normal.norm() > 0.0)) return std::nullopt;
  normal.normalize();
  const Vec3 centroid = 0.25 * (contact[0] + contact[1] + contact[2] + contact[3]);
  return PoseOnPlane(pose, centroid, normal, projected.traversable);
}

BoxExtent BoxExtentAt(const GroundPose& ground, const VehicleBox& vehicle) {
  BoxExtent e;
  e.min_x_m = vehicle.centre_ahead_m - 0.5 * vehicle.length_m - vehicle.margin_m;
  e.max_x_m = vehicle.centre_ahead_m + 0.5 * vehicle.length_m + vehicle.margin_m;
  e.half_width_m = 0.5 * vehicle.width_m + vehicle.margin_m;
  e.top_m = vehicle.height_m + vehicle.margin_m;
  e.bottom_m = -vehicle.footprint_depth_m;
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (double x : {e.min_x_m, e.max_x_m}) {
    for (double y : {-e.half_width_m, e.half_width_m}) {
      for (double z : {e.bottom_m, e.top_m}) {
        const Vec3 c = ground.T_L_B * Vec3(x, y, z);
        lo_x = std::min(lo_x, c.x()), hi_x = std::max(hi_x, c.x());
        lo_y = std::min(lo_y, c.y()), hi_y = std::max(hi_y, c.y());
      }
    }
  }
  e.planar = MapBounds{lo_x, hi_x, lo_y, hi_y};
  return e;
}

PoseCheck CheckPose(const PlanningMap& map, const VehicleBox& vehicle, const Pose2& pose) {
  if (!std::isfinite(pose.x_m) || !std::isfinite(pose.y_m) || !std::isfinite(pose.yaw_rad) ||
      !map.Bounds().Contains(pose.x_m, pose.y_m)) {
    return PoseCheck::kOutsideMap;
  }
  const bool on_wheels = vehicle.placement == VehicleBox::Placement::kWheelContacts;
  const std::optional<GroundPose> ground = on_wheels ? map.Project(pose) : map.ProjectForBox(pose);
  if (!ground) return PoseCheck::kOutsideMap;
  if (!ground->traversable) return PoseCheck::kNotTraversable;
  // The box's y axis rises by sin(roll) from level; its x axis (the nose) sinks by sin(pitch) facing
  // down a slope.
  const auto tilts_too_far = [&vehicle](const GroundPose& g) {
    return (vehicle.max_roll_deg < 90.0 && std::abs(g.T_L_B.linear()(2, 1)) > std::sin(vehicle.max_roll_deg * kPi / 180.0)) ||
           (vehicle.max_nose_down_deg < 90.0 && -g.T_L_B.linear()(2, 0) > std::sin(vehicle.max_nose_down_deg * kPi / 180.0));
  };
  if (on_wheels) {
    const std::optional<GroundPose> placed = PlaceOnWheels(map, vehicle, pose, *ground);
    if (!placed) return PoseCheck::kUnseenGround;  // a wheel over unknown ground
    if (placed->T_L_B.linear()(2, 2) < std::cos(vehicle.max_tilt_deg * kPi / 180.0)) return PoseCheck::kTiltsTooFar;
    if (tilts_too_far(*placed)) return PoseCheck::kTiltsTooFar;
    return map.CheckBox(*placed, vehicle);
  }
  if (tilts_too_far(*ground)) return PoseCheck::kTiltsTooFar;
  return map.CheckBox(*ground, vehicle);
}

}  // namespace ovpc::planner
