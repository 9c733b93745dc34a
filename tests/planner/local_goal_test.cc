#include "ovpc/planner/local_goal.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "planning_scenes.h"

namespace ovpc::planner {
namespace {

using testing::BuildScene;
using testing::PlanningScene;

const PlanningScene& Flat() {
  static const PlanningScene scene = BuildScene(testing::FlatScene());
  return scene;
}

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

TEST(LocalGoalTest, FarthestRoutePointInsideTheMap) {
  // The route runs along y = 0 far beyond the map's edge at x = 11.
  const std::vector<Eigen::Vector2d> route = {{-20.0, 0.0}, {0.0, 0.0}, {40.0, 0.0}};
  const VehicleBox vehicle;
  const auto goal = SelectLocalGoal(*Flat().map, vehicle, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, LocalGoalConfig{});
  ASSERT_TRUE(goal.has_value());
  EXPECT_FALSE(goal->is_route_end);
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(goal->pose.yaw_rad, 0.0, 1e-12);
  EXPECT_EQ(CheckPose(*Flat().map, vehicle, goal->pose), PoseCheck::kValid);
  // One step farther along the route the vehicle would no longer fit.
  EXPECT_NE(CheckPose(*Flat().map, vehicle, Pose2{goal->pose.x_m + 0.25, 0.0, 0.0}), PoseCheck::kValid);
  EXPECT_GT(goal->pose.x_m, 7.0);
  EXPECT_NEAR(goal->route_progress_m, goal->pose.x_m + 20.0, 1e-9);

  // Only requiring known, traversable ground lets the goal go up to the map's rim.
  LocalGoalConfig loose;
  loose.require_vehicle_fit = false;
  const auto rim = SelectLocalGoal(*Flat().map, vehicle, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, loose);
  ASSERT_TRUE(rim.has_value());
  EXPECT_GT(rim->pose.x_m, goal->pose.x_m);
  EXPECT_TRUE(Flat().map->IsKnownFree(rim->pose.x_m, rim->pose.y_m));
}

TEST(LocalGoalTest, RouteInTheOdometryFrameAndHeadingAlongTheRoute) {
  // The map frame L sits at (100, 50) in the odometry frame O (axes shared, as the mapper's frame).
  Eigen::Isometry3d T_L_O = Eigen::Isometry3d::Identity();
  T_L_O.translation() = Vec3(-100.0, -50.0, 0.0);
  // In L: from (-7, -3) north to (-7, 3), then east to (5, 3), then the route ends.
  const std::vector<Eigen::Vector2d> route_O = {{93.0, 47.0}, {93.0, 53.0}, {105.0, 53.0}};
  const auto goal =
      SelectLocalGoal(*Flat().map, VehicleBox{}, route_O, T_L_O, Pose2{-7.0, -3.0, kPi / 2}, LocalGoalConfig{});
  ASSERT_TRUE(goal.has_value());
  EXPECT_TRUE(goal->is_route_end);
  EXPECT_NEAR(goal->pose.x_m, 5.0, 1e-9);
  EXPECT_NEAR(goal->pose.y_m, 3.0, 1e-9);
  EXPECT_NEAR(goal->pose.yaw_rad, 0.0, 1e-12);
  EXPECT_NEAR(goal->route_progress_m, 18.0, 1e-9);
}

TEST(LocalGoalTest, AtLeastTheMinimumDistanceAheadUnlessItIsTheEnd) {
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {-2.0, 0.0}, {20.0, 0.0}};
  LocalGoalConfig config;
  config.min_distance_m = 30.0;  // no point of the route inside the map is that far
  EXPECT_FALSE(SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config));
  // The route's end qualifies at any distance.
  const std::vector<Eigen::Vector2d> short_route = {{-7.0, 0.0}, {-5.0, 0.0}};
  const auto end = SelectLocalGoal(*Flat().map, VehicleBox{}, short_route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(end.has_value());
  EXPECT_TRUE(end->is_route_end);
  EXPECT_NEAR(end->pose.x_m, -5.0, 1e-12);
}

TEST(LocalGoalTest, NothingBehindTheVehicle) {
  // The vehicle is at the corner of the route; what is left of the route leaves the map within 9 m.
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {8.5, 0.0}, {8.5, 40.0}};
  LocalGoalConfig config;
  config.min_distance_m = 10.0;  // the route's start, 15 m behind, would qualify
  EXPECT_FALSE(SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{8.0, 0.0, 0.0}, config));
  // Closer goals ahead are found, on the second leg.
  config.min_distance_m = 4.0;
  const auto goal = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{8.0, 0.0, 0.0}, config);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.x_m, 8.5, 1e-9);
  EXPECT_GE(goal->pose.y_m, 4.0);
  EXPECT_NEAR(goal->pose.yaw_rad, kPi / 2, 1e-12);

  LocalGoalConfig bad;
  bad.step_m = 0.0;
  EXPECT_THROW(SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{}, bad), std::invalid_argument);
  EXPECT_FALSE(SelectLocalGoal(*Flat().map, VehicleBox{}, {}, kIdentity, Pose2{}, LocalGoalConfig{}));
}

TEST(LocalGoalTest, KeepsAPreviousGoalThatStillQualifiesUnlessTheNewOneIsMuchFurther) {
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {20.0, 0.0}};
  LocalGoalConfig config;
  const auto fresh = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(fresh.has_value());
  // A previous goal beside the route, 1 m short of the new one.
  LocalGoal previous{Pose2{fresh->pose.x_m - 1.0, 1.5, 0.0}, fresh->route_progress_m - 1.0, false};
  config.keep_previous_within_m = 0.0;  // off: the new goal
  auto goal = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  config.keep_previous_within_m = 1.5;  // the new goal is not 1.5 m further: keep the previous one
  goal = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 1.5, 1e-12);
  EXPECT_NEAR(goal->route_progress_m, previous.route_progress_m, 1e-12);
  config.keep_previous_within_m = 0.5;  // it is more than 0.5 m further: take it
  goal = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  // A previous goal that no longer qualifies (outside the map) is dropped.
  config.keep_previous_within_m = 100.0;
  const LocalGoal gone{Pose2{60.0, 0.0, 0.0}, 67.0, false};
  goal = SelectLocalGoal(*Flat().map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, gone);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.x_m, fresh->pose.x_m, 1e-12);
}

}  // namespace
}  // namespace ovpc::planner
