// Analytic outdoor scenes and a VLP-16 on a tilted spinning base, for tests, benchmarks and the
// bundled sample cloud. The closed-loop simulator casts rays with Embree instead; the beam pattern
// and mount kinematics here are the same facts (see docs/REFERENCE.md).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/core/types.h"

namespace ovpc::synth {

/// Velodyne VLP-16 elevation angles by laser id, degrees.
inline constexpr std::array<double, 16> kVlp16ElevationDeg = {
    -15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};

/// The paper's mount: a VLP-16 tilted about the base's x axis, on a base spinning about the
/// vehicle's vertical axis, on a mast above the vehicle frame B.
struct SpinningLidarMount {
  double height_m = 1.88;          ///< sensor above the vehicle frame origin
  double tilt_rad = DegToRad(45.0);
  double spin_hz = 0.5;            ///< base rotation rate
  double scan_hz = 20.0;           ///< scans per second (VLP-16 rotation rate)
  double azimuth_step_rad = DegToRad(0.398);  ///< horizontal step at 20 Hz
  double min_range_m = 1.0;
  double max_range_m = 100.0;

  /// Pose of the sensor S in the vehicle frame B at time t.
  Eigen::Isometry3d T_B_S(double time_s) const;
};

/// Vertical cylinder (post, pole, trunk).
struct Cylinder { Vec3 base; double radius_m; double height_m; };
/// Axis-aligned box (wall, rock, roof slab).
struct Box { Vec3 min; Vec3 max; };
/// Sphere (tree crown, bush).
struct Sphere { Vec3 centre; double radius_m; };

/// Ground: z = 0 everywhere, except a planar ramp rising along +x from x = ramp_start_x to
/// ramp_end_x (slope ramp_slope_rad) for |y - ramp_centre_y| <= ramp_half_width, and flat at the
/// ramp's top height beyond it (a plateau).
struct Scene {
  double ramp_start_x = 1e9;
  double ramp_end_x = 1e9;
  double ramp_centre_y = 0.0;
  double ramp_half_width = 0.0;
  double ramp_slope_rad = 0.0;
  std::vector<Cylinder> cylinders;
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;

  double GroundHeight(double x, double y) const;
  /// Distance along the unit ray to the first hit, or +inf when nothing is hit within max_range_m.
  double Raycast(const Vec3& origin, const Vec3& direction, double max_range_m) const;
};

/// The benchmark scene: flat ground, a 20 deg ramp to a plateau, a carport (roof at 2.5 m on four
/// posts), poles and trees placed from the seed.
Scene MakeOutdoorScene(std::uint64_t seed);

/// Simulates `num_scans` consecutive scans of a static vehicle at `T_O_B`, starting at `t0_s`, with
/// Gaussian range noise of `range_sigma_m`. Deterministic from `seed`.
std::vector<Scan> SimulateScans(const Scene& scene, const SpinningLidarMount& mount,
                                const Eigen::Isometry3d& T_O_B, double t0_s, int num_scans,
                                double range_sigma_m, std::uint64_t seed);

/// A buffered outdoor cloud of about `num_points` points (the buffer's subsampling target) in the
/// local frame of the newest sensor pose (viewpoint at the origin). Deterministic from `seed`.
Points MakeOutdoorCloud(std::size_t num_points, std::uint64_t seed);

}  // namespace ovpc::synth
