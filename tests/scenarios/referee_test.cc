// The referee on made-up poses: the terrain's edge, forbidden regions.
#include "ovpc/scenarios/referee.h"

#include <algorithm>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

Eigen::Isometry3d At(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Vec3(x, y, 0.0);
  T.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  return T;
}

bool CriterionPassed(const RunResult& r, const std::string& name) {
  const auto it = std::find_if(r.criteria.begin(), r.criteria.end(), [&](const CriterionResult& c) { return c.name == name; });
  EXPECT_NE(it, r.criteria.end()) << name;
  return it != r.criteria.end() && it->passed;
}

TEST(RefereeTest, AVehicleOverTheTerrainsEdgeHasLeftItAndFails) {
  Scenario s;
  s.sim.world.terrain.size_x_m = 20.0;  // x and y within +-10 m
  s.sim.world.terrain.size_y_m = 20.0;
  s.route_m = {{0.0, 0.0}, {8.0, 0.0}};
  const sim::GatorParams gator;
  Referee referee(s, gator, At(0.0, 0.0, 0.0));
  referee.Observe(1.0, At(7.0, 0.0, 0.0), {});  // the front wheels at 7 + 1.9 m: on the terrain
  EXPECT_FALSE(referee.OffTerrain());
  referee.Observe(1.5, At(7.9, 0.0, 0.0), {});  // the front bumper (at 10.25 m) overhangs: it stands
  EXPECT_FALSE(referee.OffTerrain());
  RunResult on;
  referee.Score(&on);
  EXPECT_TRUE(CriterionPassed(on, "on_terrain"));
  // Reversing over the edge at the side: a rear wheel leaves first.
  referee.Observe(2.0, At(7.0, 9.95, -kPi / 2 - 0.3), {});  // the left rear wheel at y = 10.13
  EXPECT_TRUE(referee.OffTerrain());
  referee.Observe(3.0, At(0.0, 0.0, 0.0), {});  // once off, off: the vehicle fell
  EXPECT_TRUE(referee.OffTerrain());
  RunResult off;
  referee.Score(&off);
  EXPECT_FALSE(CriterionPassed(off, "on_terrain"));
  EXPECT_FALSE(off.passed);
}

TEST(RefereeTest, AForbiddenRegionIsEnteredByTheFootprintOrOnlyByAWheel) {
  // A ditch between x = 10 and 12 across the route; the vehicle stops with its front wheels at
  // 9.9 m and its front bumper 0.45 m further, over the ditch's edge.
  Scenario s;
  s.route_m = {{0.0, 0.0}, {20.0, 0.0}};
  s.criteria.forbidden.push_back(Region{"footprint", Vec3(10.0, -20.0, 0.0).head<2>(), Vec3(12.0, 20.0, 0.0).head<2>()});
  Region wheels{"wheels", Vec3(10.0, -20.0, 0.0).head<2>(), Vec3(12.0, 20.0, 0.0).head<2>()};
  wheels.by = Region::By::kWheels;
  s.criteria.forbidden.push_back(wheels);
  const sim::GatorParams gator;
  Referee referee(s, gator, At(0.0, 0.0, 0.0));
  referee.Observe(1.0, At(8.0, 0.0, 0.0), {});
  RunResult overhang;
  referee.Score(&overhang);
  EXPECT_FALSE(CriterionPassed(overhang, "never_enter:footprint"));
  EXPECT_TRUE(CriterionPassed(overhang, "never_enter:wheels"));
  referee.Observe(2.0, At(8.2, 0.0, 0.0), {});  // the front wheels at 10.1 m: in it
  RunResult in;
  referee.Score(&in);
  EXPECT_FALSE(CriterionPassed(in, "never_enter:wheels"));
}

// A route that comes back beside itself: a vehicle that turns back early and crosses to the return
// lane is scored from where it rejoins the route, so min_progress holds when it drives the rest.
TEST(RefereeTest, ACutUTurnIsScoredFromWhereTheVehicleRejoinsTheRoute) {
  Scenario s;
  s.sim.world.terrain.size_x_m = 60.0;
  s.sim.world.terrain.size_y_m = 60.0;
  s.route_m = {{0.0, 0.0}, {18.0, 0.0}, {18.0, 8.0}, {0.0, 8.0}};
  s.criteria.min_progress_m = 40.0;
  const sim::GatorParams gator;
  Referee referee(s, gator, At(0.0, 0.0, 0.0));
  double t = 0.0;
  const auto drive = [&](Eigen::Vector2d a, Eigen::Vector2d b, double yaw) {
    for (int i = 1; i <= 100; ++i) {
      const Eigen::Vector2d p = a + (b - a) * (i / 100.0);
      referee.Observe(t += 0.1, At(p.x(), p.y(), yaw), {});
    }
  };
  drive({0.0, 0.0}, {8.0, 0.0}, 0.0);
  drive({8.0, 0.0}, {8.0, 8.0}, kPi / 2);
  drive({8.0, 8.0}, {0.0, 8.0}, kPi);
  RunResult r;
  referee.Score(&r);
  EXPECT_NEAR(r.route_progress_m, 44.0, 1e-6);
  EXPECT_TRUE(CriterionPassed(r, "min_progress"));
}

TEST(RefereeTest, ALapsGoalAtItsStartCountsOnlyAfterTheLap) {
  Scenario s;
  s.sim.world.terrain.size_x_m = 60.0;
  s.sim.world.terrain.size_y_m = 60.0;
  s.route_m = {{0.0, 0.0}, {10.0, 0.0}, {10.0, 10.0}, {0.0, 10.0}, {0.0, 0.0}};
  s.criteria.goal_m = Eigen::Vector2d(0.0, 0.0);
  s.criteria.goal_radius_m = 1.5;
  const sim::GatorParams gator;
  Referee referee(s, gator, At(0.0, 0.0, 0.0));
  double t = 0.0;
  EXPECT_FALSE(referee.GoalReached(t, At(0.0, 0.0, 0.0))) << "at the start, before the lap";
  {
    RunResult before;
    referee.Score(&before);
    ASSERT_FALSE(before.criteria.empty());
    EXPECT_EQ(before.criteria.front().actual, "no, 0.0 m away, but it followed the route only 0.0 of the goal's 40.0 m")
        << "at the goal's place but not along the route: the score says why";
  }
  const auto drive = [&](Eigen::Vector2d a, Eigen::Vector2d b, double yaw) {
    bool reached = false;
    for (int i = 1; i <= 100; ++i) {
      const Eigen::Vector2d p = a + (b - a) * (i / 100.0);
      referee.Observe(t += 0.1, At(p.x(), p.y(), yaw), {});
      reached = reached || referee.GoalReached(t, At(p.x(), p.y(), yaw));
    }
    return reached;
  };
  EXPECT_FALSE(drive({0.0, 0.0}, {10.0, 0.0}, 0.0));
  EXPECT_FALSE(drive({10.0, 0.0}, {10.0, 10.0}, kPi / 2));
  EXPECT_FALSE(drive({10.0, 10.0}, {0.0, 10.0}, kPi));
  EXPECT_TRUE(drive({0.0, 10.0}, {0.0, 0.0}, -kPi / 2)) << "back at the start after the lap";
  RunResult r;
  referee.Score(&r);
  EXPECT_TRUE(CriterionPassed(r, "goal_reached"));
}

}  // namespace
}  // namespace ovpc::scenarios
