// The spinning mount's kinematics (see sensor_mount.h).
#include "ovpc/core/sensor_mount.h"

#include <cmath>

namespace ovpc {

Eigen::Isometry3d SpinningLidarMount::T_B_S(double time_s) const {
  // fmod keeps the yaw accurate for large times.
  const double yaw_rad = 2.0 * kPi * std::fmod(spin_hz * time_s, 1.0);
  Eigen::Isometry3d T_B_S = Eigen::Isometry3d::Identity();
  T_B_S.translation() = Vec3(0.0, 0.0, height_m);
  T_B_S.linear() = (Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()) *
                    Eigen::AngleAxisd(tilt_rad, Vec3::UnitX()))
                       .toRotationMatrix();
  return T_B_S;
}

}  // namespace ovpc
