// Pure-pursuit path follower for an Ackermann vehicle (Coulter 1992; Giesbrecht et al. 2005).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "ovpc/core/vehicle_model.h"
#include "ovpc/controller/command.h"
#include "ovpc/core/types.h"
#include "ovpc/planner/path.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::controller {

/// Follows one planned path, segment by segment: forward segments with the look-ahead point ahead,
/// reverse segments with the look-ahead point behind and a negative speed. It stops at every cusp
/// before changing direction and at the end of the path.
///
/// Per update: the look-ahead distance is L_d = gain * |v| + L_min (clamped to L_max); the look-ahead
/// point lies L_d further along the path than the vehicle's projection on it (past the segment's end
/// along the end heading); with that point at lateral offset y and distance d in the vehicle frame,
/// curvature = 2 y / d^2 = 2 sin(alpha) / d and steering = atan(wheelbase * curvature), clamped to the
/// steering limit. Speed: the target speed, lowered in tight curves (lateral acceleration limit) and
/// towards stops (deceleration limit), never below a creeping speed until the stop is reached.
///
/// Standing still with a measured steering angle far from the command, it waits (speed 0) for the
/// wheels to turn before setting off: a Reeds-Shepp path switches between full left and full right
/// at its cusps.
///
/// Create one follower per path (a new plan gets a new follower); Update is called once per control
/// step with the measured rear-axle pose and speed.
/// The vehicle's steering geometry the follower turns curvature into steering with: taken from the
/// VehicleModel, not a setting.
struct SteeringGeometry {
  double wheelbase_m = VehicleModel{}.wheelbase_m;
  double max_steering_rad = DegToRad(VehicleModel{}.max_steering_deg);
  static SteeringGeometry Of(const VehicleModel& vehicle) {
    return {vehicle.wheelbase_m, DegToRad(vehicle.max_steering_deg)};
  }
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

class PurePursuit {
 public:
  /// The largest speed a Config may set (108 km/h).
  static constexpr double kMaxSpeedMps = 30.0;

  struct Config {
    double target_speed_mps = 1.0;             ///< paper
    double reverse_speed_mps = 0.5;            ///< backwards more carefully (assumption)
    double creep_speed_mps = 0.1;              ///< least speed while a stop is not reached
    double lookahead_gain_s = 0.5;
    double lookahead_min_m = 1.0;
    double lookahead_max_m = 4.0;
    double max_lateral_accel_mps2 = 0.2;       ///< v <= sqrt(a / |curvature|)
    double stop_decel_mps2 = 0.5;              ///< v <= sqrt(2 a d) at distance d before a stop
    double stop_tolerance_m = 0.1;             ///< a cusp or the end counts as reached this close
    double standstill_mps = 0.05;              ///< below this speed the vehicle counts as stopped
    /// Standing (at the start or at a cusp), the vehicle waits until the measured steering angle is
    /// this close to the command, so that it does not set off on the wrong curve.
    double presteer_tolerance_rad = DegToRad(3.0);
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, target_speed_mps), "m/s", "paper");
      v.Field(OVPC_FIELD(c, reverse_speed_mps), "m/s", "backwards more carefully (assumption)");
      v.Field(OVPC_FIELD(c, creep_speed_mps), "m/s", "least speed while a stop is not reached");
      v.Field(OVPC_FIELD(c, lookahead_gain_s), "s", "look-ahead distance per m/s");
      v.Field(OVPC_FIELD(c, lookahead_min_m), "m", "");
      v.Field(OVPC_FIELD(c, lookahead_max_m), "m", "");
      v.Field(OVPC_FIELD(c, max_lateral_accel_mps2), "m/s^2", "v <= sqrt(a / |curvature|)");
      v.Field(OVPC_FIELD(c, stop_decel_mps2), "m/s^2", "v <= sqrt(2 a d) before a stop");
      v.Field(OVPC_FIELD(c, stop_tolerance_m), "m", "a cusp or the end counts as reached this close");
      v.Field(OVPC_FIELD(c, standstill_mps), "m/s", "slower counts as stopped");
      v.Field(OVPC_FIELD(c, presteer_tolerance_rad), "rad", "standing, steer to this close before setting off");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument for an invalid config or geometry.
  PurePursuit(const Config& config, planner::Path path, const SteeringGeometry& steering = {});

  /// The command for the vehicle's rear axle at `pose` moving at `speed_mps` (signed), with the
  /// measured steering angle if the vehicle reports one (used only to steer before setting off).
  Command Update(const planner::Pose2& pose, double speed_mps,
                 std::optional<double> steering_rad = std::nullopt);

  bool done() const { return done_; }
  std::size_t segment_index() const { return segment_; }
  const planner::Path& path() const { return path_; }
  const Config& config() const { return config_; }
  const SteeringGeometry& steering() const { return steering_; }

 private:
  // Arc length of the vehicle's projection onto the current segment, searched forward from the last
  // projection so that the follower never jumps back on a path that comes close to itself.
  double Project(const Eigen::Vector2d& position);
  Eigen::Vector2d PointAt(double s) const;

  Config config_;
  SteeringGeometry steering_;
  planner::Path path_;
  std::size_t segment_ = 0;
  std::vector<double> arc_m_;   // cumulative arc length of the current segment's poses
  std::size_t progress_ = 0;    // index of the polyline piece the vehicle was last projected on
  double last_steering_rad_ = 0.0;  // last steering command, held while stopping
  bool done_ = false;
};

}  // namespace ovpc::controller
