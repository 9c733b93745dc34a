#include "ovpc/sim/world_model.h"

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "ovpc/sim/gator.h"
#include "ovpc/sim/ray_caster.h"

namespace ovpc::sim {
namespace {

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// --- The vehicle description --------------------------------------------------------------------

TEST(GatorTest, AckermannWheelsTurnAboutOneCentre) {
  const GatorParams p;
  for (const double steer_deg : {-30.0, -12.0, 5.0, 20.0, 30.0}) {
    const WheelCommands w = AckermannCommands(p, DegToRad(steer_deg), 2.0);
    const double radius = p.wheelbase_m / std::tan(DegToRad(steer_deg));  // signed, + = left
    // Each front wheel's axle line crosses the rear axle line at the turn centre (0, radius).
    EXPECT_NEAR(0.5 * p.track_m + p.wheelbase_m / std::tan(w.steer_left_rad), radius, 1e-9);
    EXPECT_NEAR(-0.5 * p.track_m + p.wheelbase_m / std::tan(w.steer_right_rad), radius, 1e-9);
    // Rear wheels roll at their own radii about that centre; B moves at the commanded speed.
    EXPECT_NEAR(w.drive_left_radps / w.drive_right_radps,
                (radius - 0.5 * p.track_m) / (radius + 0.5 * p.track_m), 1e-9);
    EXPECT_NEAR(0.5 * (w.drive_left_radps + w.drive_right_radps) * p.wheel_radius_m, 2.0, 1e-9);
  }
  const WheelCommands straight = AckermannCommands(p, 0.0, 1.0);
  EXPECT_EQ(straight.steer_left_rad, 0.0);
  EXPECT_EQ(straight.steer_right_rad, 0.0);
  // Limits: steering at full lock, speed at top speed.
  const WheelCommands clamped = AckermannCommands(p, 1.2, 100.0);
  const WheelCommands limit = AckermannCommands(p, DegToRad(30.0), 24.0 / 3.6);
  EXPECT_NEAR(clamped.steer_left_rad, limit.steer_left_rad, 1e-12);
  EXPECT_NEAR(clamped.steer_right_rad, limit.steer_right_rad, 1e-12);
  EXPECT_NEAR(clamped.drive_left_radps, limit.drive_left_radps, 1e-12);
  EXPECT_NEAR(clamped.drive_right_radps, limit.drive_right_radps, 1e-12);
}

TEST(GatorTest, NominalTurnRadiusFollowsTheGeometry) {
  const GatorParams p;
  EXPECT_NEAR(p.NominalTurnRadius_m(), 1.9 / std::tan(DegToRad(30.0)), 1e-12);
  GatorParams bad;
  bad.cg_x_m = 3.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

/// models/gator.xml is the generator's output for the defaults. To regenerate after changing
/// GatorParams: OVPC_UPDATE_MODELS=1 build/tests/ovpc_sim_tests --gtest_filter='GatorTest.*'
TEST(GatorTest, ModelFileMatchesTheGenerator) {
  const std::string path = std::string(OVPC_SOURCE_DIR) + "/models/gator.xml";
  const std::string generated = GatorStandaloneXml(GatorParams{});
  if (std::getenv("OVPC_UPDATE_MODELS") != nullptr) {
    std::ofstream(path) << generated;
  }
  std::ifstream file(path);
  ASSERT_TRUE(file) << "cannot read " << path;
  std::stringstream content;
  content << file.rdbuf();
  EXPECT_EQ(content.str(), generated)
      << "models/gator.xml is stale; regenerate with OVPC_UPDATE_MODELS=1 (see this test)";
}

TEST(GatorTest, StandaloneModelRestsOnItsWheelsWithoutWarnings) {
  std::string warning;
  const ModelPtr model = CompileMjcf(GatorStandaloneXml(GatorParams{}), &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  const mjModel* m = model.get();
  DataPtr d(mj_makeData(m));
  const double mass = mj_getTotalmass(m);
  EXPECT_NEAR(mass, 600.0 + 2.0, 1e-6);  // curb mass + the LiDAR base
  while (d->time < 1.5) mj_step(m, d.get());
  for (int i = 0; i < mjNWARNING; ++i) EXPECT_EQ(d->warning[i].number, 0) << "warning " << i;
  // The springs are preloaded for the static load: every slide sits near 0, B near the ground.
  for (const char* joint : {"suspension_rear_left", "suspension_rear_right",
                            "suspension_front_left", "suspension_front_right"}) {
    const int j = mj_name2id(m, mjOBJ_JOINT, joint);
    ASSERT_GE(j, 0) << joint;
    EXPECT_NEAR(d->qpos[m->jnt_qposadr[j]], 0.0, 0.01) << joint;
  }
  const int chassis = mj_name2id(m, mjOBJ_BODY, gator_names::kChassis);
  EXPECT_NEAR(d->xpos[3 * chassis + 2], 0.0, 0.01);
  EXPECT_NEAR(d->qvel[0], 0.0, 1e-3);
}

// --- The world model: physics and LiDAR see the same surfaces -----------------------------------

class WorldModelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.terrain.kind = TerrainConfig::Kind::kRough;
    world_.terrain.size_x_m = 24.0;
    world_.terrain.size_y_m = 24.0;
    world_.terrain.rough.amplitude_m = 0.25;
    world_.terrain.rough.feature_m = 4.0;
    BoxObject wall;
    wall.x_m = 6.0;
    wall.y_m = 6.0;
    wall.yaw_deg = 30.0;
    wall.length_m = 0.3;
    wall.width_m = 4.0;
    wall.height_m = 2.0;
    world_.boxes.push_back(wall);
    CylinderObject post;
    post.x_m = -6.0;
    post.y_m = 6.0;
    post.radius_m = 0.3;
    world_.cylinders.push_back(post);
    EllipsoidObject bush;
    bush.x_m = -6.0;
    bush.y_m = -6.0;
    bush.radius_x_m = 1.0;
    bush.radius_y_m = 0.6;
    world_.ellipsoids.push_back(bush);
    terrain_ = std::make_unique<Heightfield>(MakeHeightfield(world_.terrain));
    solids_ = ResolveSolids(world_, *terrain_);
    // The vehicle parked in a corner, out of the way of the test rays.
    const Eigen::Isometry3d T_W_B = RestingPose(*terrain_, GatorParams{}, 8.0, -8.0, 0.0);
    model_ = BuildWorldModel(*terrain_, solids_, GatorParams{}, T_W_B, PhysicsOptions{}, &warning_);
    data_.reset(mj_makeData(model_.get()));
    mj_forward(model_.get(), data_.get());
    caster_ = std::make_unique<RayCaster>(*terrain_, solids_);
  }

  /// MuJoCo's distance along a ray, or +inf.
  double MjRay(const Vec3& origin, const Vec3& direction) const {
    int geom = -1;
    const double d = mj_ray(model_.get(), data_.get(), origin.data(), direction.data(), nullptr, 1,
                            -1, &geom);
    return d < 0.0 ? std::numeric_limits<double>::infinity() : d;
  }

  World world_;
  std::unique_ptr<Heightfield> terrain_;
  std::vector<Solid> solids_;
  ModelPtr model_;
  DataPtr data_;
  std::string warning_;
  std::unique_ptr<RayCaster> caster_;
};

TEST_F(WorldModelTest, CompilesWithoutWarnings) {
  EXPECT_TRUE(warning_.empty()) << warning_;
  EXPECT_EQ(mj_name2id(model_.get(), mjOBJ_GEOM, "box0") >= 0, true);
  EXPECT_EQ(mj_name2id(model_.get(), mjOBJ_GEOM, "cylinder0") >= 0, true);
  EXPECT_EQ(mj_name2id(model_.get(), mjOBJ_GEOM, "ellipsoid0") >= 0, true);
}

TEST_F(WorldModelTest, HeightfieldMatchesTheTerrainAndTheLidarScene) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-4.0, 4.0);
  const double top = terrain_->max_height_m() + 5.0;
  for (int i = 0; i < 60; ++i) {
    const double x = coord(rng);
    const double y = coord(rng);
    const Vec3 origin(x, y, top);
    const Vec3 down(0.0, 0.0, -1.0);
    const double expected = terrain_->HeightAt(x, y);
    EXPECT_NEAR(top - MjRay(origin, down), expected, 1e-4) << x << " " << y;
    EXPECT_NEAR(top - caster_->Cast(origin, down, 100.0).range_m, expected, 1e-4) << x << " " << y;
  }
}

TEST_F(WorldModelTest, SolidsMatchBetweenPhysicsAndLidar) {
  // Horizontal rays from 3 m away, aimed across each object at a few heights and offsets. The
  // tessellated surfaces lie within the chord tolerance (2 mm) inside the exact ones; along an
  // oblique ray that is a little more.
  for (std::size_t s = 0; s < solids_.size(); ++s) {
    const Vec3 centre = solids_[s].T_W_X.translation();
    for (const double dy : {-0.2, 0.0, 0.15}) {
      for (const double dz : {-0.1, 0.0, 0.2}) {
        const Vec3 origin = centre + Vec3(-3.0, dy, dz);
        const Vec3 dir = Vec3(1.0, 0.0, 0.0);
        const double physics = MjRay(origin, dir);
        const RayCaster::Hit lidar = caster_->Cast(origin, dir, 100.0);
        ASSERT_TRUE(std::isfinite(physics)) << solids_[s].name;
        EXPECT_EQ(lidar.surface, static_cast<int>(s)) << solids_[s].name;
        EXPECT_NEAR(lidar.range_m, physics, 0.004) << solids_[s].name << " dy " << dy << " dz " << dz;
      }
    }
  }
}

TEST_F(WorldModelTest, RestingPoseFollowsTheGround) {
  const GatorParams p;
  const Eigen::Isometry3d T = RestingPose(*terrain_, p, 1.0, 2.0, 0.7);
  for (const Vec3& wheel_B : {Vec3(0.0, 0.6, 0.0), Vec3(0.0, -0.6, 0.0), Vec3(1.9, 0.6, 0.0),
                              Vec3(1.9, -0.6, 0.0)}) {
    const Vec3 w = T * wheel_B;
    const double gap = w.z() - terrain_->HeightAt(w.x(), w.y());
    EXPECT_GE(gap, 0.01 - 1e-9);
    EXPECT_LT(gap, 0.3);
  }
}

}  // namespace
}  // namespace ovpc::sim
