// Rollout: what the pure-pursuit follower drives along a path on the kinematic bicycle model.
#include "ovpc/controller/rollout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "follow_support.h"

namespace ovpc::controller {
namespace {

using namespace testing;  // NOLINT: the support helpers

std::vector<Pose2> Roll(const Path& path, const BicycleModel::State& start) {
  return Rollout(PurePursuit::Config{}, BicycleModel(BicycleModel::Config{}), path, start, 0.02, 0.1, 120.0);
}

double MaxDistanceToPath(const Path& path, const std::vector<Pose2>& poses) {
  double worst = 0.0;
  for (const Pose2& p : poses) worst = std::max(worst, DistanceToPolyline(path.Poses(), {p.x_m, p.y_m}));
  return worst;
}

TEST(RolloutTest, OnAStraightPathThePosesAreThePathsSpacedAsAsked) {
  const Path path({Straight(Direction::kForward, {0.0, 0.0}, {10.0, 0.0})});
  const std::vector<Pose2> poses = Roll(path, At(0.0, 0.0, 0.0));
  ASSERT_GT(poses.size(), 90u);
  EXPECT_EQ(poses.front().x_m, 0.0);
  for (std::size_t i = 1; i + 1 < poses.size(); ++i) {
    const double step = std::hypot(poses[i].x_m - poses[i - 1].x_m, poses[i].y_m - poses[i - 1].y_m);
    EXPECT_GE(step, 0.1 - 1e-9);
    EXPECT_LT(step, 0.13);  // one control step more at 1 m/s
  }
  EXPECT_LT(MaxDistanceToPath(path, poses), 1e-6);
  EXPECT_NEAR(poses.back().x_m, 10.0, 0.15) << "it stops at the end";
}

TEST(RolloutTest, ASharpCornerIsOvershotAndAShortCuspSegmentIsSkipped) {
  // 6 m along x, then a right-angle turn to the left into +y: sharper than the 3.3 m full-lock
  // circle, so the vehicle swings out beyond the corner.
  PathSegment corner = Straight(Direction::kForward, {0.0, 0.0}, {6.0, 0.0});
  const PathSegment up = Straight(Direction::kForward, {6.0, 0.0}, {6.0, 8.0});
  corner.poses.insert(corner.poses.end(), up.poses.begin() + 1, up.poses.end());
  const std::vector<Pose2> turned = Roll(Path({corner}), At(0.0, 0.0, 0.0));
  double max_x = -1e9;
  for (const Pose2& p : turned) max_x = std::max(max_x, p.x_m);
  EXPECT_GT(max_x, 7.0) << "the rear axle swings more than a metre past the corner";
  EXPECT_NEAR(turned.back().y_m, 8.0, 0.3);

  // 4 m forward, 0.08 m back (less than the 0.1 m stop tolerance), 4 m forward: the follower stops
  // at the cusp and drives on without backing up.
  const Path cusps({Straight(Direction::kForward, {0.0, 0.0}, {4.0, 0.0}),
                    Straight(Direction::kReverse, {4.0, 0.0}, {3.92, 0.0}),
                    Straight(Direction::kForward, {3.92, 0.0}, {8.0, 0.0})});
  const std::vector<Pose2> skipped = Roll(cusps, At(0.0, 0.0, 0.0));
  for (std::size_t i = 1; i < skipped.size(); ++i) EXPECT_GE(skipped[i].x_m, skipped[i - 1].x_m - 1e-9);
  EXPECT_NEAR(skipped.back().x_m, 8.0, 0.15);
  // A reverse segment of a metre is driven.
  const Path back({Straight(Direction::kForward, {0.0, 0.0}, {4.0, 0.0}),
                   Straight(Direction::kReverse, {4.0, 0.0}, {3.0, 0.0}),
                   Straight(Direction::kForward, {3.0, 0.0}, {8.0, 0.0})});
  const std::vector<Pose2> driven = Roll(back, At(0.0, 0.0, 0.0));
  double least_after_cusp = 1e9;
  bool past_cusp = false;
  for (const Pose2& p : driven) {
    past_cusp |= p.x_m > 3.85;
    if (past_cusp) least_after_cusp = std::min(least_after_cusp, p.x_m);
  }
  EXPECT_LT(least_after_cusp, 3.2);
}

TEST(RolloutTest, StartsFromTheGivenSpeedAndSteering) {
  // Moving at 1 m/s with full left lock onto a straight path along x: the first metre curves left.
  const Path path({Straight(Direction::kForward, {0.0, 0.0}, {10.0, 0.0})});
  BicycleModel::State start = At(0.0, 0.0, 0.0);
  start.speed_mps = 1.0;
  start.steering_rad = DegToRad(30.0);
  const BicycleModel::Config slow_steering;  // 60 deg/s
  const std::vector<Pose2> poses =
      Rollout(PurePursuit::Config{}, BicycleModel(slow_steering), path, start, 0.02, 0.1, 60.0);
  EXPECT_GT(MaxDistanceToPath(path, poses), 0.02) << "standing with straight wheels it stays on the line";
  EXPECT_GT(poses[5].y_m, 0.0);
}

TEST(RolloutTest, BadArgumentsThrow) {
  const Path path({Straight(Direction::kForward, {0.0, 0.0}, {1.0, 0.0})});
  const BicycleModel model(BicycleModel::Config{});
  EXPECT_THROW(Rollout(PurePursuit::Config{}, model, path, At(0, 0, 0), 0.0, 0.1, 1.0), std::invalid_argument);
  EXPECT_THROW(Rollout(PurePursuit::Config{}, model, path, At(0, 0, 0), 0.02, -1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(Rollout(PurePursuit::Config{}, model, path, At(0, 0, 0), 0.02, 0.1, INFINITY),
               std::invalid_argument);
  EXPECT_EQ(Rollout(PurePursuit::Config{}, model, Path{}, At(1, 2, 0), 0.02, 0.1, 1.0).size(), 1u)
      << "an empty path: the vehicle stays where it is";
}

}  // namespace
}  // namespace ovpc::controller
