// Simulated local odometry: a gravity-aligned pose of the vehicle in the odometry frame O, derived
// from the true motion with drift, noise and bumps. Roll and pitch are the true ones (an IMU gives
// gravity); position and yaw are integrated from the true increments with errors:
//  - drift: a random walk in x, y, z and yaw whose variance grows with the distance travelled
//    (sigma per square root of metre), applied in the odometry's own heading, so a yaw error
//    bends all later motion as it does on a real vehicle;
//  - noise: white Gaussian jitter on each reported pose (not integrated);
//  - bumps: sudden pose jumps at given times (the paper's robot failed on such bumps), in the
//    vehicle's heading frame, kept from then on.
// O coincides with the world frame W at the first update. Deterministic from the seed and the
// sequence of updates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::sim {

class Rng;

class OdometrySim {
 public:
  struct Bump {
    double time_s = 0.0;
    double forward_m = 0.0;  ///< along the heading
    double left_m = 0.0;
    double up_m = 0.0;
    double yaw_rad = 0.0;
  };

  struct Config {
    double drift_xy_m_per_sqrt_m = 0.0;   ///< horizontal random walk, each axis
    double drift_z_m_per_sqrt_m = 0.0;
    double drift_yaw_rad_per_sqrt_m = 0.0;
    double noise_xy_m = 0.0;              ///< white noise on reported poses, each axis
    double noise_z_m = 0.0;
    double noise_yaw_rad = 0.0;
    std::vector<Bump> bumps;
    std::uint64_t seed = 1;

    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument if the config is invalid.
  explicit OdometrySim(const Config& config);
  ~OdometrySim();
  OdometrySim(OdometrySim&&) noexcept;
  OdometrySim& operator=(OdometrySim&&) noexcept;

  /// Feeds the true pose at `time_s` (times must not decrease). The first call sets O = W.
  void Update(double time_s, const Eigen::Isometry3d& T_W_B);

  /// The latest reported pose of B in O (identity before the first update).
  const Eigen::Isometry3d& T_O_B() const { return T_O_B_; }
  /// T_O_W at the latest update: maps a true pose to the odometry frame (T_O_X = T_O_W * T_W_X),
  /// for frames rigidly attached to the vehicle near that time (the sensor at a scan's end).
  Eigen::Isometry3d T_O_W() const { return T_O_B_ * T_W_B_.inverse(); }
  double distance_m() const { return distance_m_; }
  std::size_t bumps_applied() const { return next_bump_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  std::unique_ptr<Rng> rng_;
  bool started_ = false;
  double time_s_ = 0.0;
  Eigen::Isometry3d T_W_B_ = Eigen::Isometry3d::Identity();  ///< last true pose
  Eigen::Isometry3d T_O_B_ = Eigen::Isometry3d::Identity();  ///< last reported pose
  Vec3 position_O_ = Vec3::Zero();  ///< integrated position (noise-free part)
  double yaw_O_ = 0.0;              ///< integrated yaw (noise-free part)
  double distance_m_ = 0.0;
  std::size_t next_bump_ = 0;
  std::vector<Bump> bumps_;  ///< sorted by time
};

/// Yaw of a rotation: the heading of its x axis in the horizontal plane.
double YawOf(const Eigen::Matrix3d& R);

}  // namespace ovpc::sim
