#include "ovpc/controller/pure_pursuit.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "follow_support.h"

namespace ovpc::controller {
namespace {

using namespace testing;  // NOLINT: the support helpers

double Last(const std::vector<Step>& log, const Eigen::Vector2d& goal) {
  return (Position(log.back().state) - goal).norm();
}

TEST(PurePursuitTest, SettlesOnAStraightLineAndStopsAtItsEnd) {
  const Path path({Straight(Direction::kForward, {0.0, 0.0}, {40.0, 0.0})});
  const std::vector<Step> log = Follow(path, At(0.0, 0.6, 0.2), 90.0);  // off the line and askew
  ASSERT_TRUE(log.back().command.done);
  double max_error = 0.0, max_speed = 0.0;
  for (const Step& s : log) {
    max_speed = std::max(max_speed, s.state.speed_mps);
    if (s.state.pose.x_m > 10.0) max_error = std::max(max_error, std::abs(s.state.pose.y_m));
  }
  EXPECT_LT(max_error, 0.05);
  EXPECT_NEAR(max_speed, 1.0, 0.02);  // the paper's 1 m/s
  EXPECT_LT(Last(log, {40.0, 0.0}), 0.3);
  EXPECT_LT(std::abs(log.back().state.speed_mps), 1e-3);
  EXPECT_LT(log.back().t_s, 50.0);
}

TEST(PurePursuitTest, SettlesOnA6mCircle) {
  const Path path({Arc(Direction::kForward, {0.0, 6.0}, 6.0, -kPi / 2, 2.5 * kPi)});
  const std::vector<Step> log = Follow(path, At(0.0, -0.3, 0.0), 80.0);
  ASSERT_TRUE(log.back().command.done);
  const auto poses = path.Poses();
  double max_error = 0.0;
  int checked = 0;
  for (const Step& s : log) {
    if (s.t_s < 10.0 || s.command.done) continue;  // settled after a quarter lap, still moving
    max_error = std::max(max_error, DistanceToPolyline(poses, Position(s.state)));
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_LT(max_error, 0.15);
  EXPECT_LT(Last(log, {poses.back().pose.x_m, poses.back().pose.y_m}), 0.3);
}

TEST(PurePursuitTest, FollowsAReverseSegmentBackwards) {
  // Backing up: 3 m straight, a 45 deg arc of radius 8 m to the left (seen in the direction of
  // travel), 3 m straight.
  PathSegment reverse{Direction::kReverse, {}};
  for (const PathSegment& piece : {Straight(Direction::kReverse, {0.0, 0.0}, {-3.0, 0.0}),
                                   Arc(Direction::kReverse, {-3.0, -8.0}, 8.0, kPi / 2, kPi / 4)}) {
    reverse.poses.insert(reverse.poses.end(), piece.poses.begin() + (reverse.poses.empty() ? 0 : 1),
                         piece.poses.end());
  }
  const Eigen::Vector2d arc_end(reverse.poses.back().pose.x_m, reverse.poses.back().pose.y_m);
  const Eigen::Vector2d away = arc_end + 3.0 * Eigen::Vector2d(-std::cos(kPi / 4), -std::sin(kPi / 4));
  const PathSegment tail = Straight(Direction::kReverse, arc_end, away);
  reverse.poses.insert(reverse.poses.end(), tail.poses.begin() + 1, tail.poses.end());
  const Path path({reverse});
  ASSERT_NEAR(reverse.poses.front().pose.yaw_rad, 0.0, 1e-6);  // facing +x, driving towards -x

  const std::vector<Step> log = Follow(path, At(0.0, 0.2, 0.0), 60.0);
  ASSERT_TRUE(log.back().command.done);
  const auto poses = path.Poses();
  double max_error = 0.0, max_forward = 0.0;
  for (const Step& s : log) {
    EXPECT_LE(s.command.speed_mps, 0.0);
    max_forward = std::max(max_forward, s.state.speed_mps);
    if (s.t_s > 8.0) max_error = std::max(max_error, DistanceToPolyline(poses, Position(s.state)));
  }
  EXPECT_LE(max_forward, 0.0);
  EXPECT_LT(max_error, 0.15);
  EXPECT_LT(Last(log, away), 0.3);
  // The vehicle still faces roughly away from the direction of travel.
  EXPECT_NEAR(std::abs(std::remainder(log.back().state.pose.yaw_rad - kPi / 4, 2 * kPi)), 0.0, 0.15);
}

TEST(PurePursuitTest, StopsAtACuspBeforeReversing) {
  const Path path({Straight(Direction::kForward, {0.0, 0.0}, {8.0, 0.0}),
                   Arc(Direction::kReverse, {8.0, 8.0}, 8.0, -kPi / 2, -kPi / 8)});
  const Eigen::Vector2d goal(path.Poses().back().pose.x_m, path.Poses().back().pose.y_m);
  const std::vector<Step> log = Follow(path, At(0.0, 0.0, 0.0), 60.0);
  ASSERT_TRUE(log.back().command.done);
  double max_x = -1e9;
  int sign_changes = 0;
  double previous = 0.0;
  for (const Step& s : log) {
    max_x = std::max(max_x, s.state.pose.x_m);
    const double v = s.state.speed_mps;
    if (std::abs(v) > 1e-6) {
      if (previous != 0.0 && (v > 0) != (previous > 0)) ++sign_changes;
      previous = v;
    }
  }
  EXPECT_NEAR(max_x, 8.0, 0.3);  // stopped at the cusp
  EXPECT_EQ(sign_changes, 1);    // forward once, then backwards
  EXPECT_LT(Last(log, goal), 0.3);
}

TEST(PurePursuitTest, SlowerInTightCurvesAndSteeringClamped) {
  const Path straight({Straight(Direction::kForward, {0.0, 0.0}, {30.0, 0.0})});
  PurePursuit on_straight(PurePursuit::Config{}, straight);
  const Command fast = on_straight.Update(Pose2{5.0, 0.0, 0.0}, 1.0);
  EXPECT_NEAR(fast.speed_mps, 1.0, 1e-12);
  EXPECT_NEAR(fast.steering_rad, 0.0, 1e-9);

  const Path tight({Arc(Direction::kForward, {0.0, 4.0}, 4.0, -kPi / 2, kPi)});
  PurePursuit on_tight(PurePursuit::Config{}, tight);
  const Command slow = on_tight.Update(Pose2{0.0, 0.0, 0.0}, 1.0);
  EXPECT_LT(slow.speed_mps, 0.95);
  EXPECT_GT(slow.speed_mps, 0.5);
  EXPECT_GT(slow.steering_rad, 0.0);  // left

  // A path turning far tighter than the vehicle can: the command stays at the steering limit.
  const Path corner({Arc(Direction::kForward, {0.0, 1.0}, 1.0, -kPi / 2, kPi / 2)});
  PurePursuit on_corner(PurePursuit::Config{}, corner);
  const Command clamped = on_corner.Update(Pose2{0.0, 0.0, 0.0}, 1.0);
  EXPECT_NEAR(clamped.steering_rad, SteeringGeometry{}.max_steering_rad, 1e-12);
}

TEST(PurePursuitTest, SteersBeforeSettingOff) {
  const Path tight({Arc(Direction::kForward, {0.0, 4.0}, 4.0, -kPi / 2, kPi / 2)});
  PurePursuit follower(PurePursuit::Config{}, tight);
  const Command wait = follower.Update(Pose2{0.0, 0.0, 0.0}, 0.0, 0.0);  // wheels straight
  EXPECT_GT(wait.steering_rad, 0.3);
  EXPECT_EQ(wait.speed_mps, 0.0);
  const Command go = follower.Update(Pose2{0.0, 0.0, 0.0}, 0.0, wait.steering_rad);  // wheels turned
  EXPECT_GT(go.speed_mps, 0.0);
  // Without a measured angle, or once moving, it does not wait.
  EXPECT_GT(follower.Update(Pose2{0.0, 0.0, 0.0}, 0.0).speed_mps, 0.0);
  EXPECT_GT(follower.Update(Pose2{0.0, 0.0, 0.0}, 0.5, 0.0).speed_mps, 0.0);
}

TEST(PurePursuitTest, RepeatedPosesAreHarmless) {
  PathSegment straight = Straight(Direction::kForward, {0.0, 0.0}, {5.0, 0.0});
  straight.poses.push_back(straight.poses.back());  // the end twice
  straight.poses.insert(straight.poses.begin(), straight.poses.front());
  const Path path({straight});
  const std::vector<Step> log = Follow(path, At(0.0, 0.0, 0.0), 30.0);
  ASSERT_TRUE(log.back().command.done);
  for (const Step& s : log) ASSERT_TRUE(std::isfinite(s.command.steering_rad) && std::isfinite(s.command.speed_mps));
  EXPECT_LT(Last(log, {5.0, 0.0}), 0.3);
}

TEST(PurePursuitTest, EmptyPathIsDoneAtOnce) {
  PurePursuit follower(PurePursuit::Config{}, Path{});
  EXPECT_TRUE(follower.done());
  const Command c = follower.Update(Pose2{}, 0.0);
  EXPECT_TRUE(c.done);
  EXPECT_EQ(c.speed_mps, 0.0);
}

TEST(PurePursuitTest, InvalidConfigThrowsNamingTheField) {
  PurePursuit::Config config;
  config.lookahead_max_m = 0.5;  // below the minimum
  try {
    PurePursuit follower(config, Path{});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lookahead_max_m"), std::string::npos);
  }
  SteeringGeometry steering;
  steering.max_steering_rad = 2.0;
  EXPECT_THROW(PurePursuit(PurePursuit::Config{}, Path{}, steering), std::invalid_argument);
  steering = SteeringGeometry::Of(VehicleModel{});
  EXPECT_NO_THROW(PurePursuit(PurePursuit::Config{}, Path{}, steering));
  steering.wheelbase_m = 0.0;
  EXPECT_THROW(PurePursuit(PurePursuit::Config{}, Path{}, steering), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::controller
