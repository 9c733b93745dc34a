// When to plan again (paper: the path collides after a map update, the goal is too close, or 1 s of
// time passed). A pure function of simulated time and state; no clock is read.
#pragma once

#include <optional>

#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

enum class ReplanReason {
  kNone,
  kNoPath,         ///< there is no current path (first plan, or the last attempt failed)
  kPathBlocked,    ///< the rest of the current path fails the validity check on the newest map
  kGoalTooClose,   ///< the local goal is closer than Replanning::Config::goal_too_close_m (not the route end)
  kPeriodElapsed,  ///< Replanning::Config::period_s of simulated time since the last plan
};
const char* ReplanReasonName(ReplanReason reason);

/// The re-planning triggers (CheckReplan).
struct Replanning {
  struct Config {
    double period_s = 1.0;
    double goal_too_close_m = 2.0;
    /// A blocked path triggers a re-plan once it has been blocked after this many map updates in a
    /// row (1: after every update that finds it blocked, the paper's rule), unless the first blocked
    /// pose is nearer than `blocked_near_m`. Noise flickers single poses far along the path in and out
    /// of collision; waiting for a second update filters that without delaying near blocks.
    int blocked_confirmations = 1;
    double blocked_near_m = 0.0;
    /// A path blocked only by ground not yet seen well enough to stand a wheel on (the first blocked
    /// pose fails a ground check (IsGroundCheck) or kOutsideMap, not as an obstacle) triggers a re-plan only
    /// once that pose is nearer than this: far ahead the ground is sparse and fills in as the vehicle
    /// comes closer, and a new path at every map update, each starting another way, rocks the vehicle
    /// on the spot. Up to the block the path is still valid. 0: every block triggers (the paper's
    /// rule).
    double unseen_block_near_m = 0.0;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, period_s), "s", "paper: a re-plan each second");
      v.Field(OVPC_FIELD(c, goal_too_close_m), "m", "paper: a goal this near triggers a re-plan");
      v.Field(OVPC_FIELD(c, blocked_confirmations), "updates", "a blocked path re-plans after this many; 1: paper");
      v.Field(OVPC_FIELD(c, blocked_near_m), "m", "a block this near re-plans at once");
      v.Field(OVPC_FIELD(c, unseen_block_near_m), "m", "a block by unseen ground re-plans this near; 0: paper");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

struct ReplanInputs {
  double now_s = 0.0;                  ///< simulated time
  std::optional<double> last_plan_s;   ///< simulated time of the last plan, nothing if none
  bool has_path = false;
  bool path_blocked = false;           ///< e.g. LocalPlanner::FirstInvalidPose found a pose
  int blocked_updates = 0;             ///< map updates in a row, this one included, that found it blocked
  double blocked_distance_m = 0.0;     ///< vehicle to the first blocked pose
  bool blocked_by_unseen_ground = false;  ///< that pose fails for want of seen ground, not an obstacle
  double distance_to_goal_m = 0.0;     ///< vehicle to the current local goal
  bool goal_is_route_end = false;      ///< the local goal is the end of the route
  bool goal_is_look = false;           ///< the local goal is a place to look from (LocalGoal::is_look)
};

/// The first reason that applies, in the order of the enum; kNone if the current path stands.
ReplanReason CheckReplan(const Replanning::Config& config, const ReplanInputs& inputs);

}  // namespace ovpc::planner
