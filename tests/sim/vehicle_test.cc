// The vehicle in the simulator: speed and heading, slopes, turning, contacts, warnings. Every test
// fails on any MuJoCo warning. The LiDAR is off where it is not needed, to keep the suite fast.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/sim/simulator.h"

namespace ovpc::sim {
namespace {

std::string Join(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

#define EXPECT_NO_MUJOCO_WARNINGS(sim) EXPECT_TRUE((sim).Warnings().empty()) << Join((sim).Warnings())

Simulator::Config PhysicsOnly(double size_x_m, double size_y_m) {
  Simulator::Config config;
  config.world.terrain.size_x_m = size_x_m;
  config.world.terrain.size_y_m = size_y_m;
  config.lidar_enabled = false;
  return config;
}

/// Angle between B's z axis and the vertical.
double TiltRad(const Eigen::Isometry3d& T_W_B) {
  return std::acos(std::clamp(T_W_B.linear()(2, 2), -1.0, 1.0));
}

/// Least-squares circle through 2D points (algebraic fit): returns the radius.
double FitCircleRadius(const std::vector<Eigen::Vector2d>& pts) {
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    A(static_cast<Eigen::Index>(i), 0) = pts[i].x();
    A(static_cast<Eigen::Index>(i), 1) = pts[i].y();
    A(static_cast<Eigen::Index>(i), 2) = 1.0;
    b(static_cast<Eigen::Index>(i)) = -pts[i].squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d centre = -0.5 * s.head<2>();
  return std::sqrt(centre.squaredNorm() - s.z());
}

TEST(VehicleTest, DrivesStraightAtTheCommandedSpeed) {
  Simulator::Config config = PhysicsOnly(40.0, 16.0);
  config.start_x_m = -15.0;
  Simulator sim(config);
  sim.StepFor(0.5);  // settle on the suspension
  sim.SetCommand(0.0, 1.0);
  sim.StepFor(2.0);  // accelerate
  const Eigen::Isometry3d start = sim.T_W_B();
  const double yaw0 = YawOf(start.linear());
  double min_speed = 1e9;
  double max_speed = -1e9;
  while ((sim.T_W_B().translation() - start.translation()).norm() < 20.0 && sim.time_s() < 40.0) {
    sim.StepFor(0.1);
    min_speed = std::min(min_speed, sim.forward_speed_mps());
    max_speed = std::max(max_speed, sim.forward_speed_mps());
  }
  EXPECT_GE((sim.T_W_B().translation() - start.translation()).norm(), 20.0);
  EXPECT_GT(min_speed, 0.95);
  EXPECT_LT(max_speed, 1.05);
  EXPECT_LT(std::abs(RadToDeg(YawOf(sim.T_W_B().linear()) - yaw0)), 1.0);
  EXPECT_EQ(sim.body_contact_steps(), 0u);
  EXPECT_NO_MUJOCO_WARNINGS(sim);
}

TEST(VehicleTest, Climbs25DegreeSlope) {
  Simulator::Config config = PhysicsOnly(30.0, 12.0);
  config.world.terrain.kind = TerrainConfig::Kind::kRamp;
  config.world.terrain.ramp.start_m = 0.0;
  config.world.terrain.ramp.angle_deg = 25.0;
  config.world.terrain.ramp.height_m = 2.5;  // 5.4 m of slope, longer than the vehicle
  config.start_x_m = -4.0;
  Simulator sim(config);
  sim.StepFor(0.5);
  sim.SetCommand(0.0, 1.0);
  double max_pitch_deg = 0.0;
  double min_speed_on_slope = 1e9;
  double speed_sum_on_slope = 0.0;
  int samples_on_slope = 0;
  while (sim.T_W_B().translation().x() < 8.0 && sim.time_s() < 20.0) {
    sim.StepFor(0.1);
    const double pitch_deg = RadToDeg(TiltRad(sim.T_W_B()));
    max_pitch_deg = std::max(max_pitch_deg, pitch_deg);
    if (pitch_deg > 22.0) {  // both axles on the slope
      min_speed_on_slope = std::min(min_speed_on_slope, sim.forward_speed_mps());
      speed_sum_on_slope += sim.forward_speed_mps();
      ++samples_on_slope;
    }
  }
  EXPECT_GE(sim.T_W_B().translation().x(), 8.0) << "stuck at t = " << sim.time_s();
  EXPECT_NEAR(sim.T_W_B().translation().z(), 2.5, 0.05);  // on the plateau
  EXPECT_GT(max_pitch_deg, 24.0);
  ASSERT_GT(samples_on_slope, 10);
  EXPECT_GT(min_speed_on_slope, 0.5);  // slows at the foot of the ramp, never stalls
  EXPECT_GT(speed_sum_on_slope / samples_on_slope, 0.85);
  EXPECT_EQ(sim.body_contact_steps(), 0u);
  EXPECT_NO_MUJOCO_WARNINGS(sim);
}

TEST(VehicleTest, FullLockTurnRadiusMatchesTheNominal) {
  Simulator::Config config = PhysicsOnly(20.0, 20.0);
  config.start_x_m = 0.0;
  config.start_y_m = -3.0;
  Simulator sim(config);
  sim.StepFor(0.5);
  sim.SetCommand(DegToRad(90.0), 1.0);  // clamped to full lock, left
  sim.StepFor(2.0);
  std::vector<Eigen::Vector2d> path;
  for (int i = 0; i < 120; ++i) {
    sim.StepFor(0.1);
    path.push_back(sim.T_W_B().translation().head<2>());
  }
  const double nominal = config.vehicle.NominalTurnRadius_m();
  const double radius = FitCircleRadius(path);
  EXPECT_NEAR(radius, nominal, 0.1 * nominal) << "radius " << radius << " nominal " << nominal;
  EXPECT_GT(sim.yaw_rate_radps(), 0.0);  // left
  EXPECT_NO_MUJOCO_WARNINGS(sim);
}

TEST(VehicleTest, DoesNotTipOn20DegreeSideSlope) {
  for (const double heading : {0.0, kPi}) {  // slope rising to the left, then to the right
    Simulator::Config config = PhysicsOnly(24.0, 16.0);
    config.world.terrain.kind = TerrainConfig::Kind::kSlope;
    config.world.terrain.slope.angle_deg = 20.0;
    config.world.terrain.direction_deg = 90.0;  // rises along +y
    config.start_x_m = heading == 0.0 ? -5.0 : 5.0;
    config.start_yaw_rad = heading;
    Simulator sim(config);
    double max_tilt_deg = 0.0;
    sim.StepFor(1.0);  // parked across the slope
    max_tilt_deg = RadToDeg(TiltRad(sim.T_W_B()));
    sim.SetCommand(0.0, 1.0);
    for (int i = 0; i < 80; ++i) {
      sim.StepFor(0.1);
      max_tilt_deg = std::max(max_tilt_deg, RadToDeg(TiltRad(sim.T_W_B())));
    }
    EXPECT_GT(max_tilt_deg, 19.0) << "heading " << heading;
    EXPECT_LT(max_tilt_deg, 25.0) << "heading " << heading;
    EXPECT_GT((sim.T_W_B().translation().x() - config.start_x_m) * std::cos(heading), 6.0);
    EXPECT_EQ(sim.body_contact_steps(), 0u);
    EXPECT_NO_MUJOCO_WARNINGS(sim);
  }
}

TEST(VehicleTest, ReportsBodyContactsWithTheWorld) {
  Simulator::Config config = PhysicsOnly(20.0, 10.0);
  BoxObject wall;
  wall.x_m = 5.0;
  wall.length_m = 0.3;
  wall.width_m = 4.0;
  wall.height_m = 1.2;
  config.world.boxes.push_back(wall);
  BoxObject low_roof;  // above the deck, below the roll-over frame
  low_roof.x_m = -4.0;
  low_roof.length_m = 3.0;
  low_roof.width_m = 3.0;
  low_roof.base_m = 1.6;
  low_roof.height_m = 0.2;
  config.world.boxes.push_back(low_roof);
  config.start_x_m = -1.0;
  Simulator sim(config);
  sim.StepFor(0.5);
  EXPECT_TRUE(sim.BodyContacts().empty());
  sim.SetCommand(0.0, 1.0);
  std::vector<BodyContact> contacts;
  for (int i = 0; i < 80 && contacts.empty(); ++i) {
    sim.StepFor(0.1);
    contacts = sim.BodyContacts();
  }
  ASSERT_FALSE(contacts.empty()) << "no contact with the wall";
  EXPECT_EQ(contacts[0].world_geom, "box0");
  EXPECT_EQ(contacts[0].vehicle_geom.rfind("body_", 0), 0u) << contacts[0].vehicle_geom;
  // The front bumper is 2.35 m ahead of B: it meets the wall's near face at x = 4.85.
  EXPECT_NEAR(contacts[0].position_W.x(), 4.85, 0.1);
  EXPECT_GT(sim.body_contact_steps(), 0u);

  // Backing under the low roof: the roll-over frame or the mast hits it.
  sim.SetCommand(0.0, -1.5);
  contacts.clear();
  for (int i = 0; i < 100 && contacts.empty(); ++i) {
    sim.StepFor(0.1);
    for (const BodyContact& c : sim.BodyContacts()) {
      if (c.world_geom == "box1") contacts.push_back(c);
    }
  }
  ASSERT_FALSE(contacts.empty()) << "no contact with the roof";
  EXPECT_NE(contacts[0].vehicle_geom.find("body_"), std::string::npos);
  EXPECT_NO_MUJOCO_WARNINGS(sim);
}

TEST(VehicleTest, MuJoCoWarningsAreReported) {
  Simulator::Config config = PhysicsOnly(10.0, 10.0);
  config.physics.nconmax = 2;  // four wheels on the ground need more
  Simulator sim(config);
  sim.StepFor(0.2);
  const std::vector<std::string> warnings = sim.Warnings();
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(Join(warnings).find("contact buffer full"), std::string::npos) << Join(warnings);
}

TEST(VehicleTest, IsDeterministic) {
  Simulator::Config config = PhysicsOnly(16.0, 16.0);
  config.world.terrain.kind = TerrainConfig::Kind::kRough;
  config.world.terrain.rough.amplitude_m = 0.2;
  config.lidar_enabled = true;
  Simulator a(config);
  Simulator b(config);
  for (Simulator* sim : {&a, &b}) {
    sim->SetCommand(0.2, 1.5);
    sim->StepFor(1.0);
  }
  EXPECT_EQ(a.T_W_B().matrix(), b.T_W_B().matrix());
  const auto scans_a = a.TakeScans();
  const auto scans_b = b.TakeScans();
  ASSERT_EQ(scans_a.size(), scans_b.size());
  ASSERT_FALSE(scans_a.empty());
  EXPECT_EQ(scans_a.back().scan.points_S, scans_b.back().scan.points_S);
  EXPECT_NO_MUJOCO_WARNINGS(a);
}

TEST(VehicleTest, LidarSiteOfTheModelIsTheSensorPose) {
  Simulator::Config config = PhysicsOnly(16.0, 16.0);
  config.world.terrain.kind = TerrainConfig::Kind::kRough;
  config.world.terrain.rough.amplitude_m = 0.2;
  Simulator sim(config);
  sim.SetCommand(0.3, 2.0);
  sim.StepFor(1.3);
  // Recompute MuJoCo's kinematics at the current state on a copy of its data.
  const mjModel* m = sim.model();
  mjData* d = mj_makeData(m);
  mj_copyData(d, m, sim.data());
  mj_kinematics(m, d);
  const int site = mj_name2id(m, mjOBJ_SITE, gator_names::kLidarSite);
  ASSERT_GE(site, 0);
  Eigen::Isometry3d T_W_site = Eigen::Isometry3d::Identity();
  T_W_site.translation() = Vec3(d->site_xpos[3 * site], d->site_xpos[3 * site + 1],
                                d->site_xpos[3 * site + 2]);
  T_W_site.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
      d->site_xmat + 9 * site);
  mj_deleteData(d);
  const Eigen::Isometry3d T_W_S = sim.T_W_S();
  EXPECT_NEAR((T_W_site.translation() - T_W_S.translation()).norm(), 0.0, 1e-3);
  EXPECT_NEAR(Eigen::AngleAxisd(T_W_site.linear().transpose() * T_W_S.linear()).angle(), 0.0, 2e-3);
}

}  // namespace
}  // namespace ovpc::sim
