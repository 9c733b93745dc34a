// The sensor the pipeline is built around: a VLP-16 tilted on a spinning base (the paper's mount).
// The analytic scenes (synth/) and the simulated LiDAR (sim/) share these facts
// (see docs/REFERENCE.md).
#pragma once

#include <array>

#include "ovpc/core/types.h"

namespace ovpc {

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

}  // namespace ovpc
