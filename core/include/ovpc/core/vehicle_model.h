// The vehicle's geometry, stated once. The simulated vehicle (sim::GatorParams) takes its body from
// these defaults; the robot's stack (navigation::Navigator) derives the planner's vehicle box, the
// footprint prior and the follower's steering geometry from its own copy.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "ovpc/core/types.h"

namespace ovpc {

/// Vehicle frame B: origin on the ground under the middle of the rear axle, x forward, y left, z up.
/// Defaults: the paper's John Deere Gator TE (docs/REFERENCE.md; length, width, mast height,
/// wheelbase, track, steering limit and the rear axle position are assumptions).
struct VehicleModel {
  double length_m = 2.8;            ///< bumper to bumper
  double width_m = 1.5;
  double height_m = 2.2;            ///< ground to the top of the sensor on its mast
  double rear_overhang_m = 0.45;    ///< body behind the rear axle
  double wheelbase_m = 1.9;
  double track_m = 1.2;             ///< wheel centre to wheel centre across
  double max_steering_deg = 30.0;   ///< bicycle-model angle at the front axle's centre
  /// Turning radius of the rear axle centre the planner plans with: about half the published 7.3 m
  /// turning circle (wider than full lock allows, wheelbase / tan(max steering) = 3.3 m).
  double turning_radius_m = 3.7;

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const {
    const auto positive = [](double v, const char* name) {
      if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("vehicle.") + name + " must be > 0");
    };
    positive(length_m, "length_m");
    positive(width_m, "width_m");
    positive(height_m, "height_m");
    positive(wheelbase_m, "wheelbase_m");
    positive(track_m, "track_m");
    positive(turning_radius_m, "turning_radius_m");
    if (!(rear_overhang_m >= 0.0) || !(rear_overhang_m < length_m)) {
      throw std::invalid_argument("vehicle.rear_overhang_m must be in [0, length_m)");
    }
    if (!(max_steering_deg > 0.0) || !(max_steering_deg < 90.0)) {
      throw std::invalid_argument("vehicle.max_steering_deg must be in (0, 90)");
    }
  }
};

}  // namespace ovpc
