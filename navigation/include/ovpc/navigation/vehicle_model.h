// The robot's own geometry, stated once: the planner's vehicle box, the footprint prior and the
// follower's steering geometry are derived from it.
#pragma once

#include "ovpc/core/types.h"

namespace ovpc::navigation {

/// Vehicle frame B: origin on the ground under the middle of the rear axle, x forward, y left, z up.
/// Defaults: the paper's John Deere Gator TE (docs/REFERENCE.md; length, width, mast height and the
/// rear axle position are assumptions).
struct VehicleModel {
  double length_m = 2.8;            ///< bumper to bumper
  double width_m = 1.5;
  double height_m = 2.2;            ///< ground to the top of the sensor mast
  double rear_overhang_m = 0.45;    ///< body behind the rear axle
  double wheelbase_m = 1.9;
  double track_m = 1.2;             ///< wheel centre to wheel centre across
  double max_steering_rad = DegToRad(30.0);  ///< bicycle-model angle at the front axle's centre
  /// Turning radius of the rear axle centre the planner plans with: half the 7.3 m turning circle.
  double turning_radius_m = 3.7;
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

}  // namespace ovpc::navigation
