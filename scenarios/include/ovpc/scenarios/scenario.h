// A scenario: the world, the vehicle's start and route, faults, parameter overrides and the success
// criteria of one closed-loop run. Filled from YAML by LoadScenario (scenario_yaml.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ovpc/controller/pure_pursuit.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/planner/local_goal.h"
#include "ovpc/planner/local_planner.h"
#include "ovpc/planner/replan.h"
#include "ovpc/planner/vertex_cloud_map.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::scenarios {

/// An axis-aligned rectangle in the world frame the vehicle must never enter (any part of its
/// footprint), e.g. the ground under a low roof.
struct Region {
  std::string name;
  Eigen::Vector2d min_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_m = Eigen::Vector2d::Zero();
};

/// Success criteria with expected values (CARLA ScenarioRunner style). Unset ones are not checked.
struct Criteria {
  std::optional<Eigen::Vector2d> goal_m;  ///< goal region centre, world frame
  double goal_radius_m = 2.0;
  bool no_collision = true;               ///< no contact of a non-wheel vehicle body with the world
  std::optional<double> max_roll_deg;
  std::optional<double> max_pitch_deg;
  std::optional<double> max_time_s;       ///< the goal must be reached by then
  std::optional<double> min_progress_m;   ///< distance driven along the route
  std::vector<Region> forbidden;
};

/// Rates of the loop, all in simulated time.
struct LoopConfig {
  double map_rate_hz = 5.0;         ///< OVPC map updates from the buffered cloud
  double control_rate_hz = 50.0;    ///< pure-pursuit commands
  double record_rate_hz = 10.0;     ///< trajectory rows
  double mesh_snapshot_period_s = 10.0;  ///< mesh_*.ply snapshots (0: none)
  /// The ground under the vehicle is never in view (the sensor sees no closer than about 1.1 m from
  /// the mast), yet the vehicle stands on it. When > 0, points on the vehicle's footprint plane,
  /// grown by this margin, are added to each map update's cloud from the odometry pose, so that the
  /// planner's start pose projects onto known ground. 0 disables.
  double footprint_prior_margin_m = 0.3;
  /// Local goal candidates tried per re-plan, best first, until one gives a path.
  int goal_candidates = 3;
  /// What the footprint prior does with measured ground (points below the planner's ground
  /// clearance) over the grown footprint. kReplace drops it and lays the grid everywhere: right on
  /// flat ground, but at a ramp's foot or crest the flat grid cuts off the measured slope and leaves a
  /// step. kFill keeps it and lays grid points only where no measured point lies within the grid's
  /// spacing, so the grid fills the sensor's blind zone and never sits next to a measured point.
  enum class PriorMode { kReplace, kFill };
  PriorMode footprint_prior_mode = PriorMode::kReplace;
  /// kFill only: a grid point with measured ground within this distance takes its height from that
  /// ground (inverse-distance mean), weighted by 1 - d/blend with d the distance to the nearest
  /// measured point, instead of sitting on the vehicle's plane. At a ramp's crest under the vehicle,
  /// seen on the way up, the plane of the pitched vehicle runs a few centimetres to decimetres off
  /// the measured slope; a flat grid there makes steep slivers. 0 disables.
  double footprint_prior_blend_m = 0.0;
  /// The planner takes the ground under the vehicle's footprint, grown by this margin, as support
  /// for the wheels (VertexCloudMap::Config::known_support): the vehicle stands on it, though the
  /// sensor never sees it. Without it, a map artefact under the vehicle (a non-traversable point
  /// where the footprint prior meets rough ground) can reject every start pose until the time limit.
  /// Negative disables.
  double known_support_margin_m = 0.3;
  /// A plan to the route's end may also arrive heading straight from the vehicle to it, not only
  /// along the route's last leg (the success criterion is a position; a few metres before the end, a
  /// vehicle beside the route otherwise needs a manoeuvre to line up).
  bool route_end_any_heading = true;
  /// When > 0, each map update first drops points within `isolated_point_reach_m` of the sensor
  /// that have no other point within this radius: LiDAR outliers that survive the voxel filter (two
  /// in one voxel) float alone in free space and block every path through them. It can also drop a
  /// far, thinly hit post until the vehicle is nearer, so it is off unless a scenario's sensor has
  /// outliers (the faults scenarios).
  double isolated_point_radius_m = 0.0;
  double isolated_point_reach_m = 12.0;
};

struct Scenario {
  std::string name;
  std::string description;
  std::string path;                 ///< the file it came from
  std::uint64_t seed = 1;           ///< default seed; `ovpc run --seed` overrides
  double time_limit_s = 60.0;
  sim::Simulator::Config sim;       ///< world, vehicle, start pose, sensor faults, odometry faults
  std::vector<Eigen::Vector2d> route_m;  ///< global route, world frame (= odometry frame at start)
  LoopConfig loop;
  PointCloudBuffer::Config buffer;
  OvpcMapper::Config mapper;
  planner::LocalPlanner::Config planner;
  planner::LocalGoalConfig local_goal;
  planner::ReplanConfig replan;
  planner::VertexCloudMap::Config map;
  controller::PurePursuit::Config controller;
  Criteria criteria;
  std::vector<std::string> labels;  ///< e.g. "long": kept out of the default suite

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

}  // namespace ovpc::scenarios
