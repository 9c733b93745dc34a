#include "ovpc/scenarios/run_result.h"

#include <cmath>

namespace ovpc::scenarios {
namespace {

// x, y and heading of a planar pose of frame L in the world frame.
Eigen::Vector3d ToWorld(const Eigen::Isometry3d& T_W_L, const planner::Pose2& p) {
  const Vec3 p_W = T_W_L * Vec3(p.x_m, p.y_m, 0.0);
  const Vec3 x_axis = T_W_L.linear() * Vec3(std::cos(p.yaw_rad), std::sin(p.yaw_rad), 0.0);
  return Eigen::Vector3d(p_W.x(), p_W.y(), std::atan2(x_axis.y(), x_axis.x()));
}

}  // namespace

Eigen::Vector3d PlanRecord::VehicleW() const { return ToWorld(T_W_L, attempt.vehicle_L); }
Eigen::Vector3d PlanRecord::GoalW() const { return ToWorld(T_W_L, attempt.goal_L); }

}  // namespace ovpc::scenarios
