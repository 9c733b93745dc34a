// The referee: scores a run against the scenario's criteria from the truth (the simulator's poses
// and contacts), never from what the robot believes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/planner/route_tracker.h"
#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/scenario.h"
#include "ovpc/sim/gator.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::scenarios {

class Referee {
 public:
  /// @param scenario must outlive the referee.
  /// @param T_W_B the true pose at the start.
  Referee(const Scenario& scenario, const sim::GatorParams& vehicle, const Eigen::Isometry3d& T_W_B);

  /// Takes the truth after a physics step: distance, roll and pitch, route progress, body contacts
  /// and forbidden regions.
  void Observe(double time_s, const Eigen::Isometry3d& T_W_B, const std::vector<sim::BodyContact>& contacts);
  /// True once a wheel's contact point has left the terrain's extent (the terrain's edge is a drop:
  /// beyond it the vehicle falls).
  bool OffTerrain() const { return off_terrain_; }
  /// True (and the goal time kept) when the true pose is inside the goal region and the route has
  /// been followed up to the goal's place on it (a route that ends where it started, a lap, is not
  /// done at its start).
  bool GoalReached(double time_s, const Eigen::Isometry3d& T_W_B);
  /// The run ends at the route's end (scenarios without a goal region): that is its goal time.
  void RouteEndReached(double time_s) { goal_time_s_ = time_s; }

  /// Fills the criteria, `passed`, distance, route progress and collisions of `result`.
  void Score(RunResult* result) const;

 private:
  const Scenario& scenario_;
  sim::GatorParams vehicle_;
  Eigen::Vector3d last_position_;
  double distance_m_ = 0.0, max_roll_deg_ = 0.0, max_pitch_deg_ = 0.0;
  planner::RouteTracker route_;  ///< progress along the route in its order, from the truth
  double best_progress_m_ = 0.0;
  double goal_progress_m_ = 0.0;  ///< the goal's place on the route (its last nearest point)
  std::size_t collision_steps_ = 0;
  std::vector<std::string> collisions_;
  std::vector<bool> region_entered_;
  std::optional<double> goal_time_s_;
  bool off_terrain_ = false;
};

}  // namespace ovpc::scenarios
