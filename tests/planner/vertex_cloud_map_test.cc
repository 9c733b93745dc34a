#include "ovpc/planner/vertex_cloud_map.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "planning_scenes.h"

namespace ovpc::planner {
namespace {

using testing::BuildScene;
using testing::PlanningScene;

// The box rule written out with core's oriented-box query: the fast grid test must agree with it. A
// point above the ground clearance collides; else, with kAllPoints, a non-traversable point under the
// footprint blocks.
PoseCheck ReferenceBoxCheck(const TraversabilityCloud& cloud, const GroundPose& ground, const VehicleBox& v) {
  const double top = v.height_m + v.margin_m, bottom = -v.footprint_depth_m;
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();
  T_B_C.translation() = Vec3(v.centre_ahead_m, 0.0, 0.5 * (top + bottom));
  const Vec3 half(0.5 * v.length_m + v.margin_m, 0.5 * v.width_m + v.margin_m, 0.5 * (top - bottom));
  bool ground_blocked = false;
  for (int i : cloud.InBox(ground.T_L_B * T_B_C, half)) {
    const double height = (ground.T_L_B.inverse() * cloud.points()[i]).z();
    if (height > v.ground_clearance_m) return PoseCheck::kCollision;
    if (!cloud.traversable()[i]) ground_blocked = true;
  }
  return ground_blocked && v.footprint_check == VehicleBox::FootprintCheck::kAllPoints ? PoseCheck::kGroundUnderFootprint
                                                                                      : PoseCheck::kValid;
}

TEST(VertexCloudMapTest, BoxTestAgreesWithTheOrientedBoxQuery) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-10.0, 10.0), y(-8.0, 8.0), yaw(-kPi, kPi);
  VehicleBox all_points;
  VehicleBox wheels;  // the scenarios' rule, on wheel-contact planes (tilted on the slope)
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.placement = VehicleBox::Placement::kWheelContacts;
  int free = 0, collision = 0, ground_blocked = 0, wheel_checks = 0;
  for (const auto& spec : {testing::PostsScene(), testing::CarportScene(), testing::SlopeScene(35.0)}) {
    const PlanningScene scene = BuildScene(spec);
    for (int k = 0; k < 600; ++k) {
      const Pose2 pose{x(rng), y(rng), yaw(rng)};
      const auto ground = scene.map->Project(pose);
      if (!ground) continue;
      const PoseCheck expected = ReferenceBoxCheck(scene.map->cloud(), *ground, all_points);
      ASSERT_EQ(scene.map->CheckBox(*ground, all_points), expected) << "at " << ground->T_L_B.translation().transpose();
      ++(expected == PoseCheck::kValid ? free : expected == PoseCheck::kCollision ? collision : ground_blocked);

      // kWheels: the box part decides collisions alone (the wheel support test comes after it).
      const auto placed = PlaceOnWheels(*scene.map, wheels, pose, *ground);
      if (!placed) continue;
      ++wheel_checks;
      ASSERT_EQ(scene.map->CheckBox(*placed, wheels) == PoseCheck::kCollision,
                ReferenceBoxCheck(scene.map->cloud(), *placed, wheels) == PoseCheck::kCollision)
          << "wheels at " << placed->T_L_B.translation().transpose();
    }
  }
  EXPECT_GT(free, 300);  // every answer was exercised
  EXPECT_GT(collision, 100);
  EXPECT_GT(ground_blocked, 100);
  EXPECT_GT(wheel_checks, 600);
}

TEST(VertexCloudMapTest, ARoofBelowTheMastCollidesAHigherOneDoesNot) {
  const VehicleBox vehicle;  // 2.2 m with the mast, 0.1 m margin: box top at 2.3 m
  const Pose2 under{-1.0, 0.0, 0.0};  // box from x = -1.6 to 1.45, under the roof (x in [-2, 2])
  const PlanningScene high = BuildScene(testing::CarportScene(2.5));
  EXPECT_EQ(CheckPose(*high.map, vehicle, under), PoseCheck::kValid);
  const PlanningScene low = BuildScene(testing::CarportScene(2.25));
  EXPECT_EQ(CheckPose(*low.map, vehicle, under), PoseCheck::kCollision);
  // The ground under both roofs is in the map and traversable: it is the box that decides.
  for (const PlanningScene* scene : {&high, &low}) {
    const auto ground = scene->map->Project(under);
    ASSERT_TRUE(ground.has_value());
    EXPECT_TRUE(ground->traversable);
    EXPECT_NEAR(ground->T_L_B.translation().z(), 0.0, 1e-9);
    EXPECT_TRUE(scene->map->IsKnownFree(under.x_m, under.y_m));
  }
  // A lower vehicle fits under the 2.25 m roof.
  VehicleBox low_vehicle = vehicle;
  low_vehicle.height_m = 2.0;
  EXPECT_EQ(CheckPose(*low.map, low_vehicle, under), PoseCheck::kValid);
}

// Flat ground every 0.1 m over [-4, 6] x [-3, 3]; points for which `non_traversable` holds are
// marked non-traversable, points for which `gap` holds are left out.
template <class NonTraversable, class Gap>
VertexCloudMap FlatGround(NonTraversable non_traversable, Gap gap) {
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  for (int i = -40; i <= 60; ++i) {
    for (int j = -30; j <= 30; ++j) {
      const double x = 0.1 * i, y = 0.1 * j;
      if (gap(x, y)) continue;
      points.emplace_back(x, y, 0.0);
      normals.push_back(Vec3::UnitZ());
      traversable.push_back(non_traversable(x, y) ? 0 : 1);
    }
  }
  return VertexCloudMap(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{});
}

TEST(VertexCloudMapTest, WheelRuleLetsLowNonTraversablePointsPassBetweenTheWheels) {
  VehicleBox all_points;
  all_points.footprint_check = VehicleBox::FootprintCheck::kAllPoints;
  VehicleBox wheels = all_points;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  const Pose2 pose{0.0, 0.0, 0.0};  // rear axle at the origin, front axle at x = 1.9, wheels at y = +-0.6
  const auto none = [](double, double) { return false; };

  // A non-traversable strip across, between the axles (a shadow's rim on the ground).
  const VertexCloudMap strip = FlatGround([](double x, double) { return x > 0.85 && x < 1.05; }, none);
  EXPECT_EQ(CheckPose(strip, all_points, pose), PoseCheck::kGroundUnderFootprint);
  EXPECT_EQ(CheckPose(strip, wheels, pose), PoseCheck::kValid);

  // The same strip under the front axle: the front wheels stand on it.
  const VertexCloudMap under_axle = FlatGround([](double x, double) { return x > 1.8 && x < 2.0; }, none);
  EXPECT_EQ(CheckPose(under_axle, wheels, pose), PoseCheck::kGroundUnderFootprint);

  // A hole (no visible point within wheel_support_m) under the left front wheel.
  const VertexCloudMap hole = FlatGround(none, [](double x, double y) { return std::hypot(x - 1.9, y - 0.6) < 0.7; });
  EXPECT_EQ(CheckPose(hole, wheels, pose), PoseCheck::kUnseenGround);
  // The hole is beside the pose's origin, which still projects onto the ground.
  EXPECT_TRUE(hole.Project(pose).has_value());

  // Clean ground under the whole box.
  const VertexCloudMap clean = FlatGround(none, none);
  EXPECT_EQ(CheckPose(clean, wheels, pose), PoseCheck::kValid);
}

// The seen ground ends 0.3 m short of the front wheels (a drop, or a ditch the sensor has not seen
// into): within wheel_support_m, so the wheel rule alone accepts it; the edge tolerance does not.
// A strip of unseen ground with seen ground beyond it (a shadow) still carries the wheels.
TEST(VertexCloudMapTest, EdgeToleranceKeepsTheWheelsOffGroundPastTheLastSeen) {
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  VehicleBox careful = wheels;
  careful.edge_tolerance_m = 0.15;
  const Pose2 pose{0.0, 0.0, 0.0};  // front wheels at x = 1.9, y = +-0.6; the viewpoint at the origin
  const auto none = [](double, double) { return false; };
  const VertexCloudMap edge = FlatGround(none, [](double x, double) { return x > 1.65; });
  EXPECT_EQ(CheckPose(edge, wheels, pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(edge, careful, pose), PoseCheck::kUnseenGround);
  const VertexCloudMap shadow = FlatGround(none, [](double x, double) { return x > 1.65 && x < 2.15; });
  EXPECT_EQ(CheckPose(shadow, careful, pose), PoseCheck::kValid);
  // On seen ground the tolerance changes nothing.
  EXPECT_EQ(CheckPose(FlatGround(none, none), careful, pose), PoseCheck::kValid);
  careful.edge_tolerance_m = -0.1;
  EXPECT_THROW(careful.Validate(), std::invalid_argument);
}

// With wheel_support_per_m the support radius follows the spacing of the visible points: seen ground
// that ends 0.3 m short of the front wheels carries them 6 m from the sensor (0.3 m there), not 2 m
// from it, where the points are dense and a wheel that far past them stands over an edge.
TEST(VertexCloudMapTest, WheelSupportGrowsWithTheDistanceFromTheSensor) {
  VehicleBox fixed;
  fixed.footprint_check = VehicleBox::FootprintCheck::kWheels;
  VehicleBox growing = fixed;
  growing.wheel_support_per_m = 0.05;
  growing.wheel_support_near_m = 0.2;
  EXPECT_DOUBLE_EQ(growing.WheelSupportAt(1.0), 0.2);
  EXPECT_DOUBLE_EQ(growing.WheelSupportAt(6.0), 0.3);
  EXPECT_DOUBLE_EQ(growing.WheelSupportAt(50.0), fixed.wheel_support_m);
  EXPECT_DOUBLE_EQ(fixed.WheelSupportAt(1.0), fixed.wheel_support_m);
  const auto none = [](double, double) { return false; };
  const Pose2 near_pose{0.0, 0.0, 0.0};  // front wheels at (1.9, +-0.6), 2.0 m from the sensor
  const VertexCloudMap near_edge = FlatGround(none, [](double x, double) { return x > 1.65; });
  EXPECT_EQ(CheckPose(near_edge, fixed, near_pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(near_edge, growing, near_pose), PoseCheck::kUnseenGround);
  const Pose2 far_pose{4.1, 0.0, 0.0};  // front wheels at (6.0, +-0.6), 6.03 m from the sensor
  const VertexCloudMap far_edge = FlatGround(none, [](double x, double) { return x > 5.75; });
  EXPECT_EQ(CheckPose(far_edge, fixed, far_pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(far_edge, growing, far_pose), PoseCheck::kValid);
  growing.wheel_support_per_m = -0.01;
  EXPECT_THROW(growing.Validate(), std::invalid_argument);
}

// Ground 1.9 m below the viewpoint (the sensor at the origin) ends at a lip at x = lip_m; the ditch's
// near wall lies in the lip's shadow, its bottom (1 m down, traversable) is seen only where the rays
// over the lip reach it, its far wall (steep) and the ground beyond are seen. Or, with `ramp`, the
// ground goes on down a 20 deg ramp from the lip, seen.
VertexCloudMap DitchOrRamp(double lip_m, bool ramp) {
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  const double ground_z = -1.9, depth = 1.0;
  const double slope = std::tan(20.0 * kPi / 180.0);
  const Vec3 ramp_normal = Vec3(slope, 0.0, 1.0).normalized();
  const double wall_n = std::sqrt(0.5);
  for (int i = -40; i <= 100; ++i) {
    const double x = 0.1 * i;
    double z = ground_z;
    Vec3 n = Vec3::UnitZ();
    bool ok = true;
    if (x > lip_m + 1e-9) {
      if (ramp) {
        z = ground_z - slope * (x - lip_m);
        n = ramp_normal;
      } else if (x < lip_m + 1.0) {
        continue;  // the near wall, unseen
      } else if (x <= lip_m + 2.5) {
        z = ground_z - depth;
        if (-z * lip_m / -ground_z > x) continue;  // in the lip's shadow
      } else if (x < lip_m + 3.5) {
        z = ground_z - depth + (x - lip_m - 2.5);
        n = Vec3(-wall_n, 0.0, wall_n);
        ok = false;
      }
    }
    for (int j = -30; j <= 30; ++j) {
      points.emplace_back(x, 0.1 * j, z);
      normals.push_back(n);
      traversable.push_back(ok ? 1 : 0);
    }
  }
  GroundContext ground;
  ground.ground_reference_z_m = ground_z;
  return VertexCloudMap(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, ground);
}

// The crest test: a front wheel 0.05 m past a ditch's lip stands within wheel_support_m of the lip's
// points, so the wheel rule alone accepts it; rays over the lip that reach the ditch's bottom and far
// wall show that the ground falls away there, and no seen ground lies beyond it: refused. A wheel
// 0.4 m short of the lip, and a wheel past the crest of a seen 20 deg ramp, stand.
TEST(VertexCloudMapTest, CrestTestKeepsTheWheelsOffALipTheSensorHasSeenPast) {
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.placement = VehicleBox::Placement::kWheelContacts;
  VehicleBox crest = wheels;
  crest.crest_margin_m = 0.2;
  const Pose2 pose{0.0, 0.0, 0.0};  // front wheels at x = 1.9, y = +-0.6
  const VertexCloudMap past = DitchOrRamp(1.85, false);
  EXPECT_EQ(CheckPose(past, wheels, pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(past, crest, pose), PoseCheck::kCrest);
  EXPECT_EQ(CheckPose(DitchOrRamp(2.3, false), crest, pose), PoseCheck::kValid);
  // Turned 29 deg to the right, the front wheels stand at x = 1.96 (left) and 1.38 (right).
  const Pose2 turned{0.0, 0.0, -0.5};
  EXPECT_EQ(CheckPose(DitchOrRamp(2.3, false), crest, turned), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(DitchOrRamp(1.9, false), wheels, turned), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(DitchOrRamp(1.9, false), crest, turned), PoseCheck::kCrest);
  // Down a seen ramp: the ground beyond the wheels is seen.
  EXPECT_EQ(CheckPose(DitchOrRamp(1.85, true), crest, pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(DitchOrRamp(1.0, true), crest, pose), PoseCheck::kValid);
  crest.crest_drop_m = 0.0;
  EXPECT_THROW(crest.Validate(), std::invalid_argument);
}

// The wheel rules with the crest test, as the preset has them.
VehicleBox CrestBox() {
  VehicleBox crest;
  crest.footprint_check = VehicleBox::FootprintCheck::kWheels;
  crest.placement = VehicleBox::Placement::kWheelContacts;
  crest.crest_margin_m = 0.2;
  return crest;
}

// The vehicle stands at the origin facing +x, 1.9 m below the viewpoint: its footprint grown by
// 0.3 m is known support (to 2.65 m ahead, 0.75 m past the front wheels), the crest test applying
// past its own front wheels (SupportRegion::crest_from_x_m), as the navigator passes it.
GroundContext StandingAtTheOrigin() {
  GroundContext context;
  context.ground_reference_z_m = -1.9;
  context.known_support.pose = Pose2{0.0, 0.0, 0.0};
  context.known_support.min_x_m = -0.75;
  context.known_support.max_x_m = 2.65;
  context.known_support.half_width_m = 1.05;
  context.known_support.crest_from_x_m = 1.92;
  return context;
}

// The crest test's search for seen ground beyond a wheel skips the known support: there the
// footprint prior lays ground that was never seen (in `fill` mode on past a lip, up to the known
// support's end).
TEST(VertexCloudMapTest, TheFootprintPriorsGroundDoesNotCarryAWheelPastALip) {
  const VehicleBox crest = CrestBox();
  const Pose2 pose{0.0, 0.0, 0.0};  // front wheels at x = 1.9, y = +-0.6
  // The vehicle stands at `pose` by a lip at x = 1.85; its known support reaches to 2.65, and the
  // footprint prior's ground is laid on to there; the ditch's bottom, 1 m down, is seen over the lip.
  // 0.3 m on, its front wheels stand on the prior's ground 0.35 m past the lip: that ground does not
  // carry them; the same ground, seen, would.
  GroundContext prior = StandingAtTheOrigin();
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  const auto add = [&](double x, double y, double z) {
    points.emplace_back(x, y, z);
    normals.push_back(Vec3::UnitZ());
    traversable.push_back(1);
  };
  for (int i = -40; 0.1 * i <= 2.65; ++i) {
    for (int j = -30; j <= 30; ++j) {
      if (0.1 * i <= 1.85 || std::abs(0.1 * j) <= 1.05) add(0.1 * i, 0.1 * j, -1.9);  // the prior: in the region
    }
  }
  for (int i = 29; i <= 33; ++i) {
    for (int j = -10; j <= 10; ++j) add(0.1 * i, 0.1 * j, -2.9);
  }
  const Pose2 on{0.3, 0.0, 0.0};
  const VertexCloudMap with_prior(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, prior);
  EXPECT_EQ(CheckPose(with_prior, crest, pose), PoseCheck::kValid) << "where it stands";
  EXPECT_EQ(CheckPose(with_prior, crest, on), PoseCheck::kCrest);
  prior.known_support = SupportRegion{};
  const VertexCloudMap seen(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, prior);
  EXPECT_EQ(CheckPose(seen, crest, on), PoseCheck::kValid) << "the same ground, seen, carries it";
}

// The known support reaches 0.75 m past the vehicle's front wheels (its nose and a margin), where it
// does not stand. A ditch's lip lies 0.2 m ahead of the front wheels and the top 0.2 m of its 45 deg
// near wall is seen, steep, below it; nothing beyond is seen, so the crest test has no ray to go by.
// A pose 0.5 m on puts the front wheels 0.3 m past the lip: refused, as it would be outside the
// region. 0.1 m on, the wheels still stand on the rim.
TEST(VertexCloudMapTest, SteepGroundSeenUnderTheNoseCarriesNoWheel) {
  VehicleBox crest = CrestBox();
  crest.ground_clearance_m = 0.35;  // the preset's: the box on its wheels clears the lip
  const Pose2 pose{0.0, 0.0, 0.0};  // front wheels at x = 1.9, y = +-0.6
  GroundContext context = StandingAtTheOrigin();
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  const auto add_row = [&](double x, double z, bool ok) {
    for (int j = -30; j <= 30; ++j) {
      points.emplace_back(x, 0.1 * j, z);
      normals.push_back(ok ? Vec3::UnitZ() : Vec3(std::sqrt(0.5), 0.0, std::sqrt(0.5)));
      traversable.push_back(ok ? 1 : 0);
    }
  };
  for (int i = -40; i <= 21; ++i) add_row(0.1 * i, -1.9, true);  // up to the lip at x = 2.1
  add_row(2.15, -1.95, false);  // the top of the near wall
  add_row(2.25, -2.05, false);
  const VertexCloudMap map(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, context);
  EXPECT_EQ(CheckPose(map, crest, pose), PoseCheck::kValid) << "where it stands";
  EXPECT_EQ(CheckPose(map, crest, Pose2{0.1, 0.0, 0.0}), PoseCheck::kValid) << "front wheels on the rim";
  EXPECT_EQ(CheckPose(map, crest, Pose2{0.5, 0.0, 0.0}), PoseCheck::kGroundUnderFootprint);
  context.known_support = SupportRegion{};
  const VertexCloudMap outside(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, context);
  EXPECT_EQ(CheckPose(outside, crest, Pose2{0.5, 0.0, 0.0}), PoseCheck::kGroundUnderFootprint) << "as outside";
}

// Flat ground seen everywhere but in a 1.2 m hole behind the vehicle (the ring round the mast the
// sensor never sees): the rear wheels of a pose 1.2 m back stand in its middle, unseen. Ground
// remembered there at the same height carries them; remembered 0.6 m lower (a ditch's floor seen
// earlier), or remembered not traversable (a steep face), it does not; a wheel with a visible
// point near it is judged by that point, whatever is remembered.
TEST(VertexCloudMapTest, RememberedGroundJudgesAWheelOnlyWhereNothingIsSeen) {
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.wheel_support_m = 0.35;
  const auto hole = [](double x, double y) { return x > -1.8 && x < -0.6 && std::abs(y) < 1.5; };
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  for (int i = -40; i <= 60; ++i) {
    for (int j = -30; j <= 30; ++j) {
      if (hole(0.1 * i, 0.1 * j)) continue;
      points.emplace_back(0.1 * i, 0.1 * j, -1.9);
      normals.push_back(Vec3::UnitZ());
      traversable.push_back(1);
    }
  }
  const Pose2 back{-1.2, 0.0, 0.0};  // rear wheels at (-1.2, +-0.6), front wheels at (0.7, +-0.6)
  GroundContext context;
  context.ground_reference_z_m = -1.9;
  const VertexCloudMap unseen(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, context);
  EXPECT_EQ(CheckPose(unseen, wheels, back), PoseCheck::kUnseenGround);
  const auto remember = [&](double z, std::uint8_t ok) {
    std::vector<Vec3> r;
    for (int i = -18; i <= -6; ++i) {
      for (int j = -15; j <= 15; ++j) r.emplace_back(0.1 * i, 0.1 * j, z);
    }
    GroundContext with = context;
    with.remembered = std::make_shared<const RememberedGround>(r, std::vector<std::uint8_t>(r.size(), ok));
    return VertexCloudMap(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, with);
  };
  EXPECT_EQ(CheckPose(remember(-1.9, 1), wheels, back), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(remember(-2.5, 1), wheels, back), PoseCheck::kUnseenGround) << "a floor 0.6 m down";
  EXPECT_EQ(CheckPose(remember(-1.9, 0), wheels, back), PoseCheck::kUnseenGround) << "a steep face";
  // A lip remembered behind the rear wheels (x = -1.2): flat ground back to `lip_x`, then a 40
  // degree wall, not traversable, going down. Within the wheel's support of the wall, memory
  // does not carry it, though the nearest remembered point is the flat top right under it.
  const auto remember_lip = [&](double lip_x) {
    std::vector<Vec3> r;
    std::vector<std::uint8_t> ok;
    for (int i = -18; i <= -6; ++i) {
      for (int j = -15; j <= 15; ++j) {
        const double x = 0.1 * i;
        r.emplace_back(x, 0.1 * j, x >= lip_x ? -1.9 : -1.9 - std::tan(40.0 * M_PI / 180.0) * (lip_x - x));
        ok.push_back(x >= lip_x ? 1 : 0);
      }
    }
    GroundContext with = context;
    with.remembered = std::make_shared<const RememberedGround>(r, ok);
    return VertexCloudMap(TraversabilityCloud(points, normals, traversable), VertexCloudMap::Config{}, with);
  };
  EXPECT_EQ(CheckPose(remember_lip(-1.45), wheels, back), PoseCheck::kUnseenGround) << "0.25 m from a lip";
  EXPECT_EQ(CheckPose(remember_lip(-1.65), wheels, back), PoseCheck::kValid) << "0.45 m from a lip";
  // Where a non-traversable point is seen near a wheel, memory does not overrule it.
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (std::hypot(points[k].x() - 0.7, points[k].y() - 0.6) < 0.25) traversable[k] = 0;
  }
  EXPECT_EQ(CheckPose(remember(-1.9, 1), wheels, back), PoseCheck::kGroundUnderFootprint);
  EXPECT_THROW(RememberedGround({Vec3(0.0, std::nan(""), 0.0)}, {1}), std::invalid_argument);
  EXPECT_THROW(RememberedGround({Vec3::Zero()}, {}), std::invalid_argument);
}

// The ground under the vehicle's own footprint carries its wheels though nothing traversable is seen
// there; obstacles in the box still block, and wheels outside the region still need support.
TEST(VertexCloudMapTest, KnownSupportCarriesTheWheelsButNotThroughObstacles) {
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  const Pose2 pose{0.0, 0.0, 0.0};  // wheels at x = 0 and 1.9, y = +-0.6
  // Non-traversable ground under the rear left wheel (an artefact where the footprint prior meets
  // rough ground).
  const auto artefact = [](double x, double y) { return std::hypot(x, y - 0.6) < 0.25; };
  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  const auto add = [&](const Vec3& p, bool trav) {
    points.push_back(p);
    normals.push_back(Vec3::UnitZ());
    traversable.push_back(trav ? 1 : 0);
  };
  for (int i = -40; i <= 60; ++i) {
    for (int j = -30; j <= 30; ++j) add(Vec3(0.1 * i, 0.1 * j, 0.0), !artefact(0.1 * i, 0.1 * j));
  }
  const VertexCloudMap::Config config;
  GroundContext ground;
  const VertexCloudMap plain(TraversabilityCloud(points, normals, traversable), config);
  EXPECT_EQ(CheckPose(plain, wheels, pose), PoseCheck::kGroundUnderFootprint);

  // The vehicle stands at `pose`: its footprint grown by 0.3 m is known support.
  ground.known_support.pose = pose;
  ground.known_support.min_x_m = wheels.centre_ahead_m - 0.5 * wheels.length_m - 0.3;
  ground.known_support.max_x_m = wheels.centre_ahead_m + 0.5 * wheels.length_m + 0.3;
  ground.known_support.half_width_m = 0.5 * wheels.width_m + 0.3;
  const VertexCloudMap supported(TraversabilityCloud(points, normals, traversable), config, ground);
  EXPECT_EQ(CheckPose(supported, wheels, pose), PoseCheck::kValid);
  EXPECT_EQ(CheckPose(supported, wheels, Pose2{0.2, 0.0, 0.0}), PoseCheck::kValid);  // rear wheels still inside
  // Far enough that the rear left wheel is outside the region but on the artefact again: no.
  const Pose2 away{0.0, 0.0, kPi};  // turned round: the rear axle at the origin, front wheels at x = -1.9
  ground.known_support.pose = Pose2{-3.0, 0.0, 0.0};  // the region is elsewhere
  const VertexCloudMap elsewhere(TraversabilityCloud(points, normals, traversable), config, ground);
  EXPECT_EQ(CheckPose(elsewhere, wheels, away), PoseCheck::kGroundUnderFootprint);
  EXPECT_FALSE(ground.known_support.Contains(0.0, 0.6));

  // A post inside the box blocks even on known support.
  add(Vec3(1.0, 0.3, 0.8), false);
  ground.known_support.pose = pose;
  const VertexCloudMap post(TraversabilityCloud(points, normals, traversable), config, ground);
  EXPECT_EQ(CheckPose(post, wheels, pose), PoseCheck::kCollision);
}

TEST(VertexCloudMapTest, ProjectsOntoTheSlopeAlignedToItsNormalKeepingTheHeading) {
  const double slope = DegToRad(5.0);
  const PlanningScene scene = BuildScene(testing::SlopeScene(5.0));
  const double yaw = 0.3;
  const auto ground = scene.map->Project(Pose2{0.0, 0.5, yaw});  // mid-ramp
  ASSERT_TRUE(ground.has_value());
  EXPECT_TRUE(ground->traversable);
  const Vec3 origin = ground->T_L_B.translation();
  EXPECT_NEAR(origin.x(), 0.0, 1e-12);
  EXPECT_NEAR(origin.y(), 0.5, 1e-12);
  EXPECT_NEAR(origin.z(), std::tan(slope) * 1.0, 0.02);  // ground height at x = 0
  const Eigen::Matrix3d R = ground->T_L_B.linear();
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-9);
  const Vec3 normal(-std::sin(slope), 0.0, std::cos(slope));
  EXPECT_NEAR(R.col(2).dot(normal), 1.0, 1e-3);
  // x stays in the vertical plane of the heading.
  EXPECT_NEAR(std::atan2(R(1, 0), R(0, 0)), yaw, 1e-9);
}

// A 20 deg ramp from x = 0 up to a 2 m plateau, scanned from 3.6 m before its foot (slope_20's
// geometry).
PlanningScene LongRamp(double slope_deg, double viewpoint_x) {
  testing::SceneSpec spec;
  spec.slope_deg = slope_deg;
  spec.ramp_start_x = 0.0;
  spec.ramp_end_x = 2.0 / std::tan(DegToRad(slope_deg));
  spec.ground = testing::Rect{-11.0, 14.0, -6.0, 6.0};
  spec.viewpoint_x = viewpoint_x;
  spec.gamma = -0.03;
  return BuildScene(spec);
}

TEST(VertexCloudMapTest, WheelPlacementLetsTheBoxOverARampsFootTheRigidPlaneDoesNot) {
  const PlanningScene scene = LongRamp(20.0, -3.6);
  VehicleBox rigid;
  rigid.footprint_check = VehicleBox::FootprintCheck::kWheels;
  rigid.ground_clearance_m = 0.35;  // even raised, the flat box's nose cuts into the ramp
  VehicleBox wheels = rigid;
  wheels.placement = VehicleBox::Placement::kWheelContacts;
  wheels.ground_clearance_m = 0.2;
  int rigid_collisions = 0;
  for (double x = -3.0; x <= 3.0; x += 0.1) {
    const Pose2 pose{x, 0.0, 0.0};
    rigid_collisions += CheckPose(*scene.map, rigid, pose) == PoseCheck::kCollision;
    EXPECT_EQ(CheckPose(*scene.map, wheels, pose), PoseCheck::kValid) << x;
  }
  EXPECT_GE(rigid_collisions, 8) << "rear axle 1.25 .. 0.25 m before the foot";

  // Rear wheels on the flat, front wheels 1 m up the ramp: the box pitches by the wheels' rise.
  const Pose2 straddle{-0.9, 0.0, 0.0};
  const auto projected = scene.map->Project(straddle);
  ASSERT_TRUE(projected.has_value());
  EXPECT_NEAR(projected->T_L_B.linear()(2, 2), 1.0, 1e-3);  // the nearest point is flat ground
  const auto placed = PlaceOnWheels(*scene.map, wheels, straddle, *projected);
  ASSERT_TRUE(placed.has_value());
  const double front_rise = std::tan(DegToRad(20.0)) * (wheels.wheelbase_m - 0.9);
  const double pitch = std::atan2(front_rise, wheels.wheelbase_m);
  EXPECT_NEAR(std::acos(placed->T_L_B.linear()(2, 2)), pitch, DegToRad(2.0));
  EXPECT_NEAR(placed->T_L_B.translation().z(), 0.0, 0.03);
  EXPECT_NEAR(std::atan2(placed->T_L_B.linear()(1, 0), placed->T_L_B.linear()(0, 0)), 0.0, 1e-9);
}

TEST(VertexCloudMapTest, WheelPlacementStillStopsAtASteepRampAndAStep) {
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.placement = VehicleBox::Placement::kWheelContacts;
  // 35 deg (above alpha_max): some pose along the way up is invalid, so no motion climbs it.
  const PlanningScene steep = LongRamp(35.0, -3.6);
  bool blocked = false;
  for (double x = -3.0; x <= 1.0; x += 0.1) blocked |= CheckPose(*steep.map, wheels, Pose2{x, 0.0, 0.0}) != PoseCheck::kValid;
  EXPECT_TRUE(blocked);
  // The plane through the wheels may not tilt past max_tilt_deg.
  VehicleBox strict = wheels;
  strict.max_tilt_deg = 10.0;
  const PlanningScene ramp = LongRamp(20.0, -3.6);
  EXPECT_EQ(CheckPose(*ramp.map, strict, Pose2{1.0, 0.0, 0.0}), PoseCheck::kTiltsTooFar);
  EXPECT_EQ(CheckPose(*ramp.map, wheels, Pose2{1.0, 0.0, 0.0}), PoseCheck::kValid);

  // A 0.5 m step (a wall across the way): driving at it, some pose collides or stands on its edge.
  testing::SceneSpec spec;
  spec.slope_deg = 89.0;
  spec.ramp_start_x = 0.0;
  spec.ramp_end_x = 0.5 / std::tan(DegToRad(89.0));
  spec.spacing_m = 0.1;
  spec.ground = testing::Rect{-8.0, 8.0, -5.0, 5.0};
  spec.viewpoint_x = -3.0;
  const PlanningScene step = BuildScene(spec);
  int invalid = 0;
  for (double x = -3.0; x <= 1.0; x += 0.1) invalid += CheckPose(*step.map, wheels, Pose2{x, 0.0, 0.0}) != PoseCheck::kValid;
  EXPECT_GE(invalid, 10);
  EXPECT_EQ(CheckPose(*step.map, wheels, Pose2{-2.1, 0.0, 0.0}), PoseCheck::kCollision);  // nose at the wall
}

// A wall across the way (posts 0.2 m apart, 1.4 m high; ground points 0.25 m apart, the robot's
// GHPR kernel) with a gap of 2.2 m, driven through straight on its axis: the box (1.7 m) clears the wall's ends by 0.25 m, and each wheel passes 0.5 m from
// them. The ground at the wall's foot is non-traversable (its faces climb the wall), but it is a
// foot: the wall rises from it, and the box test answers for the wall. So every pose on the way is
// valid; a lip (the ditch and crest tests above) still carries no wheel.
TEST(VertexCloudMapTest, AWallsFootCarriesAWheelThroughAGap) {
  testing::SceneSpec spec;
  spec.spacing_m = 0.25;
  spec.gamma = -0.03;
  spec.ground = testing::Rect{-6.0, 8.0, -5.0, 5.0};
  for (double y = 1.22; y <= 5.0; y += 0.2) {
    for (double side : {-1.0, 1.0}) spec.posts.push_back(testing::Post{2.0, side * y, 0.12, 1.4});
  }
  spec.viewpoint_x = -4.0;
  const PlanningScene scene = BuildScene(spec);
  VehicleBox wheels;
  wheels.footprint_check = VehicleBox::FootprintCheck::kWheels;
  wheels.placement = VehicleBox::Placement::kWheelContacts;
  int feet_near_the_wall = 0;
  const TraversabilityCloud& cloud = scene.map->cloud();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points()[i];
    feet_near_the_wall += cloud.IsFoot(i) && std::abs(p.x() - 2.0) < 0.4 && std::abs(p.z()) < 0.05;
  }
  EXPECT_GE(feet_near_the_wall, 8);
  // From 3 m before the wall until the rear wheels reach it (the ground farther on is in the wall's
  // shadow). Without feet every pose from the front wheels 0.6 m before the wall on failed as
  // ground under the footprint.
  for (double x = -3.0; x <= 1.8; x += 0.1) {
    EXPECT_EQ(CheckPose(*scene.map, wheels, Pose2{x, 0.0, 0.0}), PoseCheck::kValid) << "rear axle at x = " << x;
  }
  // Beside the gap's axis by 0.4 m the box meets the wall.
  EXPECT_EQ(CheckPose(*scene.map, wheels, Pose2{1.0, 0.4, 0.0}), PoseCheck::kCollision);
}

// On a 20 deg ramp the vehicle rolls by atan(tan 20 deg * sin(heading off the fall line)): with
// max_roll_deg 8, straight up and 15 deg off it pass (5.4 deg of roll), 45 deg off it (14.4 deg) does
// not, whichever placement; without the limit (90, the default) every heading passes.
TEST(VertexCloudMapTest, RollLimitKeepsTheVehicleNearTheFallLineOnARamp) {
  const PlanningScene ramp = LongRamp(20.0, -3.6);
  for (const auto placement : {VehicleBox::Placement::kNearestPoint, VehicleBox::Placement::kWheelContacts}) {
    VehicleBox free_roll;
    free_roll.footprint_check = VehicleBox::FootprintCheck::kWheels;
    free_roll.placement = placement;
    free_roll.ground_clearance_m = 0.35;
    VehicleBox limited = free_roll;
    limited.max_roll_deg = 8.0;
    for (double off_deg : {0.0, 15.0, -15.0, 45.0, -45.0}) {
      const Pose2 pose{2.0, 0.0, DegToRad(off_deg)};
      const PoseCheck unlimited = CheckPose(*ramp.map, free_roll, pose);
      EXPECT_EQ(unlimited, PoseCheck::kValid) << off_deg;
      const PoseCheck check = CheckPose(*ramp.map, limited, pose);
      if (std::abs(off_deg) < 30.0) {
        EXPECT_EQ(check, PoseCheck::kValid) << off_deg;
      } else {
        EXPECT_EQ(check, PoseCheck::kTiltsTooFar) << off_deg;
      }
    }
  }
  VehicleBox bad;
  bad.max_roll_deg = 0.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
  bad.max_roll_deg = 91.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// On a 25 deg ramp, max_nose_down_deg 22 refuses the vehicle facing down it (straight down, and 20 deg
// off the fall line: 23.7 deg of pitch) but not facing up it, across it (0 deg of pitch) or 60 deg off
// the fall line (13.1 deg), whichever placement; on a 15 deg ramp facing down passes. Without the limit (90, the default) every heading
// passes.
TEST(VertexCloudMapTest, NoseDownLimitRefusesFacingDownASteepSlopeOnly) {
  const PlanningScene steep = LongRamp(25.0, -3.6);
  const PlanningScene gentle = LongRamp(15.0, -3.6);
  for (const auto placement : {VehicleBox::Placement::kNearestPoint, VehicleBox::Placement::kWheelContacts}) {
    VehicleBox free_pitch;
    free_pitch.footprint_check = VehicleBox::FootprintCheck::kWheels;
    free_pitch.placement = placement;
    free_pitch.ground_clearance_m = 0.35;
    VehicleBox limited = free_pitch;
    limited.max_nose_down_deg = 22.0;
    struct Case {
      double yaw_deg;
      bool down;
    };
    for (const Case c : {Case{0.0, false}, Case{90.0, false}, Case{-90.0, false}, Case{180.0, true}, Case{160.0, true}, Case{120.0, false}}) {
      const Pose2 pose{2.0, 0.0, DegToRad(c.yaw_deg)};
      EXPECT_EQ(CheckPose(*steep.map, free_pitch, pose), PoseCheck::kValid) << c.yaw_deg;
      EXPECT_EQ(CheckPose(*steep.map, limited, pose), c.down ? PoseCheck::kTiltsTooFar : PoseCheck::kValid) << c.yaw_deg;
      EXPECT_EQ(CheckPose(*gentle.map, limited, pose), PoseCheck::kValid) << c.yaw_deg;
    }
  }
  VehicleBox bad;
  bad.max_nose_down_deg = 0.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
  bad.max_nose_down_deg = 90.5;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// Flat ground 0.1 m apart with 1.5 cm of height noise, whose vertex normals are tilted by up to
// ~17 degrees at random (as range noise tilts a mesh's small faces): on the nearest point's own
// normal the 3 m box tilts, flat ground near its ends rises above the ground clearance, and poses
// on open ground collide. The plane fitted to the 32 nearest points is within a few degrees of
// level, and no pose collides.
TEST(VertexCloudMapTest, PlaneOfTheNearestPointsKeepsNoisyFlatGroundFree) {
  Points points;
  std::vector<Vec3> normals;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> tilt(-0.3, 0.3);
  std::normal_distribution<double> noise(0.0, 0.015);
  for (int i = -60; i <= 60; ++i) {
    for (int j = -60; j <= 60; ++j) {
      points.emplace_back(0.1 * i, 0.1 * j, noise(rng));
      normals.push_back(Vec3(tilt(rng), tilt(rng), 1.0).normalized());
    }
  }
  const TraversabilityCloud cloud(points, normals, std::vector<std::uint8_t>(points.size(), 1));
  VertexCloudMap::Config own;
  VertexCloudMap::Config fitted = own;
  fitted.normal_neighbours = 32;
  const VertexCloudMap own_map(cloud, own), fitted_map(cloud, fitted);
  VehicleBox vehicle;
  vehicle.footprint_check = VehicleBox::FootprintCheck::kWheels;
  std::uniform_real_distribution<double> u(-2.0, 2.0), yaw(-kPi, kPi);
  int own_collisions = 0;
  double worst_tilt_deg = 0.0;
  for (int k = 0; k < 300; ++k) {
    const Pose2 pose{u(rng), u(rng), yaw(rng)};
    if (CheckPose(own_map, vehicle, pose) == PoseCheck::kCollision) ++own_collisions;
    EXPECT_EQ(CheckPose(fitted_map, vehicle, pose), PoseCheck::kValid);
    const auto ground = fitted_map.ProjectForBox(pose);
    ASSERT_TRUE(ground.has_value());
    worst_tilt_deg = std::max(worst_tilt_deg, std::acos(ground->T_L_B.linear()(2, 2)) * 180.0 / kPi);
    // The surface point and its traversability are still the nearest point's, and Project is
    // unchanged (the paper's rule, used for everything but the box).
    const auto own_ground = own_map.Project(pose);
    EXPECT_EQ(ground->surface_point, own_ground->surface_point);
    EXPECT_EQ(ground->traversable, own_ground->traversable);
    EXPECT_EQ(fitted_map.Project(pose)->T_L_B.matrix(), own_ground->T_L_B.matrix());
  }
  EXPECT_GT(own_collisions, 10);
  EXPECT_LT(worst_tilt_deg, 4.0);

  // A 0.3 m step 1.5 m ahead still collides: the fit takes only points within normal_radius_m of
  // the nearest, all on the lower level.
  Points step;
  for (int i = -30; i <= 40; ++i) {
    for (int j = -20; j <= 20; ++j) step.emplace_back(0.1 * i, 0.1 * j, i >= 15 ? 0.3 : 0.0);
  }
  const VertexCloudMap step_map(TraversabilityCloud(step, std::vector<Vec3>(step.size(), Vec3::UnitZ()),
                                                    std::vector<std::uint8_t>(step.size(), 1)),
                                fitted);
  EXPECT_EQ(CheckPose(step_map, vehicle, Pose2{0.0, 0.0, 0.0}), PoseCheck::kCollision);
  EXPECT_EQ(CheckPose(step_map, vehicle, Pose2{-0.5, 0.0, kPi}), PoseCheck::kValid);
  fitted.normal_neighbours = 0;
  EXPECT_THROW(fitted.Validate(), std::invalid_argument);
  fitted.normal_neighbours = 32;
  fitted.normal_radius_m = -1.0;
  EXPECT_THROW(fitted.Validate(), std::invalid_argument);
}

// The fitted planes are made on first use and kept; two threads asking at once get what one thread
// gets from a fresh map.
TEST(VertexCloudMapTest, FittedPlanesAreTheSameFromConcurrentCalls) {
  const PlanningScene scene = BuildScene(testing::PostsScene());
  VertexCloudMap::Config config;
  config.normal_neighbours = 32;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-8.0, 8.0), yaw(-kPi, kPi);
  std::vector<Pose2> poses;
  for (int k = 0; k < 2000; ++k) poses.push_back(Pose2{u(rng), u(rng), yaw(rng)});
  const auto run = [&poses](const VertexCloudMap& map, std::vector<Eigen::Matrix4d>* out) {
    out->clear();
    for (const Pose2& pose : poses) {
      const auto g = map.ProjectForBox(pose);
      out->push_back(g ? g->T_L_B.matrix() : Eigen::Matrix4d::Zero());
    }
  };
  std::vector<Eigen::Matrix4d> expected, a, b;
  run(VertexCloudMap(scene.map->cloud(), config), &expected);
  const VertexCloudMap shared(scene.map->cloud(), config);
  std::thread first([&] { run(shared, &a); });
  std::thread second([&] { run(shared, &b); });
  first.join();
  second.join();
  EXPECT_EQ(a, expected);
  EXPECT_EQ(b, expected);
  // And again, now from the kept planes.
  run(shared, &a);
  EXPECT_EQ(a, expected);
}

TEST(VertexCloudMapTest, FarFromEveryPointIsOutsideKnownSpace) {
  const PlanningScene scene = BuildScene(testing::PostsScene());
  const VehicleBox vehicle;
  EXPECT_EQ(CheckPose(*scene.map, vehicle, Pose2{50.0, 0.0, 0.0}), PoseCheck::kOutsideMap);
  EXPECT_FALSE(scene.map->Project(Pose2{50.0, 0.0, 0.0}).has_value());
  EXPECT_FALSE(scene.map->IsKnownFree(50.0, 0.0));
  // Behind the posts, as seen from the scanning vehicle, the ground is unknown.
  EXPECT_FALSE(scene.map->IsKnownFree(0.0, 5.0));
  EXPECT_TRUE(scene.map->IsKnownFree(0.0, -4.0));
  // Between the posts the ground is known but not traversable (its faces climb the posts).
  EXPECT_EQ(CheckPose(*scene.map, vehicle, Pose2{0.6, 0.0, 0.0}), PoseCheck::kNotTraversable);
  const MapBounds b = scene.map->Bounds();
  EXPECT_GE(b.min_x_m, -11.0 - 1e-9);
  EXPECT_LE(b.max_x_m, 11.0 + 1e-9);
  EXPECT_LT(b.min_x_m, -10.0);
  EXPECT_GT(b.max_y_m, 8.0);
}

TEST(VertexCloudMapTest, EmptyCloudIsOutsideEverywhere) {
  const VertexCloudMap map(TraversabilityCloud{}, VertexCloudMap::Config{});
  EXPECT_EQ(CheckPose(map, VehicleBox{}, Pose2{}), PoseCheck::kOutsideMap);
  EXPECT_FALSE(map.IsKnownFree(0.0, 0.0));
}

TEST(VertexCloudMapTest, InvalidConfigThrowsNamingTheField) {
  VertexCloudMap::Config config;
  config.max_projection_distance_m = 0.0;
  try {
    VertexCloudMap map(TraversabilityCloud{}, config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_projection_distance_m"), std::string::npos);
  }
  VehicleBox vehicle;
  vehicle.ground_clearance_m = 3.0;
  EXPECT_THROW(vehicle.Validate(), std::invalid_argument);
  // A cloud with a non-finite point: a clear error, not a grid built on it.
  const TraversabilityCloud bad({Vec3(0.0, 0.0, 0.0), Vec3(1.0, std::nan(""), 0.0)}, {Vec3::UnitZ(), Vec3::UnitZ()}, {1, 1});
  try {
    VertexCloudMap map(bad, VertexCloudMap::Config{});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ovpc::planner
