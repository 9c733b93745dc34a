// Real closed-loop runs: short ones, so that they fit the unit label.
#include "ovpc/scenarios/closed_loop.h"

#include <algorithm>

#include <random>

#include <gtest/gtest.h>

#include "../support/test_scenarios.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios {
namespace {

const char* const kShort = ovpc::testing::kShortFlatScenario;

TEST(ClosedLoopTest, SameScenarioAndSeedGiveABitIdenticalTrajectory) {
  const Scenario s = ParseScenario(kShort, "short.yaml", {"time_limit_s=4"});
  const RunResult a = RunClosedLoop(s, 7, RunOptions{});
  const RunResult b = RunClosedLoop(s, 7, RunOptions{});
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  ASSERT_GT(a.trajectory.size(), 10u);
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    ASSERT_EQ(a.trajectory[i].T_W_B.matrix(), b.trajectory[i].T_W_B.matrix()) << "row " << i;
    ASSERT_EQ(a.trajectory[i].cmd_steering_rad, b.trajectory[i].cmd_steering_rad);
    ASSERT_EQ(a.trajectory[i].cmd_speed_mps, b.trajectory[i].cmd_speed_mps);
  }
  EXPECT_GT(a.distance_m, 0.5) << "the vehicle should have set off";
}

TEST(ClosedLoopTest, ReachesAGoalOnFlatGroundAndScoresIt) {
  const Scenario s = ParseScenario(kShort, "short.yaml");
  const RunResult r = RunClosedLoop(s, 1, RunOptions{});
  EXPECT_TRUE(r.passed) << r.end_reason;
  EXPECT_EQ(r.end_reason, "goal reached");
  EXPECT_EQ(r.collision_steps, 0u);
  ASSERT_FALSE(r.criteria.empty());
  EXPECT_EQ(r.criteria.front().name, "goal_reached");
}

TEST(ClosedLoopTest, IsolatedPointsNearTheSensorAreDroppedOthersKept) {
  Points cloud;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) cloud.emplace_back(2.0 + 0.1 * i, -1.0 + 0.1 * j, -1.9);  // ground
  }
  for (int k = 0; k < 8; ++k) cloud.emplace_back(6.0, 1.0, -1.9 + 0.2 * k);  // a thin post, hit every 0.2 m
  const Vec3 floating(3.0, 0.5, 0.2), far_floating(20.0, 3.0, 1.0), pair_a(4.0, -2.0, 0.5), pair_b(4.1, -2.05, 0.55);
  cloud.insert(cloud.begin() + 5, floating);
  cloud.push_back(far_floating);
  cloud.push_back(pair_a);
  cloud.push_back(pair_b);
  Points out = cloud;
  navigation::DropIsolatedPoints(0.25, 12.0, &out);
  EXPECT_EQ(out.size(), cloud.size() - 1);  // only the lone point within 12 m
  EXPECT_EQ(std::count(out.begin(), out.end(), floating), 0);
  EXPECT_EQ(std::count(out.begin(), out.end(), far_floating), 1);  // beyond the reach
  EXPECT_EQ(std::count(out.begin(), out.end(), pair_a), 1);        // two together are not alone
  EXPECT_EQ(out[5], cloud[6]);                                      // order kept
  Points off = cloud;
  navigation::DropIsolatedPoints(0.0, 12.0, &off);
  EXPECT_EQ(off, cloud);
  Points empty;
  navigation::DropIsolatedPoints(0.25, 12.0, &empty);
  EXPECT_TRUE(empty.empty());
}

TEST(ClosedLoopTest, IsolatedPointFilterAgreesWithABruteForceSearch) {
  // Clusters and scattered points, some beyond the reach, some on cell edges (multiples of 0.25).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-15.0, 15.0), near(-0.3, 0.3);
  Points cloud;
  for (int i = 0; i < 1500; ++i) cloud.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  for (int i = 0; i < 1500; ++i) {
    const Vec3& c = cloud[static_cast<std::size_t>(i) % 300];
    cloud.push_back(c + Vec3(near(rng), near(rng), near(rng)));
  }
  for (int i = 0; i < 40; ++i) cloud.emplace_back(0.25 * i, -0.25 * i, 0.25 * (i % 3));
  Points expected;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    bool neighbour = cloud[i].squaredNorm() > 12.0 * 12.0;
    for (std::size_t j = 0; j < cloud.size() && !neighbour; ++j) {
      neighbour = j != i && (cloud[j] - cloud[i]).squaredNorm() <= 0.25 * 0.25;
    }
    if (neighbour) expected.push_back(cloud[i]);
  }
  Points out = cloud;
  navigation::DropIsolatedPoints(0.25, 12.0, &out);
  EXPECT_EQ(out, expected);
  EXPECT_LT(out.size(), cloud.size());  // something was dropped
}

TEST(ClosedLoopTest, AnImpossibleDeadlineFails) {
  const Scenario s = ParseScenario(kShort, "short.yaml", {"criteria.max_time_s=1", "time_limit_s=3"});
  const RunResult r = RunClosedLoop(s, 1, RunOptions{});
  EXPECT_FALSE(r.passed);
}

}  // namespace
}  // namespace ovpc::scenarios
