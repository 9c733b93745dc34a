#include "ovpc/planner/local_goal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ovpc/planner/vertex_cloud_map.h"
#include "planning_scenes.h"

namespace ovpc::planner {
namespace {

using testing::BuildScene;
using testing::FlatMap;
using testing::FlatPlanningScene;
using testing::PlanningScene;


const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

TEST(LocalGoalTest, FarthestRoutePointInsideTheMap) {
  // The route runs along y = 0 far beyond the map's edge at x = 11.
  const std::vector<Eigen::Vector2d> route = {{-20.0, 0.0}, {0.0, 0.0}, {40.0, 0.0}};
  const VehicleBox vehicle;
  const auto goal = SelectLocalGoal(FlatMap(), vehicle, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, LocalGoalSelection::Config{});
  ASSERT_TRUE(goal.has_value());
  EXPECT_FALSE(goal->is_route_end);
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(goal->pose.yaw_rad, 0.0, 1e-12);
  EXPECT_EQ(CheckPose(FlatMap(), vehicle, goal->pose), PoseCheck::kValid);
  // One step farther along the route the vehicle would no longer fit.
  EXPECT_NE(CheckPose(FlatMap(), vehicle, Pose2{goal->pose.x_m + 0.25, 0.0, 0.0}), PoseCheck::kValid);
  EXPECT_GT(goal->pose.x_m, 7.0);
  EXPECT_NEAR(goal->route_progress_m, goal->pose.x_m + 20.0, 1e-9);

  // Only requiring known, traversable ground lets the goal go up to the map's rim.
  LocalGoalSelection::Config loose;
  loose.require_vehicle_fit = false;
  const auto rim = SelectLocalGoal(FlatMap(), vehicle, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, loose);
  ASSERT_TRUE(rim.has_value());
  EXPECT_GT(rim->pose.x_m, goal->pose.x_m);
  EXPECT_TRUE(FlatMap().IsKnownFree(rim->pose.x_m, rim->pose.y_m));
}

TEST(LocalGoalTest, RouteInTheOdometryFrameAndHeadingAlongTheRoute) {
  // The map frame L sits at (100, 50) in the odometry frame O (axes shared, as the mapper's frame).
  Eigen::Isometry3d T_L_O = Eigen::Isometry3d::Identity();
  T_L_O.translation() = Vec3(-100.0, -50.0, 0.0);
  // In L: from (-7, -3) north to (-7, 3), then east to (5, 3), then the route ends.
  const std::vector<Eigen::Vector2d> route_O = {{93.0, 47.0}, {93.0, 53.0}, {105.0, 53.0}};
  const auto goal =
      SelectLocalGoal(FlatMap(), VehicleBox{}, route_O, T_L_O, Pose2{-7.0, -3.0, kPi / 2}, LocalGoalSelection::Config{});
  ASSERT_TRUE(goal.has_value());
  EXPECT_TRUE(goal->is_route_end);
  EXPECT_NEAR(goal->pose.x_m, 5.0, 1e-9);
  EXPECT_NEAR(goal->pose.y_m, 3.0, 1e-9);
  EXPECT_NEAR(goal->pose.yaw_rad, 0.0, 1e-12);
  EXPECT_NEAR(goal->route_progress_m, 18.0, 1e-9);
}

TEST(LocalGoalTest, AtLeastTheMinimumDistanceAheadUnlessItIsTheEnd) {
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {-2.0, 0.0}, {20.0, 0.0}};
  LocalGoalSelection::Config config;
  config.min_distance_m = 30.0;  // no point of the route inside the map is that far
  EXPECT_FALSE(SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config));
  // The route's end qualifies at any distance.
  const std::vector<Eigen::Vector2d> short_route = {{-7.0, 0.0}, {-5.0, 0.0}};
  const auto end = SelectLocalGoal(FlatMap(), VehicleBox{}, short_route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(end.has_value());
  EXPECT_TRUE(end->is_route_end);
  EXPECT_NEAR(end->pose.x_m, -5.0, 1e-12);
}

TEST(LocalGoalTest, NothingBehindTheVehicle) {
  // The vehicle is at the corner of the route; what is left of the route leaves the map within 9 m.
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {8.5, 0.0}, {8.5, 40.0}};
  LocalGoalSelection::Config config;
  config.min_distance_m = 10.0;  // the route's start, 15 m behind, would qualify
  EXPECT_FALSE(SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{8.0, 0.0, 0.0}, config));
  // Closer goals ahead are found, on the second leg.
  config.min_distance_m = 4.0;
  const auto goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{8.0, 0.0, 0.0}, config);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.x_m, 8.5, 1e-9);
  EXPECT_GE(goal->pose.y_m, 4.0);
  EXPECT_NEAR(goal->pose.yaw_rad, kPi / 2, 1e-12);

  LocalGoalSelection::Config bad;
  bad.step_m = 0.0;
  EXPECT_THROW(SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{}, bad), std::invalid_argument);
  EXPECT_FALSE(SelectLocalGoal(FlatMap(), VehicleBox{}, {}, kIdentity, Pose2{}, LocalGoalSelection::Config{}));
}

TEST(LocalGoalTest, KeepsAPreviousGoalThatStillQualifiesUnlessTheNewOneIsMuchFurther) {
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {20.0, 0.0}};
  LocalGoalSelection::Config config;
  const auto fresh = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(fresh.has_value());
  // A previous goal 1.5 m beside the route, 1 m short of the new one: it scores 1 m of progress
  // less, 0.75 m of offset penalty less (0.5 per metre) and its small detour to the route's end less.
  LocalGoal previous{Pose2{fresh->pose.x_m - 1.0, 1.5, 0.0}, fresh->route_progress_m - 1.0, false, 1.5};
  const double remaining = 27.0 - previous.route_progress_m;
  const double behind = 1.0 + 0.75 + std::hypot(remaining, 1.5) - remaining;
  ASSERT_GT(behind, 1.75);
  ASSERT_LT(behind, 2.0);
  config.keep_previous_within_m = 0.0;  // off: the new goal
  auto goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  config.keep_previous_within_m = 2.0;  // the new goal does not score 2 m more: keep the previous one
  goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 1.5, 1e-12);
  EXPECT_NEAR(goal->route_progress_m, previous.route_progress_m, 1e-12);
  config.keep_previous_within_m = 1.5;  // 1 m further along the route, but it scores more than 1.5 m more: take it
  goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, previous);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  // A previous goal that no longer qualifies (outside the map) is dropped.
  config.keep_previous_within_m = 100.0;
  const LocalGoal gone{Pose2{60.0, 0.0, 0.0}, 67.0, false};
  goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, gone);
  ASSERT_TRUE(goal.has_value());
  EXPECT_NEAR(goal->pose.x_m, fresh->pose.x_m, 1e-12);
}

// Flat, traversable ground every 0.1 m over [-4, 12] x [-8, 8].
TraversabilityCloud FlatGround() {
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  for (int i = -40; i <= 120; ++i) {
    for (int j = -80; j <= 80; ++j) {
      points.emplace_back(0.1 * i, 0.1 * j, 0.0);
      normals.push_back(Vec3::UnitZ());
      traversable.push_back(1);
    }
  }
  return TraversabilityCloud(points, normals, traversable);
}

// Near the route's end, a goal 3 m beside the end has the end's route progress, but is not the end:
// once the end itself qualifies, it gives way to it, however sticky the previous goal is made.
TEST(LocalGoalTest, AGoalBesideTheRoutesEndGivesWayToTheEnd) {
  const VertexCloudMap map(FlatGround(), VertexCloudMap::Config{});
  const std::vector<Eigen::Vector2d> route = {{-3.0, 0.0}, {8.0, 0.0}};
  const Pose2 vehicle{2.0, -3.0, 0.0};
  LocalGoalSelection::Config config;
  config.min_distance_m = 2.5;
  config.lateral_offsets_m = {1.5, 3.0};
  config.keep_previous_within_m = 1.0;
  const LocalGoal beside{Pose2{8.0, -3.0, 0.0}, 11.0, false, -3.0};
  ASSERT_EQ(CheckPose(map, VehicleBox{}, beside.pose), PoseCheck::kValid);
  const auto goal = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, vehicle, config, beside);
  ASSERT_TRUE(goal.has_value());
  EXPECT_TRUE(goal->is_route_end);
  EXPECT_NEAR(goal->pose.x_m, 8.0, 1e-9);
  EXPECT_NEAR(goal->pose.y_m, 0.0, 1e-12);
  EXPECT_EQ(goal->lateral_offset_m, 0.0);
}

// Flat ground every 0.1 m over [-4, 12] x [-8, 8] and a wall 2 m high across y in [-3, 3] at x = 5
// with no ground behind it (|y| < 3.5): the route along y = 0 is blocked, the ground beside the wall
// is open.
VertexCloudMap WallAcrossTheRoute() {
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  for (int i = -40; i <= 120; ++i) {
    for (int j = -80; j <= 80; ++j) {
      if (i > 50 && std::abs(j) < 35) continue;  // hidden behind the wall
      points.emplace_back(0.1 * i, 0.1 * j, 0.0);
      normals.push_back(Vec3::UnitZ());
      traversable.push_back(1);
    }
  }
  for (int j = -30; j <= 30; ++j) {
    for (int k = 1; k <= 20; ++k) {
      points.emplace_back(5.0, 0.1 * j, 0.1 * k);
      normals.push_back(-Vec3::UnitX());
      traversable.push_back(0);
    }
  }
  return VertexCloudMap(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{});
}

TEST(LocalGoalTest, AWideOffsetWinsWhenItGetsMuchFurther) {
  const VertexCloudMap map = WallAcrossTheRoute();
  const std::vector<Eigen::Vector2d> route = {{-3.0, 0.0}, {30.0, 0.0}};
  LocalGoalSelection::Config config;
  config.min_distance_m = 2.0;
  config.lateral_offsets_m = {1.5, 4.5};
  // On the route and 1.5 m beside it the map ends at the wall; 4.5 m beside it the vehicle passes
  // the wall (box half width 0.85 m) and gets to the far end of the map.
  const Pose2 start{-3.0, 0.0, 0.0};
  const auto wide = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(wide.has_value());
  EXPECT_NEAR(wide->pose.y_m, 4.5, 1e-12);
  EXPECT_GT(wide->pose.x_m, 8.0);
  EXPECT_EQ(CheckPose(map, VehicleBox{}, wide->pose), PoseCheck::kValid);
  // On the route itself the goal is no further than just behind the wall, reached by projecting
  // onto the ground at the wall's foot.
  config.lateral_offsets_m.clear();
  const auto on_route = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(on_route.has_value());
  EXPECT_NEAR(on_route->pose.y_m, 0.0, 1e-12);
  EXPECT_LT(on_route->pose.x_m, 6.0);
  // With a heavy penalty per metre of offset the near offset wins after all.
  config.lateral_offsets_m = {1.5, 4.5};
  config.lateral_offset_penalty = 100.0;
  const auto near = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(near.has_value());
  EXPECT_NEAR(near->pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(near->pose.x_m, on_route->pose.x_m, 1e-12);
}

// 1.5 m before the route's end, with something in the box of the end pose itself (a bush 2.3 m past
// the end): the last metre of the route counts as its end, so the goal is on the route just short of
// it rather than beside the route at least min_distance_m away.
TEST(LocalGoalTest, TheLastMetreOfTheRouteStandsInForItsEnd) {
  const TraversabilityCloud ground = FlatGround();
  Points points = ground.points();
  std::vector<Vec3> normals = ground.normals();
  std::vector<std::uint8_t> traversable = ground.traversable();
  points.emplace_back(10.3, 0.0, 1.0);  // in the box of a pose at x = 8 (box to 10.4 m), not at 7.75
  normals.push_back(-Vec3::UnitX());
  traversable.push_back(0);
  const VertexCloudMap map(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{});
  const std::vector<Eigen::Vector2d> route = {{-3.0, 0.0}, {8.0, 0.0}};
  const Pose2 vehicle{6.5, 0.0, 0.0};
  ASSERT_EQ(CheckPose(map, VehicleBox{}, Pose2{8.0, 0.0, 0.0}), PoseCheck::kCollision);
  LocalGoalSelection::Config config;
  config.min_distance_m = 2.5;
  config.lateral_offsets_m = {1.5, 3.0};
  const auto beside = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, vehicle, config);
  ASSERT_TRUE(beside.has_value());
  EXPECT_GE(std::abs(beside->pose.y_m), 1.5);  // without the zone: a point beside the route
  config.end_zone_m = 1.0;
  const auto end = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, vehicle, config);
  ASSERT_TRUE(end.has_value());
  EXPECT_NEAR(end->pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(end->pose.x_m, 7.75, 1e-9);
  EXPECT_TRUE(end->is_route_end);
  config.end_zone_m = -1.0;
  EXPECT_THROW(SelectLocalGoal(map, VehicleBox{}, route, kIdentity, vehicle, config), std::invalid_argument);
}

TEST(LocalGoalTest, RouteProgressInAWindowIsNotFooledByLapsSideBySide) {
  // Out along y = 0, back along y = 4, out again along y = 2: 0-20, 24-44, 46-66 m of arc length.
  const std::vector<Eigen::Vector2d> route = {{0, 0}, {20, 0}, {20, 4}, {0, 4}, {0, 2}, {20, 2}};
  const Eigen::Vector2d p(10.0, 1.9);  // beside the first lap, on the third
  EXPECT_NEAR(RouteProgress(route, p), 56.0, 1e-9);  // closest of the whole route: the third lap
  EXPECT_NEAR(RouteProgress(route, p, 9.0, 5.0, 10.0), 10.0, 1e-9);  // tracked from 9 m: the first
  // The window clamps: a vehicle far ahead of its tracked progress advances to the window's end.
  EXPECT_NEAR(RouteProgress(route, Eigen::Vector2d(19.0, 0.0), 2.0, 5.0, 10.0), 12.0, 1e-9);
  EXPECT_NEAR(RouteProgress({{1.0, 1.0}}, p), 0.0, 1e-12);
}

TEST(LocalGoalTest, CandidatesEndWhereTheRouteLeavesTheMapForLongerThanTheGap) {
  // The route leaves the flat map (x beyond about 11) and comes back into it on the way home.
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {40.0, 0.0}, {40.0, 3.0}, {-7.0, 3.0}};
  LocalGoalSelection::Config config;
  const auto no_limit = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(no_limit.has_value());
  EXPECT_GT(no_limit->route_progress_m, 50.0);  // on the way home: cuts the route short
  config.max_gap_m = 8.0;
  const auto limited = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(limited.has_value());
  EXPECT_LT(limited->route_progress_m, 20.0);
  EXPECT_NEAR(limited->pose.y_m, 0.0, 1e-12);
  // Tracked progress puts "ahead" where the vehicle is along the route, not at the nearest lap.
  const auto home = SelectLocalGoals(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{5.0, 0.2, 0.0}, config,
                                     std::nullopt, 1, 80.0);  // at x = 10 on the way home
  ASSERT_EQ(home.size(), 1u);
  EXPECT_GT(home.front().route_progress_m, 80.0);
  EXPECT_NEAR(home.front().pose.y_m, 3.0, 1e-12);
}

TEST(LocalGoalTest, CandidatesEndWhereTheRouteStraysFromTheChordByMoreThanTheDetour) {
  // A U-turn inside the map: out along y = 0 to x = 6, round and back along y = 5. Without a limit
  // the goal lies on the way back; with max_detour_m the candidates end before the route turns back.
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {6.0, 0.0}, {8.5, 2.5}, {6.0, 5.0}, {-7.0, 5.0}};
  LocalGoalSelection::Config config;
  config.max_gap_m = 8.0;
  const auto no_limit = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(no_limit.has_value());
  EXPECT_GT(no_limit->route_progress_m, 20.0) << "past the turn, on the way back";
  config.max_detour_m = 3.0;
  const auto goals = SelectLocalGoals(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config,
                                      std::nullopt, 5, 0.0);
  ASSERT_FALSE(goals.empty());
  for (const LocalGoal& g : goals) {
    EXPECT_LE(g.route_progress_m, 13.0 + 2 * 3.54) << "in the turn at most, not on the way back";
    EXPECT_GT(g.pose.x_m, 5.0);
  }
  // Round the turn, the way back is a candidate: the route behind strays less.
  const auto round = SelectLocalGoals(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{7.0, 4.0, 2.4}, config,
                                      std::nullopt, 1, 19.0);
  ASSERT_EQ(round.size(), 1u);
  EXPECT_GT(round.front().route_progress_m, 21.0);
  // A straight route never strays: the same goal as without the limit.
  const std::vector<Eigen::Vector2d> straight = {{-7.0, 0.0}, {40.0, 0.0}};
  config.max_gap_m = std::numeric_limits<double>::infinity();
  const auto a = SelectLocalGoal(FlatMap(), VehicleBox{}, straight, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  config.max_detour_m = std::numeric_limits<double>::infinity();
  const auto b = SelectLocalGoal(FlatMap(), VehicleBox{}, straight, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->route_progress_m, b->route_progress_m);
}

TEST(LocalGoalTest, CandidatesEndAtMostMaxAheadAlongTheRoute) {
  // A hairpin inside the map: out along y = 0, back along y = 3. No gap stops the candidates, so
  // without a limit the goal lies on the way back and skips the turn.
  const std::vector<Eigen::Vector2d> route = {{-7.0, 0.0}, {6.0, 0.0}, {6.0, 3.0}, {-7.0, 3.0}};
  LocalGoalSelection::Config config;
  config.max_gap_m = 8.0;
  const auto no_limit = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(no_limit.has_value());
  EXPECT_GT(no_limit->route_progress_m, 16.0);  // past the turn, on the way back
  config.max_ahead_m = 8.0;
  const auto limited = SelectLocalGoals(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config,
                                        std::nullopt, 5, 0.0);
  ASSERT_FALSE(limited.empty());
  for (const LocalGoal& g : limited) EXPECT_LE(g.route_progress_m, 8.0 + 1e-9);
  EXPECT_NEAR(limited.front().route_progress_m, 8.0, 0.3);
  // The limit moves with the vehicle's progress.
  const auto later = SelectLocalGoals(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{1.0, 0.0, 0.0}, config,
                                      std::nullopt, 1, 8.0);
  ASSERT_EQ(later.size(), 1u);
  EXPECT_GT(later.front().route_progress_m, 8.0);
  EXPECT_LE(later.front().route_progress_m, 16.0 + 1e-9);
  LocalGoalSelection::Config bad;
  bad.max_ahead_m = 0.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// The first failing check of `at(x, y)` over the box's footprint, sampled every 0.1 m.
template <class At>
PoseCheck CheckFootprint(const GroundPose& ground, const VehicleBox& vehicle, At at) {
  const double x0 = vehicle.centre_ahead_m - 0.5 * vehicle.length_m - vehicle.margin_m;
  const double half = 0.5 * vehicle.width_m + vehicle.margin_m;
  for (double x = x0; x <= x0 + vehicle.length_m + 2 * vehicle.margin_m + 1e-9; x += 0.1) {
    for (double y = -half; y <= half + 1e-9; y += 0.1) {
      const Vec3 p = ground.T_L_B * Vec3(x, y, 0.0);
      const PoseCheck check = at(p.x(), p.y());
      if (check != PoseCheck::kValid) return check;
    }
  }
  return PoseCheck::kValid;
}

// A flat known square, x and y in [-10, 10], with a wall of non-traversable ground across it at
// x in [4, 5] from y = -10 up to y = 4: the way round is the gap between y = 4 and y = 10.
class WallMap : public PlanningMap {
 public:
  static bool Wall(double x, double y) { return x >= 4.0 && x <= 5.0 && y <= 4.0; }
  static bool Known(double x, double y) { return std::abs(x) <= 10.0 && std::abs(y) <= 10.0; }
  std::optional<GroundPose> Project(const Pose2& pose) const override {
    if (!Known(pose.x_m, pose.y_m)) return std::nullopt;
    return PoseOnPlane(pose, Vec3(pose.x_m, pose.y_m, 0.0), Vec3::UnitZ(), !Wall(pose.x_m, pose.y_m));
  }
  PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const override {
    // The footprint must lie on known ground away from the wall.
    return CheckFootprint(ground, vehicle, [](double x, double y) {
      return Known(x, y) && !Wall(x, y) ? PoseCheck::kValid : PoseCheck::kGroundUnderFootprint;
    });
  }
  bool IsKnownFree(double x_m, double y_m) const override { return Known(x_m, y_m) && !Wall(x_m, y_m); }
  MapBounds Bounds() const override { return MapBounds{-10.0, 10.0, -10.0, 10.0}; }
};

TEST(LocalGoalTest, ReachableGoalTakesTheWayRoundAWallTheRouteRunsInto) {
  const WallMap map;
  const VehicleBox vehicle;
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {30.0, 0.0}};
  const Pose2 start{-5.0, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.max_gap_m = 8.0;
  // The reachable goal lies past the wall, where the vehicle gets only through the gap.
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  const auto goals = SelectLocalGoals(map, vehicle, route, kIdentity, start, config, std::nullopt, 3);
  ASSERT_FALSE(goals.empty());
  const LocalGoal& best = goals.front();
  EXPECT_GT(best.pose.x_m, 5.0);
  EXPECT_EQ(CheckPose(map, vehicle, best.pose), PoseCheck::kValid);
  EXPECT_GT(best.route_progress_m, 15.0);
  EXPECT_LT(std::abs(NormalizeYaw(best.pose.yaw_rad)), kPi / 2);  // heading on towards the route's end
  for (const LocalGoal& g : goals) {
    EXPECT_EQ(CheckPose(map, vehicle, g.pose), PoseCheck::kValid);
    EXPECT_FALSE(g.is_route_end);
  }

  // With the gap closed nothing past the wall is reachable. The route rule still picks a goal past
  // it (the wall is narrower than the gap the route may run outside known free space); the
  // reachable goals stay in front of it.
  struct Closed : WallMap {
    std::optional<GroundPose> Project(const Pose2& pose) const override {
      if (!Known(pose.x_m, pose.y_m)) return std::nullopt;
      const bool wall = pose.x_m >= 4.0 && pose.x_m <= 5.0;
      return PoseOnPlane(pose, Vec3(pose.x_m, pose.y_m, 0.0), Vec3::UnitZ(), !wall);
    }
    bool IsKnownFree(double x_m, double y_m) const override { return Known(x_m, y_m) && !(x_m >= 4.0 && x_m <= 5.0); }
  };
  const Closed closed;
  LocalGoalSelection::Config route_rule = config;
  route_rule.mode = LocalGoalSelection::Config::Mode::kRoute;
  const auto on_route = SelectLocalGoal(closed, vehicle, route, kIdentity, start, route_rule);
  ASSERT_TRUE(on_route.has_value());
  EXPECT_GT(on_route->pose.x_m, 5.0);
  const auto blocked = SelectLocalGoals(closed, vehicle, route, kIdentity, start, config, std::nullopt, 3);
  ASSERT_FALSE(blocked.empty());
  for (const LocalGoal& g : blocked) EXPECT_LT(g.pose.x_m, 4.0);
}

// At the rim of what the map has seen, straight ahead (a crest, an edge), the best place the vehicle
// fits is nearer than min_distance_m. Without look_at_rim every goal keeps that distance, so none is
// ahead of the vehicle; with it that place is a candidate too, pulled back so that the vehicle would
// fit 0.4 m farther on, and marked as a place to look from, unless the vehicle is within 1 m of it.
TEST(LocalGoalTest, ReachableGoalLooksOverTheRimStraightAhead) {
  const VehicleBox vehicle;
  const std::vector<Eigen::Vector2d> route = {{-20.0, 0.0}, {40.0, 0.0}};
  const auto last_fit = SelectLocalGoal(FlatMap(), vehicle, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, LocalGoalSelection::Config{});
  ASSERT_TRUE(last_fit.has_value());
  // From 2.45 m short of the last fit the place to look from (0.5 m cells, pulled back so that the
  // vehicle also fits 0.4 m on) lies about 1.7 m ahead: beyond the 1 m within which the vehicle looks
  // by standing, and nearer than min_distance_m, which keeps the plain goals' cells farther out.
  const Pose2 here{last_fit->pose.x_m - 2.45, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  config.min_distance_m = 4.0;
  const auto plain = SelectLocalGoals(FlatMap(), vehicle, route, kIdentity, here, config, std::nullopt, 3);
  for (const LocalGoal& g : plain) {
    EXPECT_FALSE(g.is_look);
    EXPECT_GE(std::hypot(g.pose.x_m - here.x_m, g.pose.y_m - here.y_m), config.min_distance_m);
  }
  config.look_at_rim = true;
  const auto look = SelectLocalGoals(FlatMap(), vehicle, route, kIdentity, here, config, std::nullopt, 3);
  const auto it = std::find_if(look.begin(), look.end(), [](const LocalGoal& l) { return l.is_look; });
  ASSERT_NE(it, look.end()) << "a place to look from among the candidates";
  EXPECT_EQ(std::count_if(look.begin(), look.end(), [](const LocalGoal& l) { return l.is_look; }), 1);
  const LocalGoal& g = *it;
  EXPECT_LT(std::hypot(g.pose.x_m - here.x_m, g.pose.y_m - here.y_m), config.min_distance_m);
  EXPECT_LT(std::abs(g.pose.y_m), 0.5);
  EXPECT_LT(std::abs(NormalizeYaw(g.pose.yaw_rad)), 0.5);
  EXPECT_GT(g.pose.x_m, here.x_m) << "ahead, at the rim";
  EXPECT_EQ(CheckPose(FlatMap(), vehicle, Pose2{g.pose.x_m + 0.4, g.pose.y_m, g.pose.yaw_rad}), PoseCheck::kValid)
      << "the vehicle fits 0.4 m farther on too";
  // Near the rim, so that the sensor looks down what lies beyond it steeply: within the margin and
  // one cell of the last place the vehicle fits (with a 0.8 m margin the place was 1.25 m short).
  EXPECT_LT(last_fit->pose.x_m - g.pose.x_m, 0.4 + 0.5 + 1e-9);
  for (const LocalGoal& l : look) {
    if (!l.is_look) {
      EXPECT_GE(std::hypot(l.pose.x_m - here.x_m, l.pose.y_m - here.y_m), config.min_distance_m);
    }
  }
  // Standing within 1 m of that place, the vehicle looks from where it is: no place to look from.
  const Pose2 there{g.pose.x_m - 0.6, 0.0, 0.0};
  for (const LocalGoal& l : SelectLocalGoals(FlatMap(), vehicle, route, kIdentity, there, config, std::nullopt, 3)) {
    EXPECT_FALSE(l.is_look);
  }
}

TEST(LocalGoalTest, ReachableGoalOnOpenGroundFollowsTheRoute) {
  const std::vector<Eigen::Vector2d> route = {{-20.0, 0.0}, {0.0, 0.0}, {40.0, 0.0}};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  const auto goal = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(goal.has_value());
  EXPECT_GT(goal->pose.x_m, 5.0);  // near the map's far rim along the route
  EXPECT_LT(std::abs(goal->pose.y_m), 1.5);
  EXPECT_EQ(CheckPose(FlatMap(), VehicleBox{}, goal->pose), PoseCheck::kValid);
  // Weighing the distance from the route keeps the goal on it here (and never moves it away).
  LocalGoalSelection::Config near_route = config;
  near_route.reach_offset_penalty = 0.5;
  const auto on_route = SelectLocalGoal(FlatMap(), VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, near_route);
  ASSERT_TRUE(on_route.has_value());
  EXPECT_LE(std::abs(on_route->pose.y_m), std::abs(goal->pose.y_m) + 1e-9);
  near_route.reach_offset_penalty = -1.0;
  EXPECT_THROW(near_route.Validate(), std::invalid_argument);

  // The route's end, when reached, is the goal itself.
  const std::vector<Eigen::Vector2d> short_route = {{-7.0, 0.0}, {3.0, 2.0}};
  const auto end = SelectLocalGoal(FlatMap(), VehicleBox{}, short_route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config);
  ASSERT_TRUE(end.has_value());
  EXPECT_TRUE(end->is_route_end);
  EXPECT_NEAR(end->pose.x_m, 3.0, 1e-9);
  EXPECT_NEAR(end->pose.y_m, 2.0, 1e-9);
}

// Dense ground (0.2 m apart) up to x = 2, then sparse ground (1.5 m apart) to x = 20, as far from
// the sensor: the planner stands a wheel only near a visible point, so a goal out on the sparse
// ground is one few paths lead to.
TEST(LocalGoalTest, ReachableGoalStaysOnGroundDenseEnoughToStandOn) {
  Points points;
  std::vector<Vec3> normals;
  for (int i = -50; i <= 10; ++i) {
    for (int j = -30; j <= 30; ++j) points.emplace_back(0.2 * i, 0.2 * j, 0.0);
  }
  for (double x = 3.5; x <= 20.0; x += 1.5) {
    for (double y = -6.0; y <= 6.0; y += 1.5) points.emplace_back(x, y, 0.0);
  }
  normals.assign(points.size(), Vec3::UnitZ());
  VertexCloudMap::Config map_config;
  map_config.max_projection_distance_m = 1.2;  // every place on the sparse ground projects
  const VertexCloudMap map(TraversabilityCloud(points, normals, std::vector<std::uint8_t>(points.size(), 1)),
                           map_config);
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {40.0, 0.0}};
  const Pose2 start{-6.0, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  // Any distance to the nearest point: the goal goes out over the sparse ground.
  const auto anywhere = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(anywhere.has_value());
  EXPECT_GT(anywhere->pose.x_m, 10.0);
  // Within 0.5 m of a point: the sparse ground is islands the reach does not cross, so the goal is
  // at the far end of the dense ground.
  config.reach_support_m = 0.5;
  const auto supported = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(supported.has_value());
  EXPECT_GT(supported->pose.x_m, 0.0);
  EXPECT_LT(supported->pose.x_m, 2.5);
  EXPECT_LT(std::abs(supported->pose.y_m), 1.5);
  EXPECT_EQ(CheckPose(map, VehicleBox{}, supported->pose), PoseCheck::kValid);
  config.reach_support_m = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}


// A band 1.4 m wide without points across the route (a swale's floor and near wall, seen only at a
// grazing angle), between dense ground on both sides. Its middle cells lie 0.45 m from the nearest
// point: within reach_support_m (0.5 m), but beyond the 0.35 m a wheel stands within near the sensor
// with the wheel rule. The reach then stops at the band, as the planner's wheels do, so no goal lies
// past ground no path crosses; with the footprint rule (no wheel support) it crosses the band.
TEST(LocalGoalTest, ReachableGoalCrossesNoBandTheWheelsCannotStandIn) {
  Points points;
  for (int i = -50; i <= 50; ++i) {
    for (int j = -30; j <= 30; ++j) {
      const double x = 0.2 * i;
      if (x > 1.85 && x < 3.15) continue;  // the band: points at x = 1.8 and 3.2 either side of it
      points.emplace_back(x, 0.2 * j, 0.0);
    }
  }
  const std::vector<Vec3> normals(points.size(), Vec3::UnitZ());
  VertexCloudMap::Config map_config;
  map_config.max_projection_distance_m = 1.2;  // the band's middle projects onto ground beside it
  const VertexCloudMap map(TraversabilityCloud(points, normals, std::vector<std::uint8_t>(points.size(), 1)),
                           map_config);
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {40.0, 0.0}};
  const Pose2 start{-3.0, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  config.reach_support_m = 0.5;
  VehicleBox footprint;  // every point under the footprint: no wheel support
  const auto across = SelectLocalGoal(map, footprint, route, kIdentity, start, config);
  ASSERT_TRUE(across.has_value());
  EXPECT_GT(across->pose.x_m, 3.2);
  VehicleBox wheels = footprint;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.wheel_support_m = 0.5;
  wheels.wheel_support_per_m = 0.05;
  wheels.wheel_support_near_m = 0.35;
  EXPECT_EQ(CheckPose(map, wheels, Pose2{0.6, 0.0, 0.0}), PoseCheck::kUnseenGround) << "the front wheels in the band";
  const auto before = SelectLocalGoal(map, wheels, route, kIdentity, start, config);
  ASSERT_TRUE(before.has_value());
  EXPECT_LT(before->pose.x_m, 1.85);
  EXPECT_EQ(CheckPose(map, wheels, before->pose), PoseCheck::kValid);
}

// Flat traversable ground over x in [-10, xmax], y in [-10, 10], with a roof too low for the vehicle
// over x in [x0, x1], |y| <= 3: the ground under it is seen and traversable, but a box there
// collides.
class LowRoofMap : public PlanningMap {
 public:
  /// Beside the roof (|y| > 3) the ground is known up to x_side (the roof's shadow), under it up to
  /// x_max.
  LowRoofMap(double x_max, double x0, double x1, double x_side) : x_max_(x_max), x0_(x0), x1_(x1), x_side_(x_side) {}
  bool Known(double x, double y) const {
    return x >= -10.0 && x <= (std::abs(y) <= 3.0 ? x_max_ : x_side_) && std::abs(y) <= 10.0;
  }
  bool Roof(double x, double y) const { return x >= x0_ && x <= x1_ && std::abs(y) <= 3.0; }
  std::optional<GroundPose> Project(const Pose2& pose) const override {
    if (!Known(pose.x_m, pose.y_m)) return std::nullopt;
    return PoseOnPlane(pose, Vec3(pose.x_m, pose.y_m, 0.0), Vec3::UnitZ(), true);
  }
  PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const override {
    return CheckFootprint(ground, vehicle, [this](double x, double y) {
      if (Roof(x, y)) return PoseCheck::kCollision;
      return Known(x, y) ? PoseCheck::kValid : PoseCheck::kGroundUnderFootprint;
    });
  }
  bool IsKnownFree(double x_m, double y_m) const override { return Known(x_m, y_m); }
  MapBounds Bounds() const override { return MapBounds{-10.0, x_max_, -10.0, 10.0}; }

 private:
  double x_max_, x0_, x1_, x_side_;
};

TEST(LocalGoalTest, ReachableGoalGoesRoundARoofTooLowToPassUnder) {
  // The ground under the roof is traversable, but the vehicle cannot be there; the known ground ends
  // at the roof's far edge, and beside the roof 3 m short of it (its shadow): the cost to go goes
  // round the roof, not under it.
  const LowRoofMap map(4.0, 0.0, 4.0, -3.0);
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {30.0, 0.0}};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  const auto goals = SelectLocalGoals(map, VehicleBox{}, route, kIdentity, Pose2{-7.0, 0.0, 0.0}, config, std::nullopt, 3);
  ASSERT_FALSE(goals.empty());
  // The best goal is at the front edge on the side of the corner, heading round it (with the roof
  // ignored it heads straight on, under the roof).
  EXPECT_GT(std::abs(goals.front().pose.yaw_rad), 0.3);
  EXPECT_LT(goals.front().pose.x_m, 0.0);
  for (const LocalGoal& g : goals) EXPECT_EQ(CheckPose(map, VehicleBox{}, g.pose), PoseCheck::kValid);
}

TEST(LocalGoalTest, ReachableGoalKeepsToTheSideOfThePreviousGoalWhenBothAreAsGood) {
  // The known ground ends at x = 4, over the roof: the two ways round it are equally good, and
  // the previous goal's side is kept.
  const LowRoofMap map(4.0, 0.0, 4.0, 4.0);
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {30.0, 0.0}};
  const Pose2 start{-6.0, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  config.previous_goal_penalty = 0.3;
  for (const double side : {-1.0, 1.0}) {
    // The previous goal, on that side (not kept itself: keep_previous_within_m is 0).
    const LocalGoal previous{Pose2{-5.0, 4.5 * side, 0.0}, 5.0, false};
    const auto goal = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config, previous);
    ASSERT_TRUE(goal.has_value());
    EXPECT_GT(goal->pose.y_m * side, 2.0) << side;
  }
  config.previous_goal_penalty = -0.1;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

// Flat known ground, x in [-10, 20], |y| <= 6, with two columns of posts (x = 4 and 7) 3 m apart
// across it (y = +-1.5, +-4.5, ...): each post's foot is non-traversable within 0.4 m of its centre,
// so the lanes between them are 2.2 m wide, room for the 1.7 m box with its margins.
class PostRowsMap : public PlanningMap {
 public:
  static bool Post(double x, double y) {
    for (const double px : {4.0, 7.0}) {
      for (double py = -10.5; py <= 10.5; py += 3.0) {
        if (std::hypot(x - px, y - py) <= 0.4) return true;
      }
    }
    return false;
  }
  static bool Known(double x, double y) { return x >= -10.0 && x <= 20.0 && std::abs(y) <= 6.0; }
  std::optional<GroundPose> Project(const Pose2& pose) const override {
    if (!Known(pose.x_m, pose.y_m)) return std::nullopt;
    return PoseOnPlane(pose, Vec3(pose.x_m, pose.y_m, 0.0), Vec3::UnitZ(), !Post(pose.x_m, pose.y_m));
  }
  PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const override {
    return CheckFootprint(ground, vehicle, [](double x, double y) {
      if (Post(x, y)) return PoseCheck::kCollision;
      return Known(x, y) ? PoseCheck::kValid : PoseCheck::kGroundUnderFootprint;
    });
  }
  bool IsKnownFree(double x_m, double y_m) const override { return Known(x_m, y_m) && !Post(x_m, y_m); }
  MapBounds Bounds() const override { return MapBounds{-10.0, 20.0, -6.0, 6.0}; }
};

TEST(LocalGoalTest, ReachableGoalGoesDownALaneBetweenPostsTheVehicleFits) {
  // The reach keeps the vehicle's half width from each non-traversable point itself; growing the
  // post's grid cells by whole cells instead closed the 2.2 m lane, and the goal stayed in front
  // of the first column.
  const PostRowsMap map;
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {30.0, 0.0}};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  config.cell_m = 0.5;  // the closed loop's cells
  const auto goals = SelectLocalGoals(map, VehicleBox{}, route, kIdentity, Pose2{-2.0, 0.0, 0.0}, config, std::nullopt, 3);
  ASSERT_FALSE(goals.empty());
  EXPECT_GT(goals.front().pose.x_m, 8.0);
  EXPECT_LT(std::abs(goals.front().pose.y_m), 1.5);
  for (const LocalGoal& g : goals) EXPECT_EQ(CheckPose(map, VehicleBox{}, g.pose), PoseCheck::kValid);
}

// A wall across known ground (x in [4, 5]) with two gaps 1 m wide, at y in [5.5, 6.5] and
// [-6.5, -5.5]: too narrow for the vehicle's reach, open to the cost to go. Past the wall the ground
// is known south of the route (y < 0) and unseen north of it.
class TwoGapsMap : public PlanningMap {
 public:
  static bool Wall(double x, double y) {
    return x >= 4.0 && x <= 5.0 && !(std::abs(y) >= 5.5 && std::abs(y) <= 6.5);
  }
  static bool Known(double x, double y) { return x >= -10.0 && std::abs(y) <= 10.0 && (x <= 5.0 || (x <= 10.0 && y < 0.0)); }
  std::optional<GroundPose> Project(const Pose2& pose) const override {
    if (!Known(pose.x_m, pose.y_m)) return std::nullopt;
    return PoseOnPlane(pose, Vec3(pose.x_m, pose.y_m, 0.0), Vec3::UnitZ(), !Wall(pose.x_m, pose.y_m));
  }
  PoseCheck CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const override {
    return CheckFootprint(ground, vehicle, [](double x, double y) {
      if (Wall(x, y)) return PoseCheck::kCollision;
      return Known(x, y) ? PoseCheck::kValid : PoseCheck::kGroundUnderFootprint;
    });
  }
  bool IsKnownFree(double x_m, double y_m) const override { return Known(x_m, y_m) && !Wall(x_m, y_m); }
  MapBounds Bounds() const override { return MapBounds{-10.0, 10.0, -10.0, 10.0}; }
};

TEST(LocalGoalTest, ReachableGoalPrefersTheWayRoundItHasSeenToBeFree) {
  // Both ways round are as long; the south one runs over ground seen to be free, the north one over
  // unseen ground. Counted alike, the unseen way is at least as good (here a grid cell's offset
  // makes it a little better) and the goal goes north; counting unseen ground dearer, south.
  const TwoGapsMap map;
  const std::vector<Eigen::Vector2d> route = {{-10.0, 0.0}, {30.0, 0.0}};
  const Pose2 start{-6.0, 0.0, 0.0};
  LocalGoalSelection::Config config;
  config.mode = LocalGoalSelection::Config::Mode::kReachable;
  const auto alike = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(alike.has_value());
  EXPECT_GT(alike->pose.y_m, 2.0);
  config.unknown_cost = 1.5;
  const auto seen = SelectLocalGoal(map, VehicleBox{}, route, kIdentity, start, config);
  ASSERT_TRUE(seen.has_value());
  EXPECT_LT(seen->pose.y_m, -2.0);
  EXPECT_LT(seen->pose.x_m, 4.0);  // in front of the wall: the gap is too narrow to reach through
  EXPECT_EQ(CheckPose(map, VehicleBox{}, seen->pose), PoseCheck::kValid);
  config.unknown_cost = 0.5;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::planner
