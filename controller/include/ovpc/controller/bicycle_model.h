// Kinematic bicycle model of an Ackermann vehicle, for tests and quick closed-loop checks.
#pragma once

#include "ovpc/core/vehicle_model.h"
#include "ovpc/controller/command.h"
#include "ovpc/core/types.h"
#include "ovpc/planner/path.h"

namespace ovpc::controller {

/// Rear-axle kinematic bicycle: x' = v cos(yaw), y' = v sin(yaw), yaw' = v tan(steering) / wheelbase.
/// The speed follows the command within an acceleration limit and the steering angle within a rate
/// limit and the steering stop. The model is immutable; the state is a separate value (Step is pure).
class BicycleModel {
 public:
  struct Config {
    double wheelbase_m = VehicleModel{}.wheelbase_m;
    double max_steering_rad = DegToRad(VehicleModel{}.max_steering_deg);
    double max_steering_rate_radps = DegToRad(60.0);
    double max_accel_mps2 = 1.0;                   ///< also the braking limit
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  struct State {
    planner::Pose2 pose;  ///< rear axle centre in the plane
    double speed_mps = 0.0;
    double steering_rad = 0.0;
  };

  /// @throws std::invalid_argument for an invalid config.
  explicit BicycleModel(const Config& config);

  /// The state `dt_s` later under `command`. @pre dt_s > 0.
  State Step(const State& state, const Command& command, double dt_s) const;

  const Config& config() const { return config_; }

 private:
  Config config_;
};

}  // namespace ovpc::controller
