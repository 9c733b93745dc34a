#include "ovpc/sim/odometry.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/sim/simulator.h"

namespace ovpc::sim {
namespace {

/// A true path: a curve on a hill, rolling and pitching, sampled every 10 ms for `seconds`.
std::vector<std::pair<double, Eigen::Isometry3d>> CurvedPath(double seconds) {
  std::vector<std::pair<double, Eigen::Isometry3d>> path;
  for (int i = 0; i <= static_cast<int>(seconds * 100.0); ++i) {
    const double t = 0.01 * i;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double yaw = 0.3 * t;
    T.translation() = Vec3(3.0 * std::sin(0.3 * t) / 0.3, 3.0 * (1.0 - std::cos(0.3 * t)) / 0.3,
                           0.2 * t);
    T.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(0.1, Vec3::UnitY()) *
                  Eigen::AngleAxisd(0.05 * std::sin(t), Vec3::UnitX()))
                     .toRotationMatrix();
    path.emplace_back(t, T);
  }
  return path;
}

std::vector<Eigen::Isometry3d> RunOdometry(const OdometrySim::Config& config, double seconds) {
  OdometrySim odometry(config);
  std::vector<Eigen::Isometry3d> out;
  for (const auto& [t, T_W_B] : CurvedPath(seconds)) {
    odometry.Update(t, T_W_B);
    out.push_back(odometry.T_O_B());
  }
  return out;
}

TEST(OdometryTest, WithoutErrorsItIsTheTruePose) {
  const auto path = CurvedPath(10.0);
  const auto odom = RunOdometry(OdometrySim::Config{}, 10.0);
  for (std::size_t i = 0; i < path.size(); ++i) {
    EXPECT_TRUE(odom[i].isApprox(path[i].second, 1e-9)) << i;
  }
}

TEST(OdometryTest, DeterministicFromTheSeed) {
  OdometrySim::Config config;
  config.drift_xy_m_per_sqrt_m = 0.02;
  config.drift_yaw_rad_per_sqrt_m = 0.005;
  config.noise_xy_m = 0.01;
  config.seed = 5;
  const auto a = RunOdometry(config, 5.0);
  const auto b = RunOdometry(config, 5.0);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].matrix(), b[i].matrix());
  config.seed = 6;
  EXPECT_NE(RunOdometry(config, 5.0).back().matrix(), a.back().matrix());
}

TEST(OdometryTest, StaysGravityAligned) {
  OdometrySim::Config config;
  config.drift_xy_m_per_sqrt_m = 0.05;
  config.drift_yaw_rad_per_sqrt_m = 0.02;
  config.noise_yaw_rad = 0.01;
  const auto path = CurvedPath(10.0);
  const auto odom = RunOdometry(config, 10.0);
  for (std::size_t i = 0; i < path.size(); ++i) {
    // Only the heading differs: the body's z axis has the same tilt from vertical.
    EXPECT_NEAR(odom[i].linear()(2, 2), path[i].second.linear()(2, 2), 1e-9);
    EXPECT_NEAR(odom[i].linear().col(0).z(), path[i].second.linear().col(0).z(), 1e-9);
  }
}

TEST(OdometryTest, DriftGrowsWithTheSquareRootOfDistance) {
  // Straight line, 100 m: the horizontal error's spread over seeds is sigma * sqrt(100) per axis.
  OdometrySim::Config config;
  config.drift_xy_m_per_sqrt_m = 0.01;
  double sum_sq = 0.0;
  constexpr int kSeeds = 200;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    config.seed = static_cast<std::uint64_t>(seed);
    OdometrySim odometry(config);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int i = 0; i <= 100; ++i) {
      T.translation().x() = i;
      odometry.Update(i, T);
    }
    EXPECT_NEAR(odometry.distance_m(), 100.0, 1e-9);
    sum_sq += (odometry.T_O_B().translation() - T.translation()).head<2>().squaredNorm();
  }
  const double rms_per_axis = std::sqrt(sum_sq / (2.0 * kSeeds));
  EXPECT_NEAR(rms_per_axis, 0.1, 0.015);
}

TEST(OdometryTest, NoiseDoesNotAccumulate) {
  OdometrySim::Config config;
  config.noise_xy_m = 0.05;
  const auto path = CurvedPath(30.0);
  const auto odom = RunOdometry(config, 30.0);
  double max_error = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    max_error = std::max(max_error, (odom[i].translation() - path[i].second.translation()).norm());
  }
  EXPECT_GT(max_error, 0.05);
  EXPECT_LT(max_error, 0.4);  // about 5.5 sigma of a 2D Gaussian over 3000 samples
}

TEST(OdometryTest, BumpsJumpAtTheirTimeAndStay) {
  OdometrySim::Config config;
  OdometrySim::Bump bump;
  bump.time_s = 2.0;
  bump.forward_m = 0.3;
  bump.yaw_rad = DegToRad(5.0);
  config.bumps.push_back(bump);
  const auto path = CurvedPath(4.0);
  const auto odom = RunOdometry(config, 4.0);
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double t = path[i].first;
    const Eigen::Isometry3d error = odom[i] * path[i].second.inverse();  // T_O_W
    if (t < 2.0 - 1e-9) {
      EXPECT_TRUE(error.isApprox(Eigen::Isometry3d::Identity(), 1e-9)) << t;
    } else {
      EXPECT_NEAR(YawOf(error.linear()), DegToRad(5.0), 1e-9) << t;
    }
  }
  // At the bump the vehicle appears 0.3 m further along its heading, turned by 5 deg.
  const std::size_t k = 200;  // t = 2.0
  ASSERT_NEAR(path[k].first, 2.0, 1e-12);
  const Vec3 jump = odom[k].translation() - path[k].second.translation();
  const double heading = YawOf(path[k].second.linear());
  EXPECT_NEAR(jump.x(), 0.3 * std::cos(heading), 1e-9);
  EXPECT_NEAR(jump.y(), 0.3 * std::sin(heading), 1e-9);
}

TEST(OdometryTest, InvalidConfigsNameTheField) {
  OdometrySim::Config config;
  config.noise_xy_m = -1.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  OdometrySim odometry{OdometrySim::Config{}};
  odometry.Update(1.0, Eigen::Isometry3d::Identity());
  EXPECT_THROW(odometry.Update(0.5, Eigen::Isometry3d::Identity()), std::invalid_argument);
}

TEST(SimulatorOdometryTest, ScansCarryTheOdometryPose) {
  Simulator::Config config;
  config.world.terrain.size_x_m = 30.0;
  config.world.terrain.size_y_m = 20.0;
  OdometrySim::Bump bump;
  bump.time_s = 0.52;  // between two scans
  bump.left_m = 0.2;
  config.odometry.bumps.push_back(bump);
  Simulator sim(config);
  sim.SetCommand(0.0, 2.0);
  sim.StepFor(1.0);
  const auto scans = sim.TakeScans();
  ASSERT_EQ(scans.size(), 20u);
  for (const Simulator::SensorScan& s : scans) {
    const Vec3 offset = s.scan.T_O_S.translation() - s.T_W_S.translation();
    if (s.scan.time_s < 0.52) {
      EXPECT_LT(offset.norm(), 1e-9) << s.scan.time_s;
    } else {
      EXPECT_NEAR(offset.norm(), 0.2, 0.01) << s.scan.time_s;  // the bump, nearly sideways
    }
  }
  EXPECT_EQ(sim.odometry().bumps_applied(), 1u);
}

}  // namespace
}  // namespace ovpc::sim
