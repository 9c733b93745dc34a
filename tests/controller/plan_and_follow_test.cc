// The planner's paths followed by pure pursuit on the bicycle model, on the planner's test scenes.
#include <cmath>

#include <gtest/gtest.h>

#include "../planner/planning_scenes.h"
#include "follow_support.h"
#include "ovpc/planner/local_planner.h"

namespace ovpc::controller {
namespace {

using namespace testing;  // NOLINT: the support helpers

struct Followed {
  std::vector<Step> log;
  Path path;
};

Followed PlanAndFollow(const ovpc::testing::PlanningScene& scene, const planner::Pose2& start,
                       const planner::Pose2& goal) {
  const planner::LocalPlanner planner(planner::LocalPlanner::Config{});
  const planner::PlanResult plan = planner.Plan(*scene.map, start, goal);
  EXPECT_TRUE(plan.found()) << planner::PlanStatusName(plan.status);
  BicycleModel::State state;
  state.pose = start;
  return {Follow(plan.path, state, 120.0), plan.path};
}

TEST(PlanAndFollowTest, AroundThePostsWithoutTouchingThem) {
  const ovpc::testing::PlanningScene scene = ovpc::testing::BuildScene(ovpc::testing::PostsScene());
  const Followed run = PlanAndFollow(scene, scene.spec.start, scene.spec.goal);
  ASSERT_TRUE(run.log.back().command.done);
  const planner::VehicleBox vehicle;
  for (const Step& s : run.log) {
    // Every post stays outside the vehicle's footprint (no margin) along the driven trajectory.
    const planner::Pose2& p = s.state.pose;
    for (const ovpc::testing::Post& post : scene.spec.posts) {
      const double dx = post.x - p.x_m, dy = post.y - p.y_m;
      const double x = std::cos(p.yaw_rad) * dx + std::sin(p.yaw_rad) * dy - vehicle.centre_ahead_m;
      const double y = -std::sin(p.yaw_rad) * dx + std::cos(p.yaw_rad) * dy;
      ASSERT_FALSE(std::abs(x) <= 0.5 * vehicle.length_m + post.radius &&
                   std::abs(y) <= 0.5 * vehicle.width_m + post.radius)
          << "post at (" << post.x << ", " << post.y << ") hit at t = " << s.t_s;
    }
    ASSERT_LT(DistanceToPolyline(run.path.Poses(), Position(s.state)), 0.15) << "t = " << s.t_s;
  }
  EXPECT_LT((Position(run.log.back().state) - Eigen::Vector2d(scene.spec.goal.x_m, scene.spec.goal.y_m)).norm(), 0.3);
}

TEST(PlanAndFollowTest, ThroughCuspsToASidewaysGoal) {
  const ovpc::testing::PlanningScene scene = ovpc::testing::BuildScene(ovpc::testing::FlatScene());
  const planner::Pose2 start{-3.0, 0.0, 0.0}, goal{-3.0, 2.0, 0.0};
  const Followed run = PlanAndFollow(scene, start, goal);
  ASSERT_GE(run.path.NumCusps(), 1);
  ASSERT_TRUE(run.log.back().command.done);
  bool reversed = false;
  for (const Step& s : run.log) reversed |= s.state.speed_mps < -0.1;
  EXPECT_TRUE(reversed);
  EXPECT_LT((Position(run.log.back().state) - Eigen::Vector2d(goal.x_m, goal.y_m)).norm(), 0.3);
  EXPECT_LT(std::abs(std::remainder(run.log.back().state.pose.yaw_rad - goal.yaw_rad, 2 * kPi)), 0.15);
}

}  // namespace
}  // namespace ovpc::controller
