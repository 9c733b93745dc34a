// The simulated vehicle: a John Deere Gator-like utility vehicle with Ackermann front steering,
// rear-wheel drive, suspension and a mast carrying the VLP-16 on its spinning base. The MuJoCo
// description is generated from these parameters, so the planner and controller can read the same
// figures (wheelbase, steering limit) the physics uses. models/gator.xml is this generator's output
// for the defaults, on a plane (a test keeps it in sync).
//
// Vehicle frame B: origin on the ground under the middle of the rear axle (at rest on flat ground),
// x forward, y left, z up. The mast stands on the rear axle, so the sensor pose in B is the core's
// SpinningLidarMount::T_B_S(t).
#pragma once

#include <string>

#include "ovpc/core/sensor_mount.h"
#include "ovpc/core/types.h"
#include "ovpc/core/vehicle_model.h"

namespace ovpc::sim {

struct GatorParams {
  // Published figure (docs/REFERENCE.md): top speed 24 km/h.
  double max_speed_mps = 24.0 / 3.6;

  // The body's geometry: the vehicle model's (ovpc/core/vehicle_model.h), stated there once.
  double length_m = VehicleModel{}.length_m;
  double width_m = VehicleModel{}.width_m;
  double wheelbase_m = VehicleModel{}.wheelbase_m;
  double track_m = VehicleModel{}.track_m;
  double max_steer_deg = VehicleModel{}.max_steering_deg;  ///< bicycle-model angle at the front axle's centre
  double rear_overhang_m = VehicleModel{}.rear_overhang_m;  ///< body behind the rear axle

  // Assumptions (no published figure found); change them here.
  double wheel_radius_m = 0.3;
  double wheel_width_m = 0.25;
  double mass_kg = 600.0;             ///< curb mass, wheels included
  double wheel_mass_kg = 20.0;
  double ground_clearance_m = 0.25;   ///< underside of the frame
  double body_top_m = 1.0;            ///< cargo bed and hood height
  double rops_height_m = 1.95;        ///< top of the roll-over frame over the seats
  double rops_rear_x_m = 0.75;        ///< the frame spans x in [rear, front]
  double rops_front_x_m = 1.75;
  double cg_x_m = 0.8;                ///< centre of mass ahead of the rear axle (58 % on the rear)
  double cg_z_m = 0.6;                ///< centre of mass above the ground
  double friction = 1.0;              ///< tyre friction (issue 3: >= 0.6 to climb with rear drive)

  // Suspension: a vertical slide per wheel; at rest on flat ground every slide is at 0.
  double suspension_travel_m = 0.08;  ///< either way
  double suspension_stiffness_n_per_m = 30000.0;
  double suspension_damping_ns_per_m = 3000.0;

  // Actuators: velocity-controlled rear wheels, position-controlled steering knuckles.
  double drive_gain_nms = 4000.0;     ///< torque per rad/s of wheel speed error
  double drive_max_torque_nm = 1000.0;
  double steer_gain_nm_per_rad = 2000.0;

  /// The LiDAR on the mast: 1.88 m above B, tilted 45 deg, base spinning at 0.5 Hz.
  SpinningLidarMount lidar;

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;

  /// Path radius of B (rear axle centre) at full lock: wheelbase / tan(max steer).
  double NominalTurnRadius_m() const;
};

/// What the four actuated joints are asked to do for one bicycle-model command.
struct WheelCommands {
  double steer_left_rad = 0.0;   ///< knuckle angles; the inner wheel turns more (Ackermann)
  double steer_right_rad = 0.0;
  double drive_left_radps = 0.0;  ///< rear wheel speeds; the outer wheel turns faster
  double drive_right_radps = 0.0;
};

/// Ackermann geometry: both front wheels turn about the common centre on the rear axle line at
/// radius wheelbase / tan(steering) from B, and each rear wheel rolls at its own radius.
/// `steering_rad` > 0 turns left; it is clamped to +-max_steer, the speed to +-max_speed.
WheelCommands AckermannCommands(const GatorParams& params, double steering_rad, double speed_mps);

/// Names used in the generated model (bodies, joints, actuators, geoms).
namespace gator_names {
inline constexpr const char* kChassis = "chassis";
inline constexpr const char* kLidarBase = "lidar_base";
inline constexpr const char* kLidarSpin = "lidar_spin";
inline constexpr const char* kLidarSite = "lidar";
inline constexpr const char* kSteerLeft = "steer_front_left";
inline constexpr const char* kSteerRight = "steer_front_right";
inline constexpr const char* kDriveLeft = "drive_rear_left";
inline constexpr const char* kDriveRight = "drive_rear_right";
/// Wheel collision geoms all start with this prefix; every other vehicle geom is "body".
inline constexpr const char* kWheelGeomPrefix = "wheel_";
}  // namespace gator_names

/// MJCF pieces. Vehicle geoms collide with the world, never with each other: vehicle geoms have
/// contype 2, conaffinity 1; world geoms contype 1, conaffinity 2.
std::string GatorDefaultsXml(const GatorParams& params);
/// The chassis body (free joint) at `T_W_B` with wheels, mast and LiDAR base.
std::string GatorBodyXml(const GatorParams& params, const Eigen::Isometry3d& T_W_B);
std::string GatorActuatorsXml(const GatorParams& params);

/// A complete model: the vehicle resting on a plane (what models/gator.xml holds).
std::string GatorStandaloneXml(const GatorParams& params);

}  // namespace ovpc::sim
