// The closed loop: the simulator and the robot's Navigator stepped together in simulated time, the
// Referee scoring the run from the truth and the Recorder keeping what a user looks at.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/scenarios/scenario.h"

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
  navigation::NavigatorStats navigator;  ///< the navigator's counters and stage timings, as it kept them
  std::size_t collision_steps = 0;
  std::vector<std::string> collisions;  ///< first contacts: time, vehicle geom, world geom
  std::vector<TrajectorySample> trajectory;
  std::vector<PlanRecord> plan_log;
  std::vector<navigation::CycleRecord> cycles;  ///< the navigator's map-and-plan cycles
  std::vector<MapPoint> map_points;     ///< the maps' points over the run (subsampled), world frame
  std::vector<std::string> files;       ///< files written (mesh snapshots, frames)
  StageStats physics_lidar;
  std::string map_backend;  ///< the map backend's name ("ovpc", "octomap", "elevation", a plug-in's)
};

struct RunOptions {
  /// Plug-ins for the robot's stack, made for each run from its effective configuration: a user's
  /// own map backend, planner or follower. Unset, or a null plug-in: the navigator's default, but
  /// for the map backend, which is then the one the scenario's `navigator.map` names.
  std::function<navigation::Navigator::Plugins(const navigation::Navigator::Config&)> make_plugins;
  std::string out_dir;    ///< mesh snapshots and frames go here ("" writes none)
  bool frames = false;    ///< rendered chase-camera PNG frames (needs EGL)
  double frame_period_s = 0.5;
  bool progress = false;  ///< a progress line on stderr
  /// 2: the navigator's map-and-plan cycles run on a thread of their own when the configuration
  /// has a latency (navigator.latency_s > 0); the trajectory is the same with 1.
  int threads = 1;
};

/// The navigator's configuration for a run: the scenario's, with the planner seeded from `seed` and
/// the geometry derived from its vehicle model (what result.json records).
navigation::Navigator::Config NavigatorConfigFor(const Scenario& scenario, std::uint64_t seed);

/// Runs the scenario with `seed` feeding every random source (LiDAR noise and faults, odometry,
/// planner). The same scenario and seed give a bit-identical trajectory on the same machine.
/// @throws std::invalid_argument for an invalid scenario, std::runtime_error if the simulator fails.
RunResult RunClosedLoop(const Scenario& scenario, std::uint64_t seed, const RunOptions& options);

}  // namespace ovpc::scenarios
