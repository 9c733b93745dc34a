#include "ovpc/planner/replan.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ovpc::planner {

const char* ReplanReasonName(ReplanReason reason) {
  switch (reason) {
    case ReplanReason::kNone: return "none";
    case ReplanReason::kNoPath: return "no path";
    case ReplanReason::kPathBlocked: return "path blocked";
    case ReplanReason::kGoalTooClose: return "goal too close";
    case ReplanReason::kPeriodElapsed: return "period elapsed";
  }
  return "unknown";
}

void Replanning::Config::Validate() const {
  if (!(period_s > 0.0) || !std::isfinite(period_s)) {
    throw std::invalid_argument("Replanning::Config: period_s must be > 0, got " + std::to_string(period_s));
  }
  if (!(goal_too_close_m >= 0.0) || !std::isfinite(goal_too_close_m)) {
    throw std::invalid_argument("Replanning::Config: goal_too_close_m must be >= 0, got " + std::to_string(goal_too_close_m));
  }
  if (blocked_confirmations < 1) {
    throw std::invalid_argument("Replanning::Config: blocked_confirmations must be >= 1, got " +
                                std::to_string(blocked_confirmations));
  }
  if (!(unseen_block_near_m >= 0.0) || !std::isfinite(unseen_block_near_m)) {
    throw std::invalid_argument("Replanning::Config: unseen_block_near_m must be >= 0, got " +
                                std::to_string(unseen_block_near_m));
  }
  if (!(blocked_near_m >= 0.0) || !std::isfinite(blocked_near_m)) {
    throw std::invalid_argument("Replanning::Config: blocked_near_m must be >= 0, got " + std::to_string(blocked_near_m));
  }
}

ReplanReason CheckReplan(const Replanning::Config& config, const ReplanInputs& inputs) {
  if (!inputs.has_path || !inputs.last_plan_s) return ReplanReason::kNoPath;
  const bool far_unseen = config.unseen_block_near_m > 0.0 && inputs.blocked_by_unseen_ground &&
                          inputs.blocked_distance_m >= config.unseen_block_near_m;
  if (inputs.path_blocked && !far_unseen &&
      (std::max(1, inputs.blocked_updates) >= config.blocked_confirmations ||
       inputs.blocked_distance_m < config.blocked_near_m)) {
    return ReplanReason::kPathBlocked;
  }
  if (!inputs.goal_is_route_end && !inputs.goal_is_look && inputs.distance_to_goal_m < config.goal_too_close_m) {
    return ReplanReason::kGoalTooClose;
  }
  if (inputs.now_s - *inputs.last_plan_s >= config.period_s) return ReplanReason::kPeriodElapsed;
  return ReplanReason::kNone;
}

}  // namespace ovpc::planner
