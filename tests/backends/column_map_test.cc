// The comparison backends on analytic scenes ray-cast from a sensor 1.88 m above flat ground: the
// OctoMap columns find the ground under a roof and let the roof collide only with a box that reaches
// it; the 2.5D elevation map reads the roof as the height of the cells under it (its documented
// limitation). Both: a thin post collides, a ramp gives the ramp's normal, unknown space is unknown,
// and the VehicleBox rules (wheels, wheel contacts, roll limit) work through the PlanningMap.
#include <cmath>
#include <memory>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "ovpc/backends/column_map.h"
#include "ovpc/backends/elevation_columns.h"
#include "ovpc/backends/octomap_columns.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc::backends {
namespace {

using planner::PoseCheck;
using planner::Pose2;

constexpr double kSensorHeightM = 1.88;

// The scene seen from (0, 0, 1.88): rays every 0.3 deg of azimuth over the front half and every
// 0.5 deg of elevation from -50 to 0 deg (0.1 deg up to +40 deg, so that a roof is sampled as densely
// as the ground, as the spinning sensor's many scans do), up to 14 m, noise-free; hits in frame L
// (viewpoint at the origin), one per 5 cm cell (the buffer's voxel filter, roughly).
Points Scan(const synth::Scene& scene) {
  const Vec3 origin(0.0, 0.0, kSensorHeightM);
  Points points;
  std::set<std::tuple<long, long, long>> cells;
  for (double az = -90.0; az <= 90.0; az += 0.3) {
    for (double el = -50.0; el <= 40.0; el += el < 0.0 ? 0.5 : 0.1) {
      const double a = DegToRad(az), e = DegToRad(el);
      const Vec3 d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const double range = scene.Raycast(origin, d, 14.0);
      if (!std::isfinite(range)) continue;
      const Vec3 p = origin + range * d - origin;
      if (cells.insert({std::lround(std::floor(p.x() / 0.05)), std::lround(std::floor(p.y() / 0.05)),
                        std::lround(std::floor(p.z() / 0.05))})
              .second) {
        points.push_back(p);
      }
    }
  }
  return points;
}

// Ground level in frame L.
constexpr double kGroundZ = -kSensorHeightM;

ColumnMap::Config MapConfig() { return ColumnMap::Config{}; }

// The vehicle's ground in frame L.
planner::GroundContext Ground() {
  planner::GroundContext ground;
  ground.ground_reference_z_m = kGroundZ;
  return ground;
}

std::unique_ptr<ColumnMap> OctoMapOf(const synth::Scene& scene, double resolution_m = 0.1) {
  OctoMapColumns tree(resolution_m);
  tree.Insert(Scan(scene), Vec3::Zero());
  return std::make_unique<ColumnMap>(tree.Columns(), MapConfig(), Ground());
}

std::unique_ptr<ColumnMap> ElevationOf(const synth::Scene& scene) {
  baselines::ElevationMap grid;  // 0.1 m cells, 50 m, the baseline's defaults
  grid.Update(Scan(scene), Vec3::Zero(), kGroundZ);
  return std::make_unique<ColumnMap>(ElevationColumns(grid), MapConfig(), Ground());
}

// A carport: its roof's underside 2.5 m above the ground over x in [4, 8], y in [-3, 3].
synth::Scene Carport(double roof_m = 2.5) {
  synth::Scene scene;
  scene.boxes.push_back({Vec3(4.0, -3.0, roof_m), Vec3(8.0, 3.0, roof_m + 0.1)});
  return scene;
}

// A post 0.1 m square and 2 m tall at (5, 1).
synth::Scene Post() {
  synth::Scene scene;
  scene.boxes.push_back({Vec3(4.95, 0.95, 0.0), Vec3(5.05, 1.05, 2.0)});
  return scene;
}

// A ramp rising along +x at `slope_deg` from x = 2 to x = 12, 40 m wide.
synth::Scene Ramp(double slope_deg) {
  synth::Scene scene;
  scene.ramp_start_x = 2.0;
  scene.ramp_end_x = 12.0;
  scene.ramp_half_width = 20.0;
  scene.ramp_slope_rad = DegToRad(slope_deg);
  return scene;
}

// A wall 3 m tall across x = 5 .. 5.3, y in [-2, 2]: the ground behind it is in its shadow.
synth::Scene Wall() {
  synth::Scene scene;
  scene.boxes.push_back({Vec3(5.0, -2.0, 0.0), Vec3(5.3, 2.0, 3.0)});
  return scene;
}

// The vehicle box of the library defaults, and one 0.4 m taller (its top 2.7 m above the ground).
planner::VehicleBox Box() { return planner::VehicleBox{}; }
planner::VehicleBox TallBox() {
  planner::VehicleBox box;
  box.height_m += 0.4;
  return box;
}

double AngleDeg(const Vec3& a, const Vec3& b) { return RadToDeg(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0))); }

TEST(OctoMapColumnsTest, GroundUnderARoofIsFoundAndTheRoofCollidesOnlyWithABoxThatReachesIt) {
  const auto map = OctoMapOf(Carport());
  const auto ground = map->Project(Pose2{6.0, 0.0, 0.0});
  ASSERT_TRUE(ground.has_value()) << "the ground under the roof was seen";
  EXPECT_NEAR(ground->T_L_B.translation().z(), kGroundZ, 0.1) << "the ground, not the roof";
  EXPECT_TRUE(ground->traversable);
  // The box at 3.5 m reaches under the roof (its front at 3.5 + 2.35 + 0.1 m).
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kValid) << "2.3 m box top under a 2.5 m roof";
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{5.5, 0.0, 0.0}), PoseCheck::kValid);
  EXPECT_EQ(planner::CheckPose(*map, TallBox(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kCollision) << "2.7 m box top";
  EXPECT_EQ(planner::CheckPose(*map, TallBox(), Pose2{2.0, 5.0, 0.0}), PoseCheck::kValid) << "clear of the roof";
  // The roof is occupied, the space under it free.
  OctoMapColumns tree(0.1);
  tree.Insert(Scan(Carport()), Vec3::Zero());
  EXPECT_EQ(tree.Occupancy(Vec3(5.0, 0.0, 2.5 - kSensorHeightM + 0.02)), 1);
  EXPECT_EQ(tree.Occupancy(Vec3(5.0, 0.0, 1.0 - kSensorHeightM)), 0);
}

TEST(OctoMapColumnsTest, ALowRoofCollidesWithTheVehicleBox) {
  const auto map = OctoMapOf(Carport(1.8));
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kCollision);
}

TEST(OctoMapColumnsTest, AThinPostCollides) {
  const auto map = OctoMapOf(Post());
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 1.0, 0.0}), PoseCheck::kCollision);
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, -2.0, 0.0}), PoseCheck::kValid) << "beside it";
}

TEST(OctoMapColumnsTest, ARampGivesItsNormal) {
  for (double slope : {15.0, 25.0}) {
    const auto map = OctoMapOf(Ramp(slope));
    const auto ground = map->Project(Pose2{6.0, 0.0, 0.0});
    ASSERT_TRUE(ground.has_value());
    const Vec3 ramp_normal(-std::sin(DegToRad(slope)), 0.0, std::cos(DegToRad(slope)));
    EXPECT_LT(AngleDeg(ground->T_L_B.linear().col(2), ramp_normal), 3.0) << slope << " deg";
    EXPECT_NEAR(ground->T_L_B.translation().z(), kGroundZ + 4.0 * std::tan(DegToRad(slope)), 0.15);
    EXPECT_TRUE(ground->traversable) << slope << " deg is below alpha_max";
  }
  const auto steep = OctoMapOf(Ramp(35.0));
  const auto ground = steep->Project(Pose2{4.0, 0.0, 0.0});
  ASSERT_TRUE(ground.has_value());
  EXPECT_FALSE(ground->traversable) << "35 deg is above alpha_max";
}

TEST(OctoMapColumnsTest, UnknownSpaceIsUnknown) {
  const auto map = OctoMapOf(Wall());
  EXPECT_TRUE(map->IsKnownFree(3.0, 0.0));
  // Behind the wall, in its shadow, and beyond the sensor's range.
  for (const Pose2& pose : {Pose2{8.0, 0.0, 0.0}, Pose2{20.0, 5.0, 0.0}, Pose2{-6.0, 0.0, 0.0}}) {
    EXPECT_FALSE(map->Project(pose).has_value()) << pose.x_m << ", " << pose.y_m;
    EXPECT_FALSE(map->IsKnownFree(pose.x_m, pose.y_m));
    EXPECT_EQ(planner::CheckPose(*map, Box(), pose), PoseCheck::kOutsideMap);
  }
  OctoMapColumns tree(0.1);
  tree.Insert(Scan(Wall()), Vec3::Zero());
  EXPECT_EQ(tree.Occupancy(Vec3(8.0, 0.0, kGroundZ + 0.5)), -1) << "the shadow is not free";
}

TEST(OctoMapColumnsTest, VehicleBoxRulesWorkThroughThePlanningMap) {
  const auto map = OctoMapOf(Wall());
  planner::VehicleBox wheels;
  wheels.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
  wheels.placement = planner::VehicleBox::Placement::kWheelContacts;
  EXPECT_EQ(planner::CheckPose(*map, wheels, Pose2{1.0, 4.0, 0.0}), PoseCheck::kValid);
  // Heading -y past the wall's end: the body is clear of the wall, but a front wheel stands 0.8 m
  // deep in its shadow, where no ground was seen.
  EXPECT_EQ(planner::CheckPose(*map, wheels, Pose2{7.0, 3.9, -kPi / 2}), PoseCheck::kUnseenGround);
  EXPECT_EQ(planner::CheckPose(*map, wheels, Pose2{7.0, 5.5, -kPi / 2}), PoseCheck::kValid) << "all wheels on seen ground";
  // Across a 15 deg ramp the vehicle rolls 15 deg.
  const auto ramp = OctoMapOf(Ramp(15.0));
  planner::VehicleBox roll = wheels;
  EXPECT_EQ(planner::CheckPose(*ramp, roll, Pose2{6.0, -1.0, kPi / 2}), PoseCheck::kValid);
  roll.max_roll_deg = 12.0;
  EXPECT_EQ(planner::CheckPose(*ramp, roll, Pose2{6.0, -1.0, kPi / 2}), PoseCheck::kTiltsTooFar);
}

TEST(OctoMapColumnsTest, CoarseVoxelsStillFindGroundUnderTheRoof) {
  const auto map = OctoMapOf(Carport(), 0.2);
  const auto ground = map->Project(Pose2{6.0, 0.0, 0.0});
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(ground->T_L_B.translation().z(), kGroundZ, 0.2);
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kValid);
  EXPECT_EQ(planner::CheckPose(*map, TallBox(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kCollision);
}

TEST(ElevationColumnsTest, ARoofIsTheHeightOfTheCellsUnderItAndCollidesWithAnyBoxUnderIt) {
  const auto map = ElevationOf(Carport());
  const auto ground = map->Project(Pose2{6.0, 0.0, 0.0});
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(ground->T_L_B.translation().z(), 2.5 - kSensorHeightM, 0.1)
      << "the documented 2.5D limitation: the ground under the roof is lost, the roof is its cells' height";
  // So even the 2.3 m box that fits under the 2.5 m roof collides with it, and so does a taller one.
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kCollision);
  EXPECT_EQ(planner::CheckPose(*map, TallBox(), Pose2{3.5, 0.0, 0.0}), PoseCheck::kCollision);
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{2.0, 5.0, 0.0}), PoseCheck::kValid) << "clear of the roof";
  // The roof's edge is a step of 2.5 m: the ground there is not traversable.
  int steps = 0;
  for (double x = 3.7; x <= 4.3; x += 0.05) {
    const auto edge = map->Project(Pose2{x, 0.0, 0.0});
    steps += edge && !edge->traversable;
  }
  EXPECT_GT(steps, 0);
}

TEST(ElevationColumnsTest, AThinPostCollides) {
  const auto map = ElevationOf(Post());
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, 1.0, 0.0}), PoseCheck::kCollision);
  EXPECT_EQ(planner::CheckPose(*map, Box(), Pose2{3.5, -2.0, 0.0}), PoseCheck::kValid) << "beside it";
}

TEST(ElevationColumnsTest, ARampGivesItsNormal) {
  for (double slope : {15.0, 25.0}) {
    const auto map = ElevationOf(Ramp(slope));
    const auto ground = map->Project(Pose2{6.0, 0.0, 0.0});
    ASSERT_TRUE(ground.has_value());
    const Vec3 ramp_normal(-std::sin(DegToRad(slope)), 0.0, std::cos(DegToRad(slope)));
    EXPECT_LT(AngleDeg(ground->T_L_B.linear().col(2), ramp_normal), 3.0) << slope << " deg";
    EXPECT_TRUE(ground->traversable) << slope << " deg is below alpha_max";
  }
  const auto steep = ElevationOf(Ramp(35.0));
  const auto ground = steep->Project(Pose2{4.0, 0.0, 0.0});
  ASSERT_TRUE(ground.has_value());
  EXPECT_FALSE(ground->traversable) << "35 deg is above alpha_max";
}

TEST(ElevationColumnsTest, UnknownSpaceIsUnknown) {
  const auto map = ElevationOf(Wall());
  EXPECT_TRUE(map->IsKnownFree(3.0, 0.0));
  for (const Pose2& pose : {Pose2{8.0, 0.0, 0.0}, Pose2{20.0, 5.0, 0.0}, Pose2{-6.0, 0.0, 0.0}}) {
    EXPECT_FALSE(map->Project(pose).has_value()) << pose.x_m << ", " << pose.y_m;
    EXPECT_FALSE(map->IsKnownFree(pose.x_m, pose.y_m));
    EXPECT_EQ(planner::CheckPose(*map, Box(), pose), PoseCheck::kOutsideMap);
  }
}

TEST(ElevationColumnsTest, VehicleBoxRulesWorkThroughThePlanningMap) {
  const auto ramp = ElevationOf(Ramp(15.0));
  planner::VehicleBox roll;
  roll.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
  roll.placement = planner::VehicleBox::Placement::kWheelContacts;
  EXPECT_EQ(planner::CheckPose(*ramp, roll, Pose2{6.0, -1.0, kPi / 2}), PoseCheck::kValid);
  roll.max_roll_deg = 12.0;
  EXPECT_EQ(planner::CheckPose(*ramp, roll, Pose2{6.0, -1.0, kPi / 2}), PoseCheck::kTiltsTooFar);
}

TEST(ColumnMapTest, AnEmptyOrMismatchedGridIsHandled) {
  ColumnGrid empty;
  empty.Reset(0.1, 0.0, 0.0, 0, 0);
  const ColumnMap map(empty, MapConfig(), Ground());
  EXPECT_FALSE(map.Project(Pose2{0.0, 0.0, 0.0}).has_value());
  EXPECT_EQ(planner::CheckPose(map, Box(), Pose2{0.0, 0.0, 0.0}), PoseCheck::kOutsideMap);
  ColumnGrid bad;
  bad.Reset(0.1, 0.0, 0.0, 2, 2);
  bad.ground_z.push_back(0.0f);  // offsets not updated
  EXPECT_THROW(ColumnMap(bad, MapConfig()), std::invalid_argument);
  ColumnMap::Config config = MapConfig();
  config.normal_radius_m = 0.0;
  EXPECT_THROW(ColumnMap(empty, config), std::invalid_argument);
  EXPECT_THROW(OctoMapColumns(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::backends
