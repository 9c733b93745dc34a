#include "ovpc/planner/planning_map.h"

#include <cmath>
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

void VehicleBox::Validate() const {
  RequirePositive(length_m, "length_m");
  RequirePositive(width_m, "width_m");
  RequirePositive(height_m, "height_m");
  RequireNonNegative(margin_m, "margin_m");
  RequireNonNegative(ground_clearance_m, "ground_clearance_m");
  RequireNonNegative(footprint_depth_m, "footprint_depth_m");
  RequirePositive(wheelbase_m, "wheelbase_m");
  RequirePositive(track_m, "track_m");
  RequirePositive(wheel_support_m, "wheel_support_m");
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
  }
  return "unknown";
}

PoseCheck CheckPose(const PlanningMap& map, const VehicleBox& vehicle, const Pose2& pose) {
  if (!std::isfinite(pose.x_m) || !std::isfinite(pose.y_m) || !std::isfinite(pose.yaw_rad) ||
      !map.Bounds().Contains(pose.x_m, pose.y_m)) {
    return PoseCheck::kOutsideMap;
  }
  const std::optional<GroundPose> ground = map.Project(pose);
  if (!ground) return PoseCheck::kOutsideMap;
  if (!ground->traversable) return PoseCheck::kNotTraversable;
  return map.CheckBox(*ground, vehicle);
}

}  // namespace ovpc::planner
