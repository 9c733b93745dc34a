// Closed-loop runs of the comparison backends (docs/BACKENDS.md) on the scenario that tells a 2.5D
// map from a 3D one: underpass_2p5, whose only way on is under a 2.5 m roof. CTest label scenario
// (about 20 s of CPU), so CI runs them with the suite and the sanitizer pass leaves them out.
#include <string>

#include <gtest/gtest.h>

#include "ovpc/scenarios/closed_loop.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios {
namespace {

RunResult RunUnderpass(const std::string& map) {
  const std::string file = std::string(OVPC_SOURCE_DIR) + "/scenarios/underpass_2p5.yaml";
  const Scenario s = LoadScenario(file, {"navigator.map=" + map});
  return RunClosedLoop(s, 1, RunOptions{});
}

// The elevation map reads the roof's height over the ground under it: the opening is a wall of the
// roof's height to it, so the vehicle never gets past the wall at x = 12 m, and never touches it.
TEST(BackendRunsTest, TheElevationMapFindsNoWayUnderTheRoof) {
  const RunResult r = RunUnderpass("elevation");
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.end_reason, "time limit");
  EXPECT_LT(r.route_progress_m, 12.0);
  EXPECT_EQ(r.collision_steps, 0u);
}

// OctoMap finds the ground under the roof (occupied with free space above it) and drives under it.
TEST(BackendRunsTest, OctoMapDrivesUnderTheRoof) {
  const RunResult r = RunUnderpass("octomap");
  EXPECT_TRUE(r.passed) << r.end_reason;
  EXPECT_EQ(r.collision_steps, 0u);
}

}  // namespace
}  // namespace ovpc::scenarios
