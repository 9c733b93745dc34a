// The simulated world in one object: MuJoCo vehicle on the generated terrain, the Embree VLP-16 on
// its spinning base, and the odometry. A closed loop sets a command, steps, and reads scans, the
// odometry pose, the true pose and the body contacts.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/core/types.h"
#include "ovpc/sim/gator.h"
#include "ovpc/sim/odometry.h"
#include "ovpc/sim/ray_caster.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/vlp16.h"
#include "ovpc/sim/world.h"
#include "ovpc/sim/world_model.h"

struct mjModel_;
struct mjData_;

namespace ovpc::sim {

/// A contact between a vehicle geom that is not a wheel and the world.
struct BodyContact {
  std::string vehicle_geom;  ///< "body_deck", "body_mast", "body_rops_roof", ...
  std::string world_geom;    ///< "terrain", "box0", "carport0_roof", ...
  Vec3 position_W = Vec3::Zero();
  double penetration_m = 0.0;
};

class Simulator {
 public:
  struct Config {
    World world;
    GatorParams vehicle;
    PhysicsOptions physics;
    /// Noise, faults and seed of the LiDAR. Its `mount` is ignored: the sensor is the one on the
    /// vehicle's mast, `vehicle.lidar`.
    Vlp16Sim::Config lidar;
    bool lidar_enabled = true;
    OdometrySim::Config odometry;
    RayCaster::Config ray_caster;
    /// Start pose of B: the vehicle is set down on the terrain there, following its slope.
    double start_x_m = 0.0;
    double start_y_m = 0.0;
    double start_yaw_rad = 0.0;

    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// A scan as the mapping pipeline sees it, and the truth behind it.
  struct SensorScan {
    Scan scan;                 ///< points_S, T_O_S (odometry), time_s
    Eigen::Isometry3d T_W_S;   ///< true sensor pose at the scan time
    std::size_t rays = 0;
    std::size_t dropouts = 0;
    std::size_t outliers = 0;
  };

  /// Builds the terrain, the MuJoCo model and the Embree scene.
  /// @throws std::invalid_argument on a bad config, std::runtime_error if MuJoCo or Embree fail.
  explicit Simulator(const Config& config);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// The bicycle-model command held until the next call: steering angle at the front axle's
  /// centre (> 0 turns left; clamped to the vehicle's limit) and speed of B (clamped to top speed).
  void SetCommand(double steering_rad, double speed_mps);

  /// One physics step; the LiDAR fires for the step's interval and the odometry is updated.
  void Step();
  /// Whole steps until at least `duration_s` more has passed.
  void StepFor(double duration_s);

  double time_s() const;
  double timestep_s() const { return config_.physics.timestep_s; }

  /// True pose of B in W.
  Eigen::Isometry3d T_W_B() const;
  /// True velocity of B's origin in W.
  Vec3 velocity_W() const;
  /// True speed of B along its x axis.
  double forward_speed_mps() const;
  /// True yaw rate about W's z axis.
  double yaw_rate_radps() const;
  /// Odometry pose of B in O at the current time.
  const Eigen::Isometry3d& T_O_B() const { return odometry_.T_O_B(); }
  /// Sensor pose at the current time, from the mount's clock and the true pose.
  Eigen::Isometry3d T_W_S() const;

  /// Scans completed since the last call, oldest first.
  std::vector<SensorScan> TakeScans();

  /// Contacts of non-wheel vehicle geoms with the world at the current step.
  std::vector<BodyContact> BodyContacts() const;
  /// Steps so far during which some non-wheel vehicle geom touched the world.
  std::size_t body_contact_steps() const { return body_contact_steps_; }

  /// MuJoCo warnings so far (compiler warnings and runtime warning counters), empty when clean.
  std::vector<std::string> Warnings() const;

  const Config& config() const { return config_; }
  const Heightfield& terrain() const { return terrain_; }
  const std::vector<Solid>& solids() const { return solids_; }
  const RayCaster& ray_caster() const { return *ray_caster_; }
  /// How the LiDAR's scans are cast (Vlp16Sim::SetParallelFor); the scans are the same either way.
  void SetRayCastParallelFor(Vlp16Sim::ParallelFor parallel_for) {
    if (lidar_ != nullptr) lidar_->SetParallelFor(std::move(parallel_for));
  }
  const OdometrySim& odometry() const { return odometry_; }
  const mjModel_* model() const;
  const mjData_* data() const;

 private:
  struct MuJoCo;
  void SetSpinJoint();
  Eigen::Isometry3d ChassisPose() const;

  Config config_;
  Heightfield terrain_;
  std::vector<Solid> solids_;
  std::unique_ptr<RayCaster> ray_caster_;
  std::unique_ptr<MuJoCo> mj_;
  std::unique_ptr<Vlp16Sim> lidar_;
  OdometrySim odometry_;
  std::vector<SensorScan> pending_scans_;
  std::vector<TrueScan> completed_;
  std::size_t body_contact_steps_ = 0;
  std::string compile_warning_;
};

}  // namespace ovpc::sim
