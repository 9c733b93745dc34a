#include "ovpc/planner/local_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "planning_scenes.h"

namespace ovpc::planner {
namespace {

using testing::BuildScene;
using testing::FlatMap;
using testing::FlatPlanningScene;
using testing::PlanningScene;

const Pose2 kStart{-7.0, 0.0, 0.0};
const Pose2 kGoal{7.0, 0.0, 0.0};

// The scene tests run with several seeds: a property of the planner, not of one lucky seed.
constexpr std::uint32_t kSeeds[] = {1, 2, 3, 4, 5, 6, 7, 8};

LocalPlanner SeededPlanner(std::uint32_t seed) { return LocalPlanner(LocalPlanner::Config{}, VehicleModel{}, seed); }

PlanResult PlanScene(const LocalPlanner& planner, const PlanningScene& scene) {
  return planner.Plan(*scene.map, scene.spec.start, scene.spec.goal);
}

// Scenes are built once per test program: the mapper is the slow part.
const PlanningScene& Posts() {
  static const PlanningScene scene = BuildScene(testing::PostsScene());
  return scene;
}
const PlanningScene& Carport() {
  static const PlanningScene scene = BuildScene(testing::CarportScene(2.5));
  return scene;
}
const PlanningScene& LowRoof() {
  static const PlanningScene scene = BuildScene(testing::LowRoofScene());
  return scene;
}

// Checks every output pose against the map, the shape of the segments, and the ends.
void ExpectWellFormed(const PlanResult& result, const PlanningMap& map, const LocalPlanner& planner,
                      const Pose2& start, const Pose2& goal) {
  ASSERT_EQ(result.status, PlanStatus::kFound);
  ASSERT_FALSE(result.path.empty());
  EXPECT_FALSE(planner.FirstInvalidPose(map, result.path).has_value());
  const std::vector<PathPose> poses = result.path.Poses();
  ASSERT_GE(poses.size(), 2u);
  EXPECT_NEAR(poses.front().pose.x_m, start.x_m, 1e-6);
  EXPECT_NEAR(poses.front().pose.y_m, start.y_m, 1e-6);
  EXPECT_NEAR(poses.back().pose.x_m, goal.x_m, 1e-3);
  EXPECT_NEAR(poses.back().pose.y_m, goal.y_m, 1e-3);
  EXPECT_NEAR(std::remainder(poses.back().pose.yaw_rad - goal.yaw_rad, 2 * kPi), 0.0, 1e-3);
  for (std::size_t i = 0; i < result.path.segments().size(); ++i) {
    const PathSegment& s = result.path.segments()[i];
    EXPECT_GE(s.poses.size(), 2u);
    if (i > 0) {
      // Segments alternate direction and share the cusp pose.
      EXPECT_NE(s.direction, result.path.segments()[i - 1].direction);
      EXPECT_EQ(s.poses.front().pose.x_m, result.path.segments()[i - 1].poses.back().pose.x_m);
      EXPECT_EQ(s.poses.front().pose.y_m, result.path.segments()[i - 1].poses.back().pose.y_m);
    }
    for (std::size_t k = 1; k < s.poses.size(); ++k) {
      const PathPose& a = s.poses[k - 1];
      const PathPose& b = s.poses[k];
      EXPECT_LE(std::hypot(b.pose.x_m - a.pose.x_m, b.pose.y_m - a.pose.y_m), 0.1 + 1e-6);
      EXPECT_GE(a.pose.yaw_rad, -kPi);
      EXPECT_LT(a.pose.yaw_rad, kPi);
      // The motion between poses goes along the heading when forward, against it when reversing.
      const double along = (b.pose.x_m - a.pose.x_m) * std::cos(a.pose.yaw_rad) +
                           (b.pose.y_m - a.pose.y_m) * std::sin(a.pose.yaw_rad);
      EXPECT_GT(s.direction == Direction::kForward ? along : -along, -1e-9);
    }
  }
}

// True if a point at (px, py) lies in the vehicle's footprint (no margin) at `pose`, grown by `grow`.
bool InFootprint(const VehicleBox& vehicle, const Pose2& pose, double px, double py, double grow) {
  const double dx = px - pose.x_m, dy = py - pose.y_m;
  const double x = std::cos(pose.yaw_rad) * dx + std::sin(pose.yaw_rad) * dy - vehicle.centre_ahead_m;
  const double y = -std::sin(pose.yaw_rad) * dx + std::cos(pose.yaw_rad) * dy;
  return std::abs(x) <= 0.5 * vehicle.length_m + grow && std::abs(y) <= 0.5 * vehicle.width_m + grow;
}

TEST(LocalPlannerTest, ScenesAreBuiltByTheMapper) {
  for (const PlanningScene* scene : {&FlatPlanningScene(), &Posts(), &Carport(), &LowRoof()}) {
    ASSERT_TRUE(scene->ovpc.ok()) << scene->ovpc.message;
    EXPECT_GT(scene->map->cloud().size(), 1000u);
  }
}

TEST(LocalPlannerTest, FlatGroundGivesANearStraightForwardPath) {
  for (const std::uint32_t seed : kSeeds) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const LocalPlanner planner = SeededPlanner(seed);
    const PlanResult result = planner.Plan(FlatMap(), kStart, kGoal);
    ExpectWellFormed(result, FlatMap(), planner, kStart, kGoal);
    EXPECT_EQ(result.path.segments().size(), 1u);
    EXPECT_EQ(result.path.segments().front().direction, Direction::kForward);
    EXPECT_LT(result.path.Length(), 1.05 * 14.0);
    double max_offset = 0.0;
    for (const PathPose& p : result.path.Poses()) max_offset = std::max(max_offset, std::abs(p.pose.y_m));
    EXPECT_LT(max_offset, 0.5);
    EXPECT_GT(result.iterations, 0u);
    EXPECT_LE(result.iterations, planner.config().max_iterations);
  }
}

TEST(LocalPlannerTest, GoesAroundAClusterOfPosts) {
  for (const std::uint32_t seed : kSeeds) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const LocalPlanner planner = SeededPlanner(seed);
    const PlanResult result = PlanScene(planner, Posts());
    ExpectWellFormed(result, *Posts().map, planner, Posts().spec.start, Posts().spec.goal);
    const VehicleBox& vehicle = planner.box();
    double max_offset = 0.0;
    for (const PathPose& p : result.path.Poses()) {
      max_offset = std::max(max_offset, std::abs(p.pose.y_m));
      for (const testing::Post& post : Posts().spec.posts) {
        EXPECT_FALSE(InFootprint(vehicle, p.pose, post.x, post.y, post.radius))
            << "post (" << post.x << ", " << post.y << ") under the vehicle at (" << p.pose.x_m << ", " << p.pose.y_m
            << ")";
      }
    }
    EXPECT_GT(max_offset, 1.2 + 0.15 + 0.5 * vehicle.width_m);  // beside the outer posts
  }
}

TEST(LocalPlannerTest, DrivesUnderACarportRoofAt2p5m) {
  for (const std::uint32_t seed : kSeeds) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const LocalPlanner planner = SeededPlanner(seed);
    const PlanningScene& scene = Carport();
    const PlanResult result = PlanScene(planner, scene);
    ExpectWellFormed(result, *scene.map, planner, scene.spec.start, scene.spec.goal);
    const testing::Rect roof = testing::CarportRoof();
    int under = 0;
    for (const PathPose& p : result.path.Poses()) under += roof.Contains(p.pose.x_m, p.pose.y_m);
    EXPECT_GT(under, 30);  // the whole 4 m under the roof
    EXPECT_LT(result.path.Length(), 1.05 * (scene.spec.goal.x_m - scene.spec.start.x_m));
  }
}

TEST(LocalPlannerTest, NeverDrivesUnderARoofAt1p6m) {
  for (const std::uint32_t seed : kSeeds) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const LocalPlanner planner = SeededPlanner(seed);
    const PlanningScene& scene = LowRoof();
    const PlanResult result = PlanScene(planner, scene);
    ASSERT_TRUE(result.status == PlanStatus::kFound || result.status == PlanStatus::kNoPath)
        << PlanStatusName(result.status);
    // This scene leaves room to pass beside the slab, in view of the scanning vehicle.
    ExpectWellFormed(result, *scene.map, planner, scene.spec.start, scene.spec.goal);
    const testing::Rect roof = testing::LowRoof();
    const VehicleBox& vehicle = planner.box();
    for (const PathPose& p : result.path.Poses()) {
      for (double x = roof.min_x; x <= roof.max_x + 1e-9; x += 0.25) {
        for (double y = roof.min_y; y <= roof.max_y + 1e-9; y += 0.25) {
          ASSERT_FALSE(InFootprint(vehicle, p.pose, x, y, 0.0))
              << "under the roof at (" << p.pose.x_m << ", " << p.pose.y_m << ")";
        }
      }
    }
  }
}

TEST(LocalPlannerTest, DoesNotCrossA35DegreeSlopeButCrossesAGentleOne) {
  const LocalPlanner planner(LocalPlanner::Config{});
  const PlanningScene steep = BuildScene(testing::SlopeScene(35.0));
  const PlanResult blocked = PlanScene(planner, steep);
  EXPECT_EQ(blocked.goal_check, PoseCheck::kValid);  // the plateau is in the map
  EXPECT_EQ(blocked.status, PlanStatus::kNoPath) << PlanStatusName(blocked.status);
  EXPECT_EQ(blocked.iterations, planner.config().max_iterations);

  // The same scene at 5 deg is crossed. (The rigid box, level at the foot of the ramp, touches a
  // steeper ramp with its front: 0.2 m clearance over the 2.45 m to the box front is about 4.7 deg.)
  const PlanningScene gentle = BuildScene(testing::SlopeScene(5.0));
  const PlanResult crossed = PlanScene(planner, gentle);
  ExpectWellFormed(crossed, *gentle.map, planner, gentle.spec.start, gentle.spec.goal);
  EXPECT_NEAR(crossed.path.Poses().back().z_m, 2.0 * std::tan(DegToRad(5.0)), 0.02);  // on the plateau
}

TEST(LocalPlannerTest, StartInCollisionIsReportedAsSuch) {
  const LocalPlanner planner(LocalPlanner::Config{});
  const PlanResult result = planner.Plan(*Posts().map, Pose2{-1.0, 0.0, 0.0}, Posts().spec.goal);
  EXPECT_EQ(result.status, PlanStatus::kStartInvalid);
  EXPECT_NE(result.start_check, PoseCheck::kValid);
  EXPECT_TRUE(result.path.empty());

  const PlanResult outside = planner.Plan(*Posts().map, Pose2{-30.0, 0.0, 0.0}, Posts().spec.goal);
  EXPECT_EQ(outside.status, PlanStatus::kStartInvalid);
  EXPECT_EQ(outside.start_check, PoseCheck::kOutsideMap);
}

TEST(LocalPlannerTest, GoalInCollisionIsReportedAsSuch) {
  const LocalPlanner planner(LocalPlanner::Config{});
  const PlanResult result = planner.Plan(*Posts().map, Posts().spec.start, Pose2{-3.0, 0.0, 0.0});
  EXPECT_EQ(result.status, PlanStatus::kGoalInvalid);
  EXPECT_EQ(result.start_check, PoseCheck::kValid);
  // The posts in the box, or the non-traversable ground of their shadows under the footprint.
  EXPECT_TRUE(result.goal_check == PoseCheck::kCollision || result.goal_check == PoseCheck::kGroundUnderFootprint)
      << PoseCheckName(result.goal_check);
}

TEST(LocalPlannerTest, SameSeedTwiceGivesTheSamePath) {
  const LocalPlanner::Config config;
  const LocalPlanner first(config, VehicleModel{}, 7);
  const PlanResult a = first.Plan(*Posts().map, Posts().spec.start, Posts().spec.goal);
  // Other plans in between consume OMPL's process-wide seed sequence; they must not matter.
  const PlanResult other = LocalPlanner(config, VehicleModel{}, 8).Plan(*Posts().map, Posts().spec.start, Posts().spec.goal);
  const PlanResult b = LocalPlanner(config, VehicleModel{}, 7).Plan(*Posts().map, Posts().spec.start, Posts().spec.goal);
  const PlanResult c = first.Plan(*Posts().map, Posts().spec.start, Posts().spec.goal);
  ASSERT_TRUE(a.found() && b.found() && c.found() && other.found());
  for (const PlanResult* r : {&b, &c}) {
    EXPECT_EQ(r->iterations, a.iterations);
    EXPECT_EQ(r->raw_states, a.raw_states);
    const std::vector<PathPose> pa = a.path.Poses(), pr = r->path.Poses();
    ASSERT_EQ(pr.size(), pa.size());
    for (std::size_t i = 0; i < pa.size(); ++i) {
      EXPECT_EQ(pr[i].pose.x_m, pa[i].pose.x_m);
      EXPECT_EQ(pr[i].pose.y_m, pa[i].pose.y_m);
      EXPECT_EQ(pr[i].pose.yaw_rad, pa[i].pose.yaw_rad);
    }
  }
  // The seed is really used: another seed explores differently.
  const bool same_search = other.iterations == a.iterations && other.raw_states == a.raw_states &&
                           other.waypoints.size() == a.waypoints.size() &&
                           std::equal(other.waypoints.begin(), other.waypoints.end(), a.waypoints.begin(),
                                      [](const Pose2& u, const Pose2& v) { return u.x_m == v.x_m && u.y_m == v.y_m; });
  EXPECT_FALSE(same_search);
}

TEST(LocalPlannerTest, ReversesWhenTheGoalIsBehind) {
  // Facing -x, goal 8 m along +x with the same heading: the shortest Reeds-Shepp path backs up.
  const LocalPlanner planner(LocalPlanner::Config{});
  const Pose2 start{-5.0, 0.0, kPi};  // +pi must be accepted and normalised to -pi
  const Pose2 goal{3.0, 0.0, -kPi};
  const PlanResult result = planner.Plan(FlatMap(), start, goal);
  ExpectWellFormed(result, FlatMap(), planner, start, goal);
  ASSERT_EQ(result.path.segments().size(), 1u);
  EXPECT_EQ(result.path.segments().front().direction, Direction::kReverse);
  EXPECT_NEAR(result.path.Length(), 8.0, 0.05);
  EXPECT_EQ(result.path.Poses().front().pose.yaw_rad, -kPi);
}

TEST(LocalPlannerTest, SidewaysGoalNeedsCusps) {
  // The goal 1.5 m to the left with the same heading: far closer than the turning radius allows
  // without reversing.
  const LocalPlanner planner(LocalPlanner::Config{});
  const Pose2 start{-3.0, 0.0, 0.0};
  const Pose2 goal{-3.0, 1.5, 0.0};
  const PlanResult result = planner.Plan(FlatMap(), start, goal);
  ExpectWellFormed(result, FlatMap(), planner, start, goal);
  EXPECT_GE(result.path.NumCusps(), 1);
}

TEST(LocalPlannerTest, AGoalWithOtherHeadingsArrivesAtAnyOfThem) {
  // The sideways goal again, with the heading straight from the start to it as a goal too: the
  // path arrives with one of the two headings, and the direct one needs no cusp.
  const LocalPlanner planner(LocalPlanner::Config{});
  const Pose2 start{-3.0, 0.0, 0.0};
  const Pose2 goal{-1.0, 1.5, 0.0};
  const double direct = std::atan2(1.5, 2.0);
  const PlanResult result = planner.Plan(FlatMap(), start, goal, {direct});
  ASSERT_TRUE(result.found()) << PlanStatusName(result.status);
  const Pose2 end = result.path.Poses().back().pose;
  EXPECT_NEAR(end.x_m, goal.x_m, 1e-6);
  EXPECT_NEAR(end.y_m, goal.y_m, 1e-6);
  const bool either = std::abs(NormalizeYaw(end.yaw_rad - goal.yaw_rad)) < 1e-6 || std::abs(NormalizeYaw(end.yaw_rad - direct)) < 1e-6;
  EXPECT_TRUE(either) << end.yaw_rad;
  // A goal position whose given heading is blocked but another is not is still a goal.
  const Pose2 blocked{-3.5, 0.5, 0.0};  // its box reaches the posts; turned round it does not
  ASSERT_EQ(CheckPose(*Posts().map, VehicleBox{}, blocked), PoseCheck::kCollision);
  ASSERT_EQ(CheckPose(*Posts().map, VehicleBox{}, Pose2{-3.5, 0.5, kPi}), PoseCheck::kValid);
  const PlanResult only = planner.Plan(*Posts().map, Posts().spec.start, blocked);
  EXPECT_EQ(only.status, PlanStatus::kGoalInvalid);
  const PlanResult turned = planner.Plan(*Posts().map, Posts().spec.start, blocked, {kPi});
  EXPECT_NE(turned.status, PlanStatus::kGoalInvalid);
}

TEST(LocalPlannerTest, PathBlockedAfterAMapUpdateIsDetected) {
  const LocalPlanner planner(LocalPlanner::Config{});
  const PlanResult result = planner.Plan(FlatMap(), kStart, kGoal);
  ASSERT_TRUE(result.found());
  EXPECT_FALSE(planner.FirstInvalidPose(FlatMap(), result.path).has_value());
  // The same straight path on the map with posts across it.
  const auto blocked = planner.FirstInvalidPose(*Posts().map, result.path);
  ASSERT_TRUE(blocked.has_value());
  const PathPose& p = result.path.Poses()[*blocked];  // stored poses: the reference stays valid
  // The first invalid pose is where the box front (2.45 m ahead of the rear axle) meets the posts at
  // x = -1.35, or the non-traversable ground around them (up to a metre wide here, where the posts
  // hide the ground from the viewpoint).
  EXPECT_GT(p.pose.x_m, -1.35 - 2.45 - 1.3);
  EXPECT_LT(p.pose.x_m, -1.35 - 2.45 + 0.1);
  const PoseCheck check = CheckPose(*Posts().map, planner.box(), p.pose);
  EXPECT_TRUE(check == PoseCheck::kCollision || check == PoseCheck::kGroundUnderFootprint) << PoseCheckName(check);
  // Past the posts the path is valid again.
  const std::size_t last = result.path.Poses().size() - 1;
  EXPECT_FALSE(planner.FirstInvalidPose(*Posts().map, result.path, last).has_value());
}

TEST(LocalPlannerTest, TinyBudgetGivesNoPathNotACrash) {
  LocalPlanner::Config config;
  config.max_iterations = 1;
  const PlanResult result = LocalPlanner(config).Plan(*Posts().map, Posts().spec.start, Posts().spec.goal);
  EXPECT_EQ(result.status, PlanStatus::kNoPath);
  EXPECT_TRUE(result.path.empty());
  EXPECT_EQ(result.iterations, 1u);
}

TEST(LocalPlannerTest, InvalidConfigThrowsNamingTheField) {
  LocalPlanner::Config config;
  VehicleModel vehicle;
  vehicle.turning_radius_m = -1.0;
  try {
    LocalPlanner planner(config, vehicle);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("turning_radius_m"), std::string::npos);
  }
  vehicle = VehicleModel{};
  vehicle.width_m = 0.0;
  EXPECT_THROW(LocalPlanner(config, vehicle), std::invalid_argument);
  config.vehicle.margin_m = -1.0;
  EXPECT_THROW(LocalPlanner{config}, std::invalid_argument);
  config = LocalPlanner::Config{};
  config.max_iterations = 0;
  EXPECT_THROW(LocalPlanner{config}, std::invalid_argument);
}

TEST(LocalPlannerTest, OmplIsSeededOncePerProcess) {
  const std::uint32_t seed = SeedOmplOnce(12345);
  EXPECT_EQ(SeedOmplOnce(999), seed);  // later calls do not change it
}

}  // namespace
}  // namespace ovpc::planner
