#include "ovpc/sim/terrain.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ovpc/sim/world.h"

namespace ovpc::sim {
namespace {

TerrainConfig Small(TerrainConfig::Kind kind) {
  TerrainConfig config;
  config.kind = kind;
  config.size_x_m = 20.0;
  config.size_y_m = 16.0;
  config.cell_m = 0.25;
  return config;
}

TEST(TerrainTest, GridCoversTheExtentCentredOnTheOrigin) {
  const Heightfield hf = MakeHeightfield(Small(TerrainConfig::Kind::kFlat));
  EXPECT_EQ(hf.num_cols(), 81);
  EXPECT_EQ(hf.num_rows(), 65);
  EXPECT_DOUBLE_EQ(hf.x_min_m(), -10.0);
  EXPECT_DOUBLE_EQ(hf.x_max_m(), 10.0);
  EXPECT_DOUBLE_EQ(hf.y_min_m(), -8.0);
  EXPECT_DOUBLE_EQ(hf.y_max_m(), 8.0);
  EXPECT_EQ(hf.min_height_m(), 0.0);
  EXPECT_EQ(hf.max_height_m(), 0.0);
  // Sizes that are not whole cells are rounded up.
  TerrainConfig odd = Small(TerrainConfig::Kind::kFlat);
  odd.size_x_m = 20.1;
  EXPECT_EQ(MakeHeightfield(odd).num_cols(), 82);
}

TEST(TerrainTest, PlanarSlopeIsExactEverywhere) {
  TerrainConfig config = Small(TerrainConfig::Kind::kSlope);
  config.slope.angle_deg = 20.0;
  config.direction_deg = 30.0;
  const Heightfield hf = MakeHeightfield(config);
  const double tan_a = std::tan(DegToRad(20.0));
  const Vec3 dir(std::cos(DegToRad(30.0)), std::sin(DegToRad(30.0)), 0.0);
  for (double x = -9.9; x < 9.9; x += 0.37) {
    for (double y = -7.9; y < 7.9; y += 0.41) {
      EXPECT_NEAR(hf.HeightAt(x, y), tan_a * (x * dir.x() + y * dir.y()), 1e-9);
    }
  }
  const Vec3 expected_normal = Vec3(-tan_a * dir.x(), -tan_a * dir.y(), 1.0).normalized();
  EXPECT_NEAR((hf.NormalAt(1.3, -2.2) - expected_normal).norm(), 0.0, 1e-9);
}

TEST(TerrainTest, RampRisesToItsPlateau) {
  TerrainConfig config = Small(TerrainConfig::Kind::kRamp);
  config.ramp.start_m = 2.0;
  config.ramp.angle_deg = 25.0;
  config.ramp.height_m = 1.5;
  const Heightfield hf = MakeHeightfield(config);
  EXPECT_NEAR(hf.HeightAt(1.0, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(hf.HeightAt(3.0, 0.0), std::tan(DegToRad(25.0)), 1e-9);  // on a grid line
  EXPECT_NEAR(hf.HeightAt(9.0, 3.0), 1.5, 1e-12);
  EXPECT_NEAR(hf.max_height_m(), 1.5, 1e-12);
}

TEST(TerrainTest, DitchHasItsDepthAndWidth) {
  TerrainConfig config = Small(TerrainConfig::Kind::kDitch);
  config.ditch.centre_m = 0.0;
  config.ditch.depth_m = 0.5;
  config.ditch.bottom_width_m = 1.0;
  config.ditch.wall_angle_deg = 45.0;  // top width 1 + 2 * 0.5 = 2 m
  const Heightfield hf = MakeHeightfield(config);
  EXPECT_NEAR(hf.HeightAt(0.0, 2.0), -0.5, 1e-12);
  EXPECT_NEAR(hf.HeightAt(0.5, 2.0), -0.5, 1e-12);
  EXPECT_NEAR(hf.HeightAt(0.75, 2.0), -0.25, 1e-12);
  EXPECT_NEAR(hf.HeightAt(1.0, 2.0), 0.0, 1e-12);
  EXPECT_NEAR(hf.HeightAt(-3.0, 2.0), 0.0, 1e-12);
  EXPECT_NEAR(hf.min_height_m(), -0.5, 1e-12);
}

TEST(TerrainTest, RoughGroundIsBoundedDeterministicAndSeeded) {
  TerrainConfig config = Small(TerrainConfig::Kind::kRough);
  config.rough.amplitude_m = 0.3;
  config.rough.seed = 7;
  const Heightfield a = MakeHeightfield(config);
  const Heightfield b = MakeHeightfield(config);
  EXPECT_EQ(a.heights_m(), b.heights_m());
  EXPECT_LE(a.max_height_m(), 0.3);
  EXPECT_GE(a.min_height_m(), -0.3);
  EXPECT_GT(a.max_height_m() - a.min_height_m(), 0.15);  // actually rough
  config.rough.seed = 8;
  EXPECT_NE(MakeHeightfield(config).heights_m(), a.heights_m());
  // The overlay also applies to the other kinds.
  TerrainConfig slope = Small(TerrainConfig::Kind::kSlope);
  slope.rough = config.rough;
  const Heightfield s = MakeHeightfield(slope);
  EXPECT_NE(s.HeightAt(1.1, 1.1), ProfileHeight(slope, 1.1, 1.1));
}

TEST(TerrainTest, CellsSplitAlongTheDiagonalMuJoCoUses) {
  // One raised vertex at (r + 1, c + 1): the diagonal (r, c)-(r + 1, c + 1) carries it, the
  // other diagonal would not.
  std::vector<double> heights(9, 0.0);
  heights[4] = 1.0;  // row 1, column 1 of a 3 x 3 grid
  const Heightfield hf(3, 3, 0.0, 0.0, 1.0, heights);
  EXPECT_NEAR(hf.HeightAt(0.5, 0.5), 0.5, 1e-12);   // on the diagonal of cell (0, 0)
  EXPECT_NEAR(hf.HeightAt(0.75, 0.25), 0.25, 1e-12);  // lower-right triangle (0,0),(0,1),(1,1)
  EXPECT_NEAR(hf.HeightAt(0.25, 0.75), 0.25, 1e-12);  // upper-left triangle (0,0),(1,1),(1,0)
  // Cell (0, 1): the raised vertex is (r + 1, c) there, off the diagonal, whose ends are low.
  EXPECT_NEAR(hf.HeightAt(1.5, 0.5), 0.0, 1e-12);
  EXPECT_NEAR(hf.HeightAt(1.75, 0.25), 0.0, 1e-12);
  EXPECT_NEAR(hf.HeightAt(1.25, 0.75), 0.5, 1e-12);
  // Outside the grid the height is clamped onto its edge.
  EXPECT_NEAR(hf.HeightAt(-5.0, 1.0), 0.0, 1e-12);
  EXPECT_NEAR(hf.MinHeightIn(0.9, 0.9, 1.1, 1.1), 0.0, 1e-12);
}

TEST(TerrainTest, InvalidConfigsNameTheField) {
  TerrainConfig config;
  config.cell_m = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = TerrainConfig{};
  config.kind = TerrainConfig::Kind::kRough;  // needs an amplitude
  try {
    config.Validate();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rough.amplitude_m"), std::string::npos) << e.what();
  }
  config = TerrainConfig{};
  config.kind = TerrainConfig::Kind::kRamp;
  config.ramp.angle_deg = 95.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = TerrainConfig{};
  config.size_x_m = 5000.0;
  config.size_y_m = 5000.0;
  config.cell_m = 0.1;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

// --- World ------------------------------------------------------------------------------------

TEST(WorldTest, CarportExpandsToRoofAndFourGroundedPosts) {
  World world;
  world.terrain = Small(TerrainConfig::Kind::kSlope);
  world.terrain.slope.angle_deg = 10.0;
  CarportObject carport;
  carport.x_m = 2.0;
  carport.y_m = 1.0;
  carport.yaw_deg = 90.0;
  world.carports.push_back(carport);
  const Heightfield hf = MakeHeightfield(world.terrain);
  const std::vector<Solid> solids = ResolveSolids(world, hf);
  ASSERT_EQ(solids.size(), 5u);
  EXPECT_EQ(solids[0].name, "carport0_roof");
  const double underside = hf.HeightAt(2.0, 1.0) + 2.5;
  EXPECT_NEAR(solids[0].T_W_X.translation().z() - solids[0].half_extents.z(), underside, 1e-9);
  // Rotated by 90 deg: the roof's long side runs along y.
  EXPECT_NEAR(std::abs((solids[0].T_W_X.linear() * Vec3::UnitX()).y()), 1.0, 1e-12);
  for (int i = 1; i < 5; ++i) {
    const Solid& post = solids[static_cast<std::size_t>(i)];
    EXPECT_EQ(post.shape, Solid::Shape::kCylinder);
    const Vec3 c = post.T_W_X.translation();
    const double bottom = c.z() - post.half_extents.z();
    const double top = c.z() + post.half_extents.z();
    EXPECT_NEAR(top, underside, 1e-9);
    // Reaches below the ground everywhere under its footprint.
    for (const double dx : {-0.08, 0.08}) {
      EXPECT_LE(bottom, hf.HeightAt(c.x() + dx, c.y()) + 1e-9);
    }
  }
}

TEST(WorldTest, ObjectsAreMeasuredFromTheGround) {
  World world;
  world.terrain = Small(TerrainConfig::Kind::kRamp);
  world.terrain.ramp.start_m = 0.0;
  world.terrain.ramp.height_m = 3.0;
  BoxObject roof;
  roof.x_m = 2.0;
  roof.base_m = 2.0;
  roof.height_m = 0.1;
  world.boxes.push_back(roof);
  EllipsoidObject crown;
  crown.x_m = -3.0;
  crown.centre_height_m = 4.0;
  world.ellipsoids.push_back(crown);
  const Heightfield hf = MakeHeightfield(world.terrain);
  const std::vector<Solid> solids = ResolveSolids(world, hf);
  ASSERT_EQ(solids.size(), 2u);
  // A floating box keeps its base height.
  EXPECT_NEAR(solids[0].T_W_X.translation().z(), hf.HeightAt(2.0, 0.0) + 2.05, 1e-9);
  EXPECT_NEAR(solids[0].half_extents.z(), 0.05, 1e-12);
  EXPECT_NEAR(solids[1].T_W_X.translation().z(), 4.0, 1e-12);
  EXPECT_EQ(solids[1].name, "ellipsoid0");
}

TEST(WorldTest, InvalidObjectsNameTheObjectAndField) {
  World world;
  world.cylinders.push_back(CylinderObject{});
  world.cylinders[0].radius_m = -1.0;
  try {
    world.Validate();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cylinders[0].radius_m"), std::string::npos) << e.what();
  }
  world = World{};
  world.carports.push_back(CarportObject{});
  world.carports[0].post_inset_m = 0.01;  // post would stick out of the roof
  EXPECT_THROW(world.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::sim
