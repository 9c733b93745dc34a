// When to plan again (paper: the path collides after a map update, the goal is too close, or 1 s of
// time passed). A pure function of simulated time and state; no clock is read.
#pragma once

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
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

struct ReplanInputs {
  double now_s = 0.0;                  ///< simulated time
  std::optional<double> last_plan_s;   ///< simulated time of the last plan, nothing if none
  bool has_path = false;
  bool path_blocked = false;           ///< e.g. LocalPlanner::FirstInvalidPose found a pose
  double distance_to_goal_m = 0.0;     ///< vehicle to the current local goal
  bool goal_is_route_end = false;      ///< the local goal is the end of the route
};

/// The first reason that applies, in the order of the enum; kNone if the current path stands.
ReplanReason CheckReplan(const ReplanConfig& config, const ReplanInputs& inputs);

}  // namespace ovpc::planner
