// The simulated Velodyne VLP-16 on the tilted spinning base, ray-cast with Embree.
//
// Scan model (the same as the core's synthetic_scene, so both sources agree):
//  - scan k covers [t0 + k / scan_hz, t0 + (k + 1) / scan_hz]; it is delivered at its end, with the
//    sensor pose at that time;
//  - a scan has n = round(2 pi / azimuth_step_rad) firings (905 at 20 Hz); firing j has azimuth
//    j * step and time t_start + j / (n scan_hz); its 16 lasers share that time and pose;
//  - every firing uses the sensor pose at its own time: the vehicle pose interpolated between the
//    two physics states around it (linear in position, slerp in rotation) composed with the
//    mount's spin at that exact time;
//  - each return is carried into the sensor frame at the scan's end with the true poses (exact
//    motion compensation, as a driver with a good IMU would do); odometry errors enter through the
//    scan's T_O_S, which the simulator sets;
//  - returns are stored firing by firing, laser id 0..15 within a firing; misses, returns closer
//    than min_range_m or beyond max_range_m, and dropouts are skipped.
// Range noise, dropouts and outliers are drawn from a stream seeded by (seed, scan index), so a
// scan does not depend on how the caller splits time into Advance calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ovpc/core/sensor_mount.h"
#include "ovpc/core/types.h"
#include "ovpc/sim/ray_caster.h"

namespace ovpc::sim {

/// A vehicle pose at a time.
struct TimedPose {
  double time_s = 0.0;
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
};

/// Interpolates between two poses (linear position, slerp rotation); `time_s` is clamped to
/// [a.time_s, b.time_s].
Eigen::Isometry3d InterpolatePose(const TimedPose& a, const TimedPose& b, double time_s);

/// One scan with the world's truth: points in the sensor frame at the scan's end, and its pose.
struct TrueScan {
  double time_s = 0.0;
  Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();
  Points points_S;
  std::size_t rays = 0;      ///< lasers fired (16 per firing)
  std::size_t dropouts = 0;  ///< returns removed by the dropout fault
  std::size_t outliers = 0;  ///< returns replaced by a random range
};

class Rng;

class Vlp16Sim {
 public:
  struct Config {
    SpinningLidarMount mount;  ///< 1.88 m, 45 deg tilt, 0.5 Hz spin, 20 Hz, 1-100 m
    double range_sigma_m = 0.015;     ///< Gaussian range noise (spec: +-3 cm)
    // Faults.
    double dropout_fraction = 0.0;    ///< returns lost at random
    double outlier_fraction = 0.0;    ///< rays given a uniform random range in [min range, hit]
    double extra_noise_sigma_m = 0.0; ///< added Gaussian range noise
    std::uint64_t seed = 1;

    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// `caster` must outlive the sensor. The first scan starts at `t0_s`.
  /// @throws std::invalid_argument if the config is invalid.
  Vlp16Sim(const Config& config, const RayCaster* caster, double t0_s = 0.0);
  ~Vlp16Sim();
  Vlp16Sim(Vlp16Sim&&) noexcept;
  Vlp16Sim& operator=(Vlp16Sim&&) noexcept;

  /// Fires every laser whose time lies in [from.time_s, to.time_s) and appends the scans that end
  /// at or before to.time_s to `completed`. Calls must be contiguous (each `from` the previous
  /// `to`) and start at or before the next firing. A firing's pose is taken when Advance reaches
  /// it; its rays are cast when its scan ends (all of a scan's firings at once, see SetParallelFor).
  void Advance(const TimedPose& from, const TimedPose& to, std::vector<TrueScan>* completed);

  /// Runs fn(i) for every i in [0, n), in any order and on any threads, and returns when all have.
  using ParallelFor = std::function<void(std::size_t n, const std::function<void(std::size_t)>& fn)>;
  /// How a scan's firings are cast: spread by `parallel_for` (empty: in order, on the caller's
  /// thread). Each firing draws its noise and faults from a stream of its own, seeded by the
  /// sensor's seed and the firing's index, so a scan is the same however its firings are spread.
  void SetParallelFor(ParallelFor parallel_for) { parallel_for_ = std::move(parallel_for); }

  /// Casts one firing: the 16 lasers from sensor pose `T_W_S` at azimuth `azimuth_rad`, noise
  /// and faults off. Ranges are +inf for misses and out-of-range hits. For tests and tools.
  std::vector<double> CastFiring(const Eigen::Isometry3d& T_W_S, double azimuth_rad) const;

  /// Unit direction of laser `laser` (0..15) at `azimuth_rad`, in the sensor frame.
  static Vec3 BeamDirection(int laser, double azimuth_rad);

  int firings_per_scan() const { return firings_per_scan_; }
  std::size_t rays_per_scan() const { return 16 * static_cast<std::size_t>(firings_per_scan_); }
  double scan_period_s() const { return 1.0 / config_.mount.scan_hz; }
  const Config& config() const { return config_; }

 private:
  /// A firing whose pose is known and whose rays are not cast yet.
  struct Firing {
    std::int64_t index;
    int azimuth;  ///< j: the firing within its scan
    Eigen::Matrix3d R_W_S;
    Vec3 origin_W;
  };
  struct FiringReturns;
  void StartScan();
  void CastPending();
  void CastOne(const Firing& firing, FiringReturns* out) const;

  Config config_;
  const RayCaster* caster_;
  double t0_s_;
  int firings_per_scan_;
  double firing_period_s_;
  std::int64_t next_firing_ = 0;  ///< global firing index since t0
  TrueScan current_;
  Points current_points_W_;
  std::vector<double> cos_azimuth_;
  std::vector<double> sin_azimuth_;
  std::vector<Firing> pending_;  ///< the current scan's firings, not cast yet
  ParallelFor parallel_for_;
};

}  // namespace ovpc::sim
