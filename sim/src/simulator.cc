#include "ovpc/sim/simulator.h"

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::sim {
namespace {

const char* const kWarningNames[mjNWARNING] = {
    "near-singular inertia matrix", "contact buffer full (raise PhysicsOptions::nconmax)",
    "constraint buffer full (raise PhysicsOptions::njmax)", "visual geom buffer full",
    "bad number in qpos", "bad number in qvel", "bad number in qacc", "bad number in ctrl"};

/// MuJoCo's default warning handler also appends to MUJOCO_LOG.TXT in the working directory; the
/// simulator reports warnings through Warnings() and stderr instead.
void WarningToStderr(const char* message) { std::fprintf(stderr, "MuJoCo warning: %s\n", message); }

int RequireId(const mjModel* m, int type, const char* name) {
  const int id = mj_name2id(m, type, name);
  if (id < 0) throw std::runtime_error(std::string("Simulator: the model has no '") + name + "'");
  return id;
}

}  // namespace

struct Simulator::MuJoCo {
  ModelPtr model;
  mjData* data = nullptr;
  int chassis_body = -1;
  int chassis_qpos = -1;
  int chassis_dof = -1;
  int spin_qpos = -1;
  int spin_dof = -1;
  int act_steer_left = -1;
  int act_steer_right = -1;
  int act_drive_left = -1;
  int act_drive_right = -1;
  std::vector<char> vehicle_geom;  ///< geom belongs to the vehicle
  std::vector<char> wheel_geom;    ///< geom is a wheel's collision shape
  WheelCommands command;

  ~MuJoCo() {
    if (data != nullptr) mj_deleteData(data);
  }

  bool IsBodyContact(const mjContact& c) const {
    const bool v1 = vehicle_geom[c.geom1] != 0;
    const bool v2 = vehicle_geom[c.geom2] != 0;
    if (v1 == v2) return false;  // world-world or vehicle-vehicle (filtered anyway)
    const int vehicle = v1 ? c.geom1 : c.geom2;
    return wheel_geom[vehicle] == 0;
  }
};

void Simulator::Config::Validate() const {
  world.Validate();
  vehicle.Validate();
  physics.Validate();
  Vlp16Sim::Config sensor = lidar;
  sensor.mount = vehicle.lidar;
  sensor.Validate();
  odometry.Validate();
  ray_caster.Validate();
  if (!std::isfinite(start_x_m) || !std::isfinite(start_y_m) || !std::isfinite(start_yaw_rad)) {
    throw std::invalid_argument("Simulator::Config: start_x_m/start_y_m/start_yaw_rad must be finite");
  }
}

Simulator::Simulator(const Config& config)
    : config_(config),
      terrain_((config.Validate(), MakeHeightfield(config.world.terrain))),
      solids_(ResolveSolids(config.world, terrain_)),
      ray_caster_(std::make_unique<RayCaster>(terrain_, solids_, config.ray_caster)),
      mj_(std::make_unique<MuJoCo>()),
      odometry_(config.odometry) {
  if (mju_user_warning == nullptr) mju_user_warning = WarningToStderr;  // unless the user set one
  const Eigen::Isometry3d T_W_B0 = RestingPose(terrain_, config_.vehicle, config_.start_x_m,
                                               config_.start_y_m, config_.start_yaw_rad);
  mj_->model = BuildWorldModel(terrain_, solids_, config_.vehicle, T_W_B0, config_.physics,
                               &compile_warning_);
  const mjModel* m = mj_->model.get();
  mj_->data = mj_makeData(m);
  if (mj_->data == nullptr) throw std::runtime_error("Simulator: mj_makeData failed");

  namespace n = gator_names;
  mj_->chassis_body = RequireId(m, mjOBJ_BODY, n::kChassis);
  const int free_joint = m->body_jntadr[mj_->chassis_body];
  mj_->chassis_qpos = m->jnt_qposadr[free_joint];
  mj_->chassis_dof = m->jnt_dofadr[free_joint];
  const int spin = RequireId(m, mjOBJ_JOINT, n::kLidarSpin);
  mj_->spin_qpos = m->jnt_qposadr[spin];
  mj_->spin_dof = m->jnt_dofadr[spin];
  mj_->act_steer_left = RequireId(m, mjOBJ_ACTUATOR, n::kSteerLeft);
  mj_->act_steer_right = RequireId(m, mjOBJ_ACTUATOR, n::kSteerRight);
  mj_->act_drive_left = RequireId(m, mjOBJ_ACTUATOR, n::kDriveLeft);
  mj_->act_drive_right = RequireId(m, mjOBJ_ACTUATOR, n::kDriveRight);
  mj_->vehicle_geom.assign(static_cast<std::size_t>(m->ngeom), 0);
  mj_->wheel_geom.assign(static_cast<std::size_t>(m->ngeom), 0);
  const std::string wheel_prefix = n::kWheelGeomPrefix;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->body_rootid[m->geom_bodyid[g]] != mj_->chassis_body) continue;
    mj_->vehicle_geom[static_cast<std::size_t>(g)] = 1;
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (name != nullptr && std::string(name).rfind(wheel_prefix, 0) == 0) {
      mj_->wheel_geom[static_cast<std::size_t>(g)] = 1;
    }
  }

  SetSpinJoint();
  mj_forward(m, mj_->data);
  odometry_.Update(time_s(), T_W_B());
  if (config_.lidar_enabled) {
    Vlp16Sim::Config sensor = config_.lidar;
    sensor.mount = config_.vehicle.lidar;
    lidar_ = std::make_unique<Vlp16Sim>(sensor, ray_caster_.get(), time_s());
  }
}

Simulator::~Simulator() = default;

const mjModel_* Simulator::model() const { return mj_->model.get(); }
const mjData_* Simulator::data() const { return mj_->data; }

double Simulator::time_s() const { return mj_->data->time; }

void Simulator::SetCommand(double steering_rad, double speed_mps) {
  mj_->command = AckermannCommands(config_.vehicle, steering_rad, speed_mps);
}

void Simulator::SetSpinJoint() {
  const SpinningLidarMount& mount = config_.vehicle.lidar;
  mjData* d = mj_->data;
  d->qpos[mj_->spin_qpos] = 2.0 * kPi * std::fmod(mount.spin_hz * d->time, 1.0);
  d->qvel[mj_->spin_dof] = 2.0 * kPi * mount.spin_hz;
}

Eigen::Isometry3d Simulator::ChassisPose() const {
  const mjtNum* q = mj_->data->qpos + mj_->chassis_qpos;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Vec3(q[0], q[1], q[2]);
  T.linear() = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized().toRotationMatrix();
  return T;
}

Eigen::Isometry3d Simulator::T_W_B() const { return ChassisPose(); }

Vec3 Simulator::velocity_W() const {
  const mjtNum* v = mj_->data->qvel + mj_->chassis_dof;
  return Vec3(v[0], v[1], v[2]);
}

double Simulator::forward_speed_mps() const {
  return velocity_W().dot(ChassisPose().linear().col(0));
}

double Simulator::yaw_rate_radps() const {
  // The free joint's angular velocity is in the body frame.
  const mjtNum* v = mj_->data->qvel + mj_->chassis_dof + 3;
  return (ChassisPose().linear() * Vec3(v[0], v[1], v[2])).z();
}

Eigen::Isometry3d Simulator::T_W_S() const {
  return ChassisPose() * config_.vehicle.lidar.T_B_S(time_s());
}

void Simulator::Step() {
  const mjModel* m = mj_->model.get();
  mjData* d = mj_->data;
  d->ctrl[mj_->act_steer_left] = mj_->command.steer_left_rad;
  d->ctrl[mj_->act_steer_right] = mj_->command.steer_right_rad;
  d->ctrl[mj_->act_drive_left] = mj_->command.drive_left_radps;
  d->ctrl[mj_->act_drive_right] = mj_->command.drive_right_radps;
  SetSpinJoint();

  const TimedPose from{d->time, ChassisPose()};
  mj_step(m, d);
  const TimedPose to{d->time, ChassisPose()};

  bool touched = false;
  for (int i = 0; i < d->ncon && !touched; ++i) touched = mj_->IsBodyContact(d->contact[i]);
  if (touched) ++body_contact_steps_;

  odometry_.Update(to.time_s, to.T_W_B);
  if (lidar_ != nullptr) {
    completed_.clear();
    lidar_->Advance(from, to, &completed_);
    for (TrueScan& truth : completed_) {
      SensorScan out;
      out.scan.time_s = truth.time_s;
      out.scan.T_O_S = odometry_.T_O_W() * truth.T_W_S;
      out.scan.points_S = std::move(truth.points_S);
      out.T_W_S = truth.T_W_S;
      out.rays = truth.rays;
      out.dropouts = truth.dropouts;
      out.outliers = truth.outliers;
      pending_scans_.push_back(std::move(out));
    }
  }
}

void Simulator::StepFor(double duration_s) {
  if (!(duration_s >= 0.0) || !std::isfinite(duration_s)) {
    throw std::invalid_argument("Simulator::StepFor: duration_s must be finite and >= 0");
  }
  const long steps = std::lround(std::ceil(duration_s / timestep_s() - 1e-9));
  for (long i = 0; i < steps; ++i) Step();
}

std::vector<Simulator::SensorScan> Simulator::TakeScans() {
  std::vector<SensorScan> out;
  out.swap(pending_scans_);
  return out;
}

std::vector<BodyContact> Simulator::BodyContacts() const {
  const mjModel* m = mj_->model.get();
  const mjData* d = mj_->data;
  std::vector<BodyContact> out;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (!mj_->IsBodyContact(c)) continue;
    const bool first_is_vehicle = mj_->vehicle_geom[c.geom1] != 0;
    const int vehicle = first_is_vehicle ? c.geom1 : c.geom2;
    const int world = first_is_vehicle ? c.geom2 : c.geom1;
    const char* vehicle_name = mj_id2name(m, mjOBJ_GEOM, vehicle);
    const char* world_name = mj_id2name(m, mjOBJ_GEOM, world);
    BodyContact contact;
    contact.vehicle_geom = vehicle_name != nullptr ? vehicle_name : "geom" + std::to_string(vehicle);
    contact.world_geom = world_name != nullptr ? world_name : "geom" + std::to_string(world);
    contact.position_W = Vec3(c.pos[0], c.pos[1], c.pos[2]);
    contact.penetration_m = -c.dist;
    out.push_back(std::move(contact));
  }
  return out;
}

std::vector<std::string> Simulator::Warnings() const {
  std::vector<std::string> out;
  if (!compile_warning_.empty()) out.push_back("compiler: " + compile_warning_);
  const mjData* d = mj_->data;
  for (int i = 0; i < mjNWARNING; ++i) {
    if (d->warning[i].number > 0) {
      out.push_back(std::string(kWarningNames[i]) + " (" + std::to_string(d->warning[i].number) +
                    " times, last info " + std::to_string(d->warning[i].lastinfo) + ")");
    }
  }
  return out;
}

}  // namespace ovpc::sim
