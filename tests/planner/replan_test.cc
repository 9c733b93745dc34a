#include "ovpc/planner/replan.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace ovpc::planner {
namespace {

ReplanInputs Standing(double now_s) {
  ReplanInputs in;
  in.now_s = now_s;
  in.last_plan_s = 10.0;
  in.has_path = true;
  in.distance_to_goal_m = 6.0;
  return in;
}

TEST(ReplanTest, EachTriggerOfThePaper) {
  const Replanning::Config config;  // 1 s, 2 m
  EXPECT_EQ(CheckReplan(config, Standing(10.5)), ReplanReason::kNone);
  // (iii) one second of simulated time.
  EXPECT_EQ(CheckReplan(config, Standing(10.999)), ReplanReason::kNone);
  EXPECT_EQ(CheckReplan(config, Standing(11.0)), ReplanReason::kPeriodElapsed);
  // (i) the path collides after a map update, whatever the time.
  ReplanInputs blocked = Standing(10.1);
  blocked.path_blocked = true;
  EXPECT_EQ(CheckReplan(config, blocked), ReplanReason::kPathBlocked);
  // (ii) the goal is too close, unless it is the end of the route.
  ReplanInputs close = Standing(10.1);
  close.distance_to_goal_m = 1.5;
  EXPECT_EQ(CheckReplan(config, close), ReplanReason::kGoalTooClose);
  close.goal_is_route_end = true;
  EXPECT_EQ(CheckReplan(config, close), ReplanReason::kNone);
  // No path yet, or the last attempt failed.
  ReplanInputs none = Standing(10.1);
  none.has_path = false;
  EXPECT_EQ(CheckReplan(config, none), ReplanReason::kNoPath);
  none = Standing(10.1);
  none.last_plan_s.reset();
  EXPECT_EQ(CheckReplan(config, none), ReplanReason::kNoPath);
}

TEST(ReplanTest, ReasonsComeInTheOrderOfTheEnum) {
  ReplanInputs all = Standing(20.0);
  all.path_blocked = true;
  all.distance_to_goal_m = 0.5;
  EXPECT_EQ(CheckReplan(Replanning::Config{}, all), ReplanReason::kPathBlocked);
  all.path_blocked = false;
  EXPECT_EQ(CheckReplan(Replanning::Config{}, all), ReplanReason::kGoalTooClose);
  EXPECT_STREQ(ReplanReasonName(ReplanReason::kPeriodElapsed), "period elapsed");
}

TEST(ReplanTest, AFarBlockMustPersistANearOneActsAtOnce) {
  Replanning::Config config;
  config.blocked_confirmations = 2;
  config.blocked_near_m = 3.0;
  ReplanInputs far = Standing(10.1);
  far.path_blocked = true;
  far.blocked_distance_m = 7.0;
  far.blocked_updates = 1;
  EXPECT_EQ(CheckReplan(config, far), ReplanReason::kNone);  // a flicker, perhaps
  far.blocked_updates = 2;
  EXPECT_EQ(CheckReplan(config, far), ReplanReason::kPathBlocked);  // still there at the next update
  ReplanInputs near = far;
  near.blocked_updates = 1;
  near.blocked_distance_m = 2.5;
  EXPECT_EQ(CheckReplan(config, near), ReplanReason::kPathBlocked);
  // The other triggers do not wait: an unconfirmed far block still lets the period elapse.
  far.blocked_updates = 1;
  far.now_s = 11.2;
  EXPECT_EQ(CheckReplan(config, far), ReplanReason::kPeriodElapsed);
  // The paper's rule (the default): the first update that finds the path blocked.
  far.now_s = 10.1;
  EXPECT_EQ(CheckReplan(Replanning::Config{}, far), ReplanReason::kPathBlocked);
}

TEST(ReplanTest, AFarBlockByUnseenGroundWaitsUntilItIsNear) {
  Replanning::Config config;
  config.unseen_block_near_m = 3.0;
  ReplanInputs in = Standing(10.2);
  in.path_blocked = true;
  in.blocked_updates = 4;
  in.blocked_distance_m = 6.0;
  in.blocked_by_unseen_ground = true;
  EXPECT_EQ(CheckReplan(config, in), ReplanReason::kNone);  // drive on: the ground fills in
  in.blocked_distance_m = 2.9;
  EXPECT_EQ(CheckReplan(config, in), ReplanReason::kPathBlocked);
  // An obstacle acts at any distance; so does unseen ground under the paper's rule.
  in.blocked_distance_m = 6.0;
  in.blocked_by_unseen_ground = false;
  EXPECT_EQ(CheckReplan(config, in), ReplanReason::kPathBlocked);
  in.blocked_by_unseen_ground = true;
  EXPECT_EQ(CheckReplan(Replanning::Config{}, in), ReplanReason::kPathBlocked);
  // The period still elapses.
  in.now_s = 11.5;
  EXPECT_EQ(CheckReplan(config, in), ReplanReason::kPeriodElapsed);
  config.unseen_block_near_m = -1.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

TEST(ReplanTest, ConfigIsValidated) {
  Replanning::Config config;
  config.period_s = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = Replanning::Config{};
  config.goal_too_close_m = -1.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = Replanning::Config{};
  config.blocked_confirmations = 0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = Replanning::Config{};
  config.blocked_near_m = -0.5;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  EXPECT_NO_THROW(Replanning::Config{}.Validate());
}

}  // namespace
}  // namespace ovpc::planner
