// Real closed-loop runs: short ones, so that they fit the unit label.
#include "ovpc/scenarios/closed_loop.h"

#include <algorithm>
#include <filesystem>


#include <gtest/gtest.h>

#include "../support/test_scenarios.h"
#include "ovpc/scenarios/report.h"
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

// With a latency the map-and-plan cycle may run beside the simulation: the trajectory depends on
// the latency, never on the thread it ran on.
TEST(ClosedLoopTest, ALatencyGivesTheSameTrajectoryWithOneThreadOrTwo) {
  const Scenario s = ParseScenario(kShort, "short.yaml", {"time_limit_s=6", "navigator.timing.latency_s=0.1"});
  RunOptions one, two;
  two.threads = 2;
  const RunResult a = RunClosedLoop(s, 3, one);
  const RunResult b = RunClosedLoop(s, 3, two);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  ASSERT_GT(a.trajectory.size(), 10u);
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    ASSERT_EQ(a.trajectory[i].T_W_B.matrix(), b.trajectory[i].T_W_B.matrix()) << "row " << i;
    ASSERT_EQ(a.trajectory[i].cmd_steering_rad, b.trajectory[i].cmd_steering_rad);
  }
  EXPECT_EQ(a.plan_log.size(), b.plan_log.size());
  EXPECT_GT(a.distance_m, 0.5) << "the vehicle should have set off";
  // The latency is a fact of the run: without it the vehicle sets off 0.1 s earlier.
  const RunResult none =
      RunClosedLoop(ParseScenario(kShort, "short.yaml", {"time_limit_s=6", "navigator.timing.latency_s=0"}), 3, one);
  ASSERT_FALSE(none.plan_log.empty());
  const auto first_moving = [](const RunResult& r) {
    for (const auto& row : r.trajectory) {
      if (row.cmd_speed_mps > 0.0) return row.time_s;
    }
    return -1.0;
  };
  EXPECT_NEAR(first_moving(a) - first_moving(none), 0.1, 0.1 + 1e-9);
  EXPECT_GT(first_moving(a), first_moving(none));
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

TEST(ClosedLoopTest, AnImpossibleDeadlineFails) {
  const Scenario s = ParseScenario(kShort, "short.yaml", {"criteria.max_time_s=1", "time_limit_s=3"});
  const RunResult r = RunClosedLoop(s, 1, RunOptions{});
  EXPECT_FALSE(r.passed);
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

// The top-down picture's work scales with the picture, not with the world: a huge object or
// forbidden region is drawn only where the picture is (these took hours before).
TEST(ReportTest, TopDownPictureOfHugeObjectsIsDrawnOnlyWhereThePictureIs) {
  const Scenario s = ParseScenario(R"(name: huge
time_limit_s: 5
terrain: {kind: flat, size_m: [40, 20]}
objects:
  - cylinder: {x_m: 3.0, y_m: 4.0, radius_m: 100000.0, height_m: 1.0}
  - box: {x_m: 0.0, y_m: 0.0, length_m: 500000.0, width_m: 3.0}
route: [[0, 0], [5, 0]]
criteria:
  forbidden: [{name: everything, min_m: [-1e7, -1e7], max_m: [1e7, 1e7]}]
)",
                                   "huge.yaml");
  const std::string file = ::testing::TempDir() + "/huge_topdown.png";
  WriteTopdownPng(s, RunResult{}, file);
  EXPECT_GT(std::filesystem::file_size(file), 1000u);
}

}  // namespace
}  // namespace ovpc::scenarios
