// The OVPC map backend's memory of ground (Config::ground_memory_s): kept in the odometry frame
// across updates whose frame L moves, judged only where the present map has no point, forgotten
// after its time.
#include "ovpc/navigation/ovpc_map_backend.h"

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/planner/planning_map.h"

namespace ovpc::navigation {
namespace {

using planner::Pose2;
using planner::PoseCheck;

// Flat ground 1.9 m below the sensor, every 0.1 m within 8 m of the point (x0, 0) of frame O, seen
// from a sensor at `sensor_x` in O (frame L is O shifted to it); none in the hole -2.2 < x < -0.8
// of O, |y| < 1.5, when `hole`.
Points GroundL(double sensor_x, bool hole) {
  Points points_L;
  for (int i = -80; i <= 80; ++i) {
    for (int j = -80; j <= 80; ++j) {
      const double x = 0.1 * i, y = 0.1 * j;
      if (x * x + y * y > 64.0) continue;
      if (hole && x > -2.2 && x < -0.8 && std::abs(y) < 1.5) continue;
      // A little relief so that the hull is not degenerate.
      points_L.emplace_back(x - sensor_x, y, -1.9 + 0.01 * std::sin(3.0 * x) * std::cos(2.0 * y));
    }
  }
  return points_L;
}

MapContext At(double sensor_x, double time_s) {
  MapContext context;
  context.T_L_B.translation() = Vec3(0.0, 0.0, -1.9);
  context.L_in_O = Vec3(sensor_x, 0.0, 0.0);
  context.time_s = time_s;
  return context;
}

TEST(OvpcMapBackendTest, RememberedGroundCarriesWheelsWhereTheMapHasNone) {
  planner::VehicleBox wheels;
  wheels.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
  wheels.wheel_support_m = 0.35;
  // In O the rear wheels stand at (-1.5, +-0.6), in the hole's middle; frame L sits 0.5 m on.
  const Pose2 pose_L{-1.5 - 0.5, 0.0, 0.0};
  for (const double memory_s : {0.0, 20.0}) {
    OvpcMapBackend::Config config;
    config.ground_memory_s = memory_s;
    OvpcMapBackend backend(config);
    ASSERT_NE(backend.Update(GroundL(0.0, false), At(0.0, 0.0)), nullptr);  // the hole seen
    const auto later = backend.Update(GroundL(0.5, true), At(0.5, 1.0));    // not seen now
    ASSERT_NE(later, nullptr);
    EXPECT_EQ(planner::CheckPose(*later, wheels, pose_L), memory_s > 0.0 ? PoseCheck::kValid : PoseCheck::kUnseenGround)
        << memory_s;
    if (memory_s > 0.0) {
      // Beyond the memory's time the hole is unseen ground again.
      const auto forgotten = backend.Update(GroundL(0.5, true), At(0.5, 25.0));
      ASSERT_NE(forgotten, nullptr);
      EXPECT_EQ(planner::CheckPose(*forgotten, wheels, pose_L), PoseCheck::kUnseenGround);
    }
  }
  OvpcMapBackend::Config bad;
  bad.ground_memory_s = -1.0;
  EXPECT_THROW(OvpcMapBackend{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::navigation
