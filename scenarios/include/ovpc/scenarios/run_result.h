// What a closed-loop run gives: the trajectory, the criteria, the planner's calls and the
// navigator's records. Below the closed loop, the Referee, the Recorder, the reports and the
// family rules, which all use it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/core/types.h"
#include "ovpc/navigation/records.h"

namespace ovpc::scenarios {

struct TrajectorySample {
  double time_s = 0.0;
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();  ///< true pose
  Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();  ///< odometry pose (what the robot knows)
  double speed_mps = 0.0;          ///< true forward speed
  double cmd_steering_rad = 0.0;
  double cmd_speed_mps = 0.0;
};

struct CriterionResult {
  std::string name;
  std::string expected;
  std::string actual;
  bool passed = false;
};

using navigation::StageStats;

/// A point of the planner's map, in the world frame (for pictures), with its flag.
struct MapPoint {
  Vec3 position_W;
  bool traversable = false;
};

/// One planner call of a run, for plans.csv: the navigator's attempt as it was, and where that
/// cycle's map frame L lay in the world (placed by the truth when the cycle was recorded).
struct PlanRecord {
  navigation::PlanAttempt attempt;
  Eigen::Isometry3d T_W_L = Eigen::Isometry3d::Identity();
  /// The vehicle and the local goal in the world frame: x, y, yaw.
  Eigen::Vector3d VehicleW() const;
  Eigen::Vector3d GoalW() const;
};

struct RunResult {
  std::string scenario;
  std::uint64_t seed = 0;
  bool passed = false;
  std::vector<CriterionResult> criteria;
  std::string end_reason;          ///< "goal reached", "time limit", ...
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  double real_time_factor = 0.0;   ///< simulated seconds per wall-clock second
  double distance_m = 0.0;         ///< driven, true path length
  double route_progress_m = 0.0;   ///< farthest point reached along the route
  double route_length_m = 0.0;
  std::vector<Eigen::Vector2d> route_m;  ///< the scenario's route (world frame), for the diagnosis
  navigation::NavigatorStats navigator;  ///< the navigator's counters and stage timings, as it kept them
  std::size_t collision_steps = 0;
  std::vector<std::string> collisions;  ///< first contacts: time, vehicle geom, world geom
  std::vector<TrajectorySample> trajectory;
  std::vector<PlanRecord> plan_log;
  std::vector<navigation::CycleRecord> cycles;  ///< the navigator's map-and-plan cycles
  std::vector<MapPoint> map_points;     ///< the maps' points over the run (subsampled), world frame
  /// The last map's points within kLastMapRadiusM of the vehicle, world frame: what the robot saw
  /// where the run ended (the diagnosis reads it).
  std::vector<MapPoint> last_map_points;
  static constexpr double kLastMapRadiusM = 10.0;
  std::vector<std::string> files;       ///< files written (mesh snapshots, frames)
  StageStats physics_lidar;
  std::string map_backend;  ///< the map backend's name ("ovpc", "octomap", "elevation", a plug-in's)
};

}  // namespace ovpc::scenarios
