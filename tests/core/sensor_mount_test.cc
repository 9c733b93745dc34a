// The spinning mount's kinematics (sensor_mount.h).
#include "ovpc/core/sensor_mount.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ovpc {
namespace {

TEST(SpinningLidarMountTest, SensorHeightAndTiltAtTimeZero) {
  const SpinningLidarMount mount;
  const Eigen::Isometry3d T_B_S = mount.T_B_S(0.0);
  EXPECT_NEAR((T_B_S.translation() - Vec3(0.0, 0.0, 1.88)).norm(), 0.0, 1e-12);
  const Vec3 spin_axis_B = T_B_S.linear().col(2);
  EXPECT_NEAR(std::acos(spin_axis_B.dot(Vec3::UnitZ())), DegToRad(45.0), 1e-12);
  // Tilted about the base's x axis: the sensor's x axis stays horizontal along the base's x.
  EXPECT_NEAR((T_B_S.linear().col(0) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((spin_axis_B - Vec3(0.0, -std::sqrt(0.5), std::sqrt(0.5))).norm(), 0.0, 1e-12);
}

TEST(SpinningLidarMountTest, HalfRevolutionAfterOneSecond) {
  const SpinningLidarMount mount;  // 0.5 Hz
  const Eigen::Isometry3d T0 = mount.T_B_S(0.0);
  const Eigen::Isometry3d T1 = mount.T_B_S(1.0);
  const Eigen::Matrix3d yaw_change = T1.linear() * T0.linear().transpose();
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(kPi, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR((yaw_change - expected).norm(), 0.0, 1e-12);
  EXPECT_NEAR((T1.translation() - T0.translation()).norm(), 0.0, 1e-12);
  // The tilt is kept while spinning.
  EXPECT_NEAR(std::acos(T1.linear().col(2).z()), DegToRad(45.0), 1e-12);
  // A quarter revolution after 0.5 s.
  const Eigen::Matrix3d quarter = mount.T_B_S(0.5).linear() * T0.linear().transpose();
  EXPECT_NEAR((quarter - Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitZ()).toRotationMatrix()).norm(),
              0.0, 1e-12);
}

}  // namespace
}  // namespace ovpc
