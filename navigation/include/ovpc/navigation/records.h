// What the Navigator records of its work: stage timings, each planner call, each map-and-plan
// cycle and the counters over a run. The testbed keeps these as they are (scenarios/closed_loop.h).
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/planner/planning_map.h"

namespace ovpc::navigation {

/// Wall-clock statistics of one stage, milliseconds per call (for reports; nothing depends on them).
struct StageStats {
  std::size_t calls = 0;
  double mean_ms = 0.0;
  double median_ms = 0.0;
  double p90_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
  double total_ms = 0.0;
};

/// Collects wall-clock samples of a stage.
class StageTimer {
 public:
  void Add(double ms) { samples_.push_back(ms); }
  StageStats Stats() const;

 private:
  std::vector<double> samples_;
};

/// One planner call (a row of plans.csv): the trigger, where the vehicle and the local goal were (in
/// that cycle's map frame L) and how the search went.
struct PlanAttempt {
  double time_s = 0.0;
  std::string reason;                ///< the re-planning trigger (planner::ReplanReasonName)
  double blocked_at_m = 0.0;         ///< path blocked: straight-line distance to the first invalid pose
  std::string blocked_by;            ///< path blocked: the check that failed there (planner::PoseCheckName)
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();  ///< the vehicle in the cycle's map frame
  planner::Pose2 vehicle_L;
  bool has_goal = false;             ///< false: no local goal qualified ("no_local_goal")
  planner::Pose2 goal_L;
  double goal_progress_m = 0.0;      ///< route progress of the local goal
  bool goal_is_look = false;         ///< the goal is a place to look from: seen ground ends just past it
  std::string outcome;               ///< "found", "no_path", "start_invalid:collision", "no_local_goal", ...
  unsigned iterations = 0;
  std::array<std::size_t, planner::kNumPoseChecks> state_checks{};  ///< by planner::PoseCheck
};

/// One map-and-plan cycle.
struct CycleRecord {
  double time_s = 0.0;
  std::size_t cloud_points = 0;      ///< prepared points handed to the map backend
  bool map_ok = false;
  std::string trigger;               ///< planner::ReplanReasonName; "" when the map failed or nothing triggered
  std::string outcome;               ///< the last attempt's outcome, "" if no plan was made
  double prepare_ms = 0.0, map_ms = 0.0, plan_ms = 0.0;  ///< wall clock
  /// CPU time of the thread that ran the cycle (the whole cycle runs on one thread): unlike the wall
  /// clock it holds when other work shares the machine.
  double prepare_cpu_ms = 0.0, map_cpu_ms = 0.0, plan_cpu_ms = 0.0;
};

/// Counters over a run.
struct NavigatorStats {
  std::size_t map_updates = 0;
  std::size_t map_failures = 0;      ///< updates that gave no map
  std::size_t plans = 0;             ///< planner calls
  std::size_t replans_found = 0;     ///< plans that gave a new path
  std::map<std::string, std::size_t> plan_outcomes;
  StageStats buffer, mapper, planner, controller;
  /// The map backend's update per stage (MapBackend::StageTimes), in the backend's order.
  std::vector<std::pair<std::string, StageStats>> map_stages;
};

}  // namespace ovpc::navigation
