// When to plan again (paper: the path collides after a map update, the goal is too close, or 1 s of
// time passed). A pure function of simulated time and state; no clock is read.
#pragma once

#include <limits>
#include <optional>

namespace ovpc::planner {

enum class ReplanReason {
  kNone,
  kNoPath,         ///< there is no current path (first plan, or the last attempt failed)
  kPathBlocked,    ///< the rest of the current path fails the validity check on the newest map
  kGoalTooClose,   ///< the local goal is closer than ReplanConfig::goal_too_close_m (not the route end)
  kPeriodElapsed,  ///< ReplanConfig::period_s of simulated time since the last plan
};
const char* ReplanReasonName(ReplanReason reason);

struct ReplanConfig {
  double period_s = 1.0;
  double goal_too_close_m = 2.0;
  /// A blocked pose farther ahead of the vehicle than this (straight line) is not yet a reason to
  /// plan again; the vehicle drives on and the path is checked again on each map update. Far poses
  /// are where the map is sparse and flickers from one update to the next, and a new random path
  /// each time undoes the last one. Infinite: any blocked pose (the paper's rule).
  double blocked_horizon_m = std::numeric_limits<double>::infinity();
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

struct ReplanInputs {
  double now_s = 0.0;                  ///< simulated time
  std::optional<double> last_plan_s;   ///< simulated time of the last plan, nothing if none
  bool has_path = false;
  bool path_blocked = false;           ///< e.g. LocalPlanner::FirstInvalidPose found a pose
  double blocked_distance_m = 0.0;     ///< vehicle to that pose (straight line)
  double distance_to_goal_m = 0.0;     ///< vehicle to the current local goal
  bool goal_is_route_end = false;      ///< the local goal is the end of the route
};

/// The first reason that applies, in the order of the enum; kNone if the current path stands.
ReplanReason CheckReplan(const ReplanConfig& config, const ReplanInputs& inputs);

}  // namespace ovpc::planner
