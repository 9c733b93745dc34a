// The vehicle's geometry, stated once. The simulated vehicle (sim::GatorParams) takes its body from
// these defaults; the robot's stack (navigation::Navigator) derives the planner's vehicle box, the
// footprint prior and the follower's steering geometry from its own copy.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "ovpc/core/config_fields.h"

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
  /// The steering servo's and the drive's limits the robot's rollout of its follower assumes. The
  /// simulated Gator's are faster (its wheels swing 0.4 rad within a control period or two); these
  /// only keep the model physical and on the cautious side.
  double max_steering_rate_radps = 4.0;
  double max_accel_mps2 = 1.0;      ///< also the braking limit

  template <class C, class V>
  static void VisitFields(C& c, V& v) {
    v.Field(OVPC_FIELD(c, length_m), "m", "the Gator TE (docs/REFERENCE.md)");
    v.Field(OVPC_FIELD(c, width_m), "m", "the Gator TE");
    v.Field(OVPC_FIELD(c, height_m), "m", "ground to the top of the sensor on its mast");
    v.Field(OVPC_FIELD(c, rear_overhang_m), "m", "body behind the rear axle");
    v.Field(OVPC_FIELD(c, wheelbase_m), "m", "the Gator TE");
    v.Field(OVPC_FIELD(c, track_m), "m", "wheel centre to wheel centre across");
    v.Field(OVPC_FIELD(c, max_steering_deg), "deg", "bicycle-model angle at the front axle's centre");
    v.Field(OVPC_FIELD(c, turning_radius_m), "m", "the planner's Reeds-Shepp radius: half the 7.3 m turning circle");
    v.Field(OVPC_FIELD(c, max_steering_rate_radps), "rad/s", "the rollout's steering servo (the simulated Gator's is faster)");
    v.Field(OVPC_FIELD(c, max_accel_mps2), "m/s^2", "the rollout's drive, braking too (cautious)");
  }

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const {
    // Bounds far beyond any ground vehicle, so that no size makes a grid over the footprint huge.
    const auto in_range = [](double v, double max, const char* name, const char* range) {
      if (!(v > 0.0) || !(v <= max)) throw std::invalid_argument(std::string("vehicle.") + name + " must be in " + range);
    };
    in_range(length_m, 20.0, "length_m", "(0, 20] m");
    in_range(width_m, 10.0, "width_m", "(0, 10] m");
    in_range(height_m, 10.0, "height_m", "(0, 10] m");
    in_range(wheelbase_m, 20.0, "wheelbase_m", "(0, 20] m");
    in_range(track_m, 10.0, "track_m", "(0, 10] m");
    in_range(turning_radius_m, 100.0, "turning_radius_m", "(0, 100] m");
    in_range(max_steering_rate_radps, 100.0, "max_steering_rate_radps", "(0, 100] rad/s");
    in_range(max_accel_mps2, 100.0, "max_accel_mps2", "(0, 100] m/s^2");
    if (!(rear_overhang_m >= 0.0) || !(rear_overhang_m < length_m)) {
      throw std::invalid_argument("vehicle.rear_overhang_m must be in [0, length_m)");
    }
    if (!(max_steering_deg > 0.0) || !(max_steering_deg < 90.0)) {
      throw std::invalid_argument("vehicle.max_steering_deg must be in (0, 90)");
    }
  }
};

}  // namespace ovpc
