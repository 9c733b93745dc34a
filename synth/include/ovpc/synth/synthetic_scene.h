// Analytic outdoor scenes scanned by a VLP-16 on a tilted spinning base, for tests, benchmarks and
// the bundled sample cloud. The closed-loop simulator casts rays with Embree instead; both take the
// beam pattern and the mount kinematics from ovpc/core/sensor_mount.h.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/core/sensor_mount.h"
#include "ovpc/core/types.h"

namespace ovpc::synth {

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
