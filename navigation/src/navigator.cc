#include "ovpc/navigation/navigator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include "ovpc/controller/rollout.h"
#include "ovpc/core/internal/clock.h"
#include "ovpc/core/internal/percentile.h"

namespace ovpc::navigation {
namespace {

// A wheel's contact patch along the ground: how far ahead of the front axle the footprint prior lays
// ground when the crest test is on (FootprintBox::ground_max_x_m).
constexpr double kContactPatchM = 0.1;
// Wheels of a pose farther than this ahead of the vehicle's own front wheels, inside the known support,
// still get the crest test (SupportRegion::crest_from_x_m): a rounding allowance, so that the
// vehicle's own pose passes and every pose ahead of it is tested.
constexpr double kOwnWheelsM = 0.02;

// The index of the path's pose nearest `here` (the first of equals).
std::size_t ClosestPose(const planner::Path& path, const Eigen::Vector2d& here) {
  const auto& poses = path.Poses();
  std::size_t closest = 0;
  double best = 1e300;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double d = (Eigen::Vector2d(poses[i].pose.x_m, poses[i].pose.y_m) - here).norm();
    if (d < best) best = d, closest = i;
  }
  return closest;
}

using ovpc::internal::Clock;
using ovpc::internal::MsSince;
using ovpc::internal::ThreadCpuMs;
using planner::Pose2;

// The tick after `due_s` (which is at or before `time_s`): one period on, or, for a caller that fell
// more than a period behind, the first tick after `time_s` (it is not run once per missed tick).
double NextTick(double time_s, double due_s, double period_s) {
  const double next = due_s + period_s;
  if (!(time_s + 1e-9 >= next)) return next;
  const double after = (std::floor((time_s + 1e-9) / period_s) + 1.0) * period_s;
  return time_s + 1e-9 >= after ? after + period_s : after;  // rounding may leave it at time_s
}

// Between a cycle's map frame L and the odometry frame O: the two have the same axes, and L's origin
// is at T_O_L's translation in O. Headings are the same in both.
struct FrameChange {
  Vec3 L_in_O = Vec3::Zero();

  Pose2 ToL(const Pose2& p_O) const { return Pose2{p_O.x_m - L_in_O.x(), p_O.y_m - L_in_O.y(), p_O.yaw_rad}; }
  Pose2 ToO(const Pose2& p_L) const { return Pose2{p_L.x_m + L_in_O.x(), p_L.y_m + L_in_O.y(), p_L.yaw_rad}; }
  planner::Path ToL(const planner::Path& path_O) const {
    return path_O.Shifted(-L_in_O.x(), -L_in_O.y(), -L_in_O.z());
  }
  planner::Path ToO(const planner::Path& path_L) const { return path_L.Shifted(L_in_O.x(), L_in_O.y(), L_in_O.z()); }
};

}  // namespace


StageStats StageTimer::Stats() const {
  StageStats s;
  s.calls = samples_.size();
  if (samples_.empty()) return s;
  std::vector<double> v = samples_;
  std::sort(v.begin(), v.end());
  for (double x : v) s.total_ms += x;
  s.mean_ms = s.total_ms / v.size();
  s.median_ms = ovpc::internal::Percentile(v, 0.5);
  s.p90_ms = ovpc::internal::Percentile(v, 0.9);
  s.p99_ms = ovpc::internal::Percentile(v, 0.99);
  s.max_ms = v.back();
  return s;
}

Pose2 ToPose2(const Eigen::Isometry3d& T) {
  const Vec3 x = T.linear().col(0);
  return Pose2{T.translation().x(), T.translation().y(), planner::NormalizeYaw(std::atan2(x.y(), x.x()))};
}

void Navigator::Timing::Validate() const {
  const auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  if (!(map_rate_hz > 0.0) || !(map_rate_hz <= 100.0)) fail("navigator.timing.map_rate_hz must be in (0, 100]");
  if (!(control_rate_hz > 0.0) || !(control_rate_hz <= 1000.0)) fail("navigator.timing.control_rate_hz must be in (0, 1000]");
  if (!(latency_s >= 0.0) || !(latency_s <= 1.0 / map_rate_hz)) {
    fail("navigator.timing.latency_s must be in [0, the map period]");
  }
}

void Navigator::PathChoice::Validate() const {
  const auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  const auto non_negative = [&](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v)) fail(std::string("navigator.path_choice.") + name + " must be >= 0");
  };
  if (goal_candidates < 1) fail("navigator.path_choice.goal_candidates must be >= 1");
  if (!std::isfinite(known_support_margin_m) || known_support_margin_m > 2.0) {
    fail("navigator.path_choice.known_support_margin_m must be at most 2 (negative disables)");
  }
  if (!std::isfinite(keep_path_within_m)) fail("navigator.path_choice.keep_path_within_m must be finite");
  non_negative(cusp_cost_m, "cusp_cost_m");
  non_negative(blocked_stop_short_m, "blocked_stop_short_m");
  non_negative(min_prefix_m, "min_prefix_m");
  if (!std::isfinite(rollout_margin_m) || rollout_margin_m > 1.0) {
    fail("navigator.path_choice.rollout_margin_m must be at most 1 (negative disables)");
  }
  if (!std::isfinite(edge_look_m) || edge_look_m > 5.0) fail("navigator.path_choice.edge_look_m must be at most 5 (negative disables)");
  if (!(edge_speed_mps > 0.0) || !std::isfinite(edge_speed_mps)) fail("navigator.path_choice.edge_speed_mps must be > 0");
  if (!(direct_heading_turn_deg >= 0.0)) fail("navigator.path_choice.direct_heading_turn_deg must be >= 0 (inf: off)");
  if (!(nearer_goal_fraction >= 0.0) || !(nearer_goal_fraction < 1.0)) {
    fail("navigator.path_choice.nearer_goal_fraction must be in [0, 1) (0: off)");
  }
}

void Navigator::Config::Validate() const {
  timing.Validate();
  vehicle.Validate();
  buffer.Validate();
  preparation.Validate();
  ovpc.Validate();
  planner.Validate();
  Box().Validate();
  local_goal.Validate();
  replan.Validate();
  path_choice.Validate();
  progress.Validate();
  follower.Validate();
}

Navigator::Navigator(const Config& config, std::vector<Eigen::Vector2d> route_O, Plugins plugins,
                     std::uint32_t planner_seed)
    : config_(config), box_(config.Box()), route_O_(std::move(route_O)), buffer_(config_.buffer) {
  config_.Validate();
  if (route_O_.empty()) throw std::invalid_argument("navigator: the route needs at least one waypoint");
  for (const auto& p : route_O_) {
    if (!p.allFinite()) throw std::invalid_argument("navigator: a route waypoint is not finite");
  }
  if (route_O_.size() >= 2) tracker_.emplace(route_O_, config_.progress);
  backend_ = plugins.map ? std::move(plugins.map) : std::make_unique<OvpcMapBackend>(config_.ovpc);
  planner_ = plugins.planner ? std::move(plugins.planner) : std::make_unique<RrtConnectPlanner>(config_.planner, config_.vehicle, planner_seed);
  builtin_follower_ = !plugins.follower;
  follower_ = plugins.follower ? std::move(plugins.follower) : std::make_unique<PurePursuitFollower>(config_.follower, controller::SteeringGeometry::Of(config_.vehicle));
  next_map_s_ = 1.0 / config_.timing.map_rate_hz;
  next_control_s_ = 0.0;
}



controller::Command Navigator::Control(double time_s, const Eigen::Isometry3d& T_O_B, double speed_mps) {
  if (time_s + 1e-9 >= next_control_s_) {
    next_control_s_ = NextTick(time_s, next_control_s_, 1.0 / config_.timing.control_rate_hz);
    const auto t = Clock::now();
    command_ = follower_->has_path() ? follower_->Update(ToPose2(T_O_B), speed_mps) : controller::Command{0.0, 0.0, true};
    if (state_.edge_O && follower_->has_path()) {
      // Creep and look: arrive at the place near an unseen drop no faster than the edge speed.
      const double d = (T_O_B.translation().head<2>() - *state_.edge_O).norm();
      const double v = config_.path_choice.edge_speed_mps;
      const double cap = std::sqrt(v * v + 2.0 * config_.follower.stop_decel_mps2 * d);
      command_.speed_mps = std::clamp(command_.speed_mps, -cap, cap);
    }
    speed_mps_ = speed_mps;
    t_controller_.Add(MsSince(t));
  }
  return command_;
}

void Navigator::AddScan(Scan scan) {
  // While a cycle runs, its buffer is not touched: the scan waits until the cycle takes effect.
  if (job_) {
    incoming_.push_back(std::move(scan));
    return;
  }
  const auto t = Clock::now();
  buffer_.Push(std::move(scan));
  t_buffer_.Add(MsSince(t));
}

// One map-and-plan cycle: what it starts from (copied when it starts, so that the caller may go on
// driving), and what it gives (put into effect by Finish). Only the cycle touches the buffer, the map
// backend and the planner while it runs.
struct Navigator::Job {
  double time_s = 0.0;
  double effect_s = 0.0;           // when it takes effect
  Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  bool following = false;          // the follower had a path it had not finished
  double progress_m = 0.0;
  double speed_mps = 0.0;          // measured, and the steering commanded, at the launch
  double steering_rad = 0.0;
  PlanState state;                 // from the one in effect at the launch; replaces it at the effect
  enum class Follow { kKeep, kFollow, kClear };
  Follow follow = Follow::kKeep;   // what the follower is told when it takes effect
  // Results.
  CycleRecord record;
  std::vector<PlanAttempt> plans;
  std::size_t plan_calls = 0, replans_found = 0;
  std::map<std::string, std::size_t> plan_outcomes;
  bool planned = false;            // a map came out, so planning was timed
  std::vector<MapStageTime> map_stages;
  std::shared_ptr<const planner::PlanningMap> map;
  Eigen::Isometry3d T_O_L = Eigen::Isometry3d::Identity(), T_L_B = Eigen::Isometry3d::Identity();
  bool on_worker = false;          // runs on the worker thread
};

Navigator::~Navigator() {
  if (job_ && job_->on_worker) {
    try {
      worker_->Wait();
    } catch (...) {  // a cycle's error no one will read
    }
  }
}

bool Navigator::CycleRunning() const { return job_ && job_->on_worker && worker_->Busy(); }

bool Navigator::Update(double time_s, const Eigen::Isometry3d& T_O_B) {
  const Eigen::Vector2d here = T_O_B.translation().head<2>();
  if (tracker_) progress_m_ = tracker_->Update(here);
  // The vehicle is at most its straight-line distance short of the goal it drives to. That bound
  // is taken where the tracker falls behind: off the route (a vehicle cutting a sharp corner, as a
  // local goal across it invites, is far from the route, and the nearest route point inside the
  // window stays on the leg it left: the goal was held back at the next corner and the vehicle
  // rocked there until the time ran out, in the corners family), and once it reaches its goal
  // (within replan.goal_too_close_m: at a hairpin's way back it is as near to the way out). On the
  // route and short of its goal the vehicle is where the tracker puts it: on the way out to a
  // hairpin, the bound put it metres ahead of itself, and from there the route's way back passed
  // for a corner cut short (the vehicle took it at once and skipped the hairpin).
  if (const auto& goal = state_.last_goal_O) {
    const double to_goal = (here - Eigen::Vector2d(goal->pose.x_m, goal->pose.y_m)).norm();
    const bool off_route = !tracker_ || (tracker_->PointAt(progress_m_) - here).norm() > config_.progress.on_route_m;
    if (off_route || to_goal <= config_.replan.goal_too_close_m) {
      progress_m_ = std::max(progress_m_, goal->route_progress_m - to_goal);
      if (tracker_) tracker_->Advance(progress_m_);
    }
  }
  bool took_effect = false;
  if (job_ && time_s + 1e-9 >= job_->effect_s) {
    Finish();
    took_effect = true;
  }
  if (!(time_s + 1e-9 >= next_map_s_)) return took_effect;
  next_map_s_ = NextTick(time_s, next_map_s_, 1.0 / config_.timing.map_rate_hz);
  if (job_) {  // a caller that jumped ahead in time: the last cycle first
    Finish();
    took_effect = true;
  }
  Launch(time_s, T_O_B);
  if (config_.timing.latency_s <= 0.0) {
    Finish();
    took_effect = true;
  }
  return took_effect;
}

namespace {

// Where the vehicle will be `dt_s` from now if it keeps driving at `speed_mps` with steering
// `steering_rad`: the bicycle model about the rear axle (B's origin), in B's plane.
Eigen::Isometry3d PredictPose(const Eigen::Isometry3d& T_O_B, double speed_mps, double steering_rad,
                              double wheelbase_m, double dt_s) {
  if (!(dt_s > 0.0) || speed_mps == 0.0) return T_O_B;
  const double s = speed_mps * dt_s;                     // arc length, signed
  const double yaw = s * std::tan(steering_rad) / wheelbase_m;
  // Chord of the arc: exact for a constant curvature (its limit for a straight line).
  const double f = std::abs(yaw) > 1e-9 ? std::sin(yaw) / yaw : 1.0;
  const double g = std::abs(yaw) > 1e-9 ? (1.0 - std::cos(yaw)) / yaw : 0.0;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.translation() = Vec3(s * f, s * g, 0.0);
  motion.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  return T_O_B * motion;
}

}  // namespace

void Navigator::Launch(double time_s, const Eigen::Isometry3d& T_O_B) {
  job_ = std::make_unique<Job>();
  Job& job = *job_;
  job.time_s = time_s;
  job.effect_s = time_s + config_.timing.latency_s;
  // The cycle's results are driven from time_s + latency_s: it plans from where the vehicle will be
  // then, predicted from the pose now, the measured speed and the steering it is driving with.
  job.T_O_B = PredictPose(T_O_B, speed_mps_, command_.steering_rad, config_.vehicle.wheelbase_m, config_.timing.latency_s);
  job.following = follower_->has_path() && !follower_->done();
  job.speed_mps = speed_mps_;
  job.steering_rad = command_.steering_rad;
  job.progress_m = progress_m_;
  job.state = state_;
  if (worker_thread_ && config_.timing.latency_s > 0.0) {
    if (!worker_) worker_ = std::make_unique<TaskThread>();  // kept for the navigator's life: its
    // thread-local scratch memory of the buffer and the map stays allocated
    job.on_worker = true;
    worker_->Start([this, &job] { MapCycle(&job); });
  } else {
    MapCycle(&job);
  }
}

void Navigator::Finish() {
  std::unique_ptr<Job> job = std::move(job_);
  if (job->on_worker) worker_->Wait();  // rethrows what the cycle threw
  t_buffer_.Add(job->record.prepare_ms);
  t_mapper_.Add(job->record.map_ms);
  for (const MapStageTime& stage : job->map_stages) {
    auto it = std::find_if(t_map_stages_.begin(), t_map_stages_.end(), [&](const auto& s) { return s.first == stage.name; });
    if (it == t_map_stages_.end()) it = t_map_stages_.insert(t_map_stages_.end(), {stage.name, StageTimer{}});
    it->second.Add(stage.ms);
  }
  ++stats_.map_updates;
  if (!job->record.map_ok) ++stats_.map_failures;
  if (job->map) {
    map_ = std::move(job->map);
    map_T_O_L_ = job->T_O_L;
    map_T_L_B_ = job->T_L_B;
  }
  if (job->planned) t_planner_.Add(job->record.plan_ms);
  stats_.plans += job->plan_calls;
  stats_.replans_found += job->replans_found;
  for (const auto& [outcome, n] : job->plan_outcomes) stats_.plan_outcomes[outcome] += n;
  for (PlanAttempt& a : job->plans) plan_log_.push_back(std::move(a));
  cycles_.push_back(job->record);
  state_ = std::move(job->state);
  if (job->follow == Job::Follow::kFollow) follower_->Follow(state_.path_O);
  if (job->follow == Job::Follow::kClear) follower_->Clear();
  // The scans that arrived while it ran (no cycle runs now: they go into the buffer).
  std::vector<Scan> incoming = std::move(incoming_);
  incoming_.clear();
  for (Scan& scan : incoming) AddScan(std::move(scan));
}

// What one map cycle knows: the map, its frame and the vehicle in it.
struct Navigator::Cycle {
  double time_s = 0.0;
  const planner::PlanningMap* map = nullptr;
  Eigen::Isometry3d T_L_O = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();
  Pose2 vehicle_L;
  FrameChange frame;  // between L and O
};

namespace {
// The outcome of a path whose rollout fails (RolloutCheck).
const char* RolloutOutcome(planner::PoseCheck check) {
  return check == planner::PoseCheck::kCollision ? "rollout collision" : "rollout ground under footprint";
}
}  // namespace

// The built-in follower driven along `path_L` from the cycle's vehicle pose (where the vehicle
// will be when the path takes effect), at the speed and steering of the launch: does the vehicle
// box, grown by rollout_margin_m, hit a map point on the way (kCollision), or, with `wheels_off_path`,
// put a wheel on ground the planner rejects where it leaves the path (kGroundUnderFootprint)?
// kValid when neither.
planner::PoseCheck Navigator::RolloutCheck(const Job& job, const Cycle& c, const planner::Path& path_L,
                                           bool wheels_off_path) const {
  controller::BicycleModel::Config model;
  model.wheelbase_m = config_.vehicle.wheelbase_m;
  model.max_steering_rad = DegToRad(config_.vehicle.max_steering_deg);
  model.max_steering_rate_radps = config_.vehicle.max_steering_rate_radps;
  model.max_accel_mps2 = config_.vehicle.max_accel_mps2;
  controller::BicycleModel::State start;
  start.pose = c.vehicle_L;
  start.speed_mps = job.speed_mps;
  start.steering_rad = job.steering_rad;
  const double max_time_s = 2.0 * path_L.Length() / config_.follower.creep_speed_mps + 10.0;
  const std::vector<Pose2> poses =
      controller::Rollout(config_.follower, controller::BicycleModel(model), path_L, start,
                          1.0 / config_.timing.control_rate_hz, config_.planner.check_resolution_m, max_time_s);
  planner::VehicleBox box = box_;
  box.margin_m = config_.path_choice.rollout_margin_m;
  // A collision anywhere is reported before a wheel off the path.
  planner::PoseCheck result = planner::PoseCheck::kValid;
  for (const Pose2& pose : poses) {
    const planner::PoseCheck check = planner::CheckPose(*c.map, box, pose);
    if (check == planner::PoseCheck::kCollision) return check;
    // A wheel on ground the planner would not stand on, where the follower leaves the path: the
    // path's own poses were checked, the follower's drift was not. Poses within one check step of
    // the path are the path's own.
    if (wheels_off_path && result == planner::PoseCheck::kValid && check == planner::PoseCheck::kGroundUnderFootprint &&
        planner::DistanceToPolyline(path_L, Eigen::Vector2d(pose.x_m, pose.y_m)) > config_.planner.check_resolution_m) {
      result = check;
    }
  }
  return result;
}

// The buffered cloud in its frame L, with lone outliers dropped and the ground under the vehicle's
// footprint laid in.
PointCloudBuffer::LocalCloud Navigator::PrepareCloud(const Job& job) {
  PointCloudBuffer::LocalCloud cloud = buffer_.Build();
  const MapPreparation::Config& prep = config_.preparation;
  DropIsolatedPoints(prep.isolated_point_radius_m, prep.isolated_point_reach_m, &cloud.points_L);
  const planner::VehicleBox& box = box_;
  if (prep.footprint_prior_margin_m > 0.0 && !cloud.points_L.empty()) {
    FootprintBox footprint;
    footprint.min_x_m = -config_.vehicle.rear_overhang_m;
    footprint.max_x_m = config_.vehicle.length_m - config_.vehicle.rear_overhang_m;
    footprint.half_width_m = config_.vehicle.width_m / 2;
    footprint.body_margin_m = box.margin_m + prep.body_margin_m;
    footprint.ground_band_m = box.ground_clearance_m;
    footprint.top_m = box.height_m + box.margin_m + 0.05;
    // With the crest test, the grid ends at the front wheels' contact patch (FootprintBox::ground_max_x_m).
    if (box.crest_margin_m >= 0.0) footprint.ground_max_x_m = box.wheelbase_m + kContactPatchM;
    AddFootprintPrior(cloud.T_O_L.inverse() * job.T_O_B, footprint, prep, &cloud.points_L);
  }
  return cloud;
}

void Navigator::MapCycle(Job* job) {
  CycleRecord& record = job->record;
  record.time_s = job->time_s;
  auto t = Clock::now();
  double cpu = ThreadCpuMs();
  PointCloudBuffer::LocalCloud cloud = PrepareCloud(*job);
  record.prepare_ms = MsSince(t);
  record.prepare_cpu_ms = ThreadCpuMs() - cpu;
  record.cloud_points = cloud.points_L.size();

  Cycle c;
  c.time_s = job->time_s;
  c.T_L_O = cloud.T_O_L.inverse();
  c.T_L_B = c.T_L_O * job->T_O_B;
  c.vehicle_L = ToPose2(c.T_L_B);
  c.frame.L_in_O = cloud.T_O_L.translation();
  MapContext context;
  context.T_L_B = c.T_L_B;
  context.L_in_O = c.frame.L_in_O;
  context.time_s = c.time_s;
  if (config_.path_choice.known_support_margin_m >= 0.0) {
    const planner::VehicleBox& box = box_;
    const double grow = config_.path_choice.known_support_margin_m;
    context.known_support.pose = c.vehicle_L;
    context.known_support.min_x_m = box.centre_ahead_m - 0.5 * box.length_m - grow;
    context.known_support.max_x_m = box.centre_ahead_m + 0.5 * box.length_m + grow;
    context.known_support.half_width_m = 0.5 * box.width_m + grow;
    context.known_support.crest_from_x_m = box.wheelbase_m + kOwnWheelsM;
  }
  t = Clock::now();
  cpu = ThreadCpuMs();
  std::shared_ptr<const planner::PlanningMap> map = backend_->Update(cloud.points_L, context);
  record.map_ms = MsSince(t);
  record.map_cpu_ms = ThreadCpuMs() - cpu;
  job->map_stages = backend_->StageTimes();
  if (!map) return;
  record.map_ok = true;
  job->map = std::move(map);
  job->T_O_L = cloud.T_O_L;
  job->T_L_B = c.T_L_B;
  c.map = job->map.get();
  job->planned = true;

  t = Clock::now();
  cpu = ThreadCpuMs();
  CheckAndReplan(job, c);
  FindEdgeAhead(job, c);
  record.plan_ms = MsSince(t);
  record.plan_cpu_ms = ThreadCpuMs() - cpu;
}

// The re-plan triggers on the new map, and the re-plan if one fires.
void Navigator::CheckAndReplan(Job* job, const Cycle& c) {
  PlanState& state = job->state;
  const Eigen::Vector2d here_O = job->T_O_B.translation().head<2>();
  std::size_t closest = 0, blocked_index = 0;
  const bool blocked = PathBlocked(*job, c, &closest, &blocked_index);
  planner::ReplanInputs in;
  in.now_s = c.time_s;
  in.last_plan_s = state.last_plan_s;
  in.has_path = job->following;
  in.path_blocked = blocked;
  state.blocked_updates = blocked ? state.blocked_updates + 1 : 0;
  in.blocked_updates = state.blocked_updates;
  if (blocked) {
    const planner::PathPose at = state.path_O.Poses()[blocked_index];
    in.blocked_distance_m = (Eigen::Vector2d(at.pose.x_m, at.pose.y_m) - here_O).norm();
    if (config_.replan.unseen_block_near_m > 0.0) {
      const planner::PoseCheck why = planner::CheckPose(*c.map, box_, c.frame.ToL(at.pose));
      in.blocked_by_unseen_ground = planner::IsGroundCheck(why) || why == planner::PoseCheck::kOutsideMap;
    }
  }
  in.distance_to_goal_m = state.goal_O ? (here_O - *state.goal_O).norm() : 0.0;
  in.goal_is_route_end = state.goal_is_route_end;
  in.goal_is_look = state.goal_is_look;
  const planner::ReplanReason reason = planner::CheckReplan(config_.replan, in);
  if (reason == planner::ReplanReason::kNone) return;
  job->record.trigger = planner::ReplanReasonName(reason);
  // The path's poses are clear, but the follower may no longer keep to them from where the vehicle
  // is now: stopped at a cusp at another heading than the path's, it swings wide of a tight turn
  // that follows. Such a path is not kept, and with no other path the vehicle stands. Nor is a
  // path the follower would leave for ground the planner rejects: at a ditch's rim the vehicle,
  // kept to a path planned seconds before, was 0.3 m outside it after its cusps and a front wheel
  // reached the lip (docs/notes/descents.md). A new path is not held to that: it starts where the
  // vehicle will be, and at a crest, where the map's ground flickers from one update to the next,
  // the same test on new paths kept the vehicle rocking there (a 24 deg descent out of its 90 s,
  // 58 s without it).
  planner::PoseCheck drift = planner::PoseCheck::kValid;
  if (reason == planner::ReplanReason::kPeriodElapsed && !blocked && job->following && builtin_follower_ &&
      config_.path_choice.rollout_margin_m >= 0.0 && closest + 1 < state.path_O.Poses().size()) {
    drift = RolloutCheck(*job, c, c.frame.ToL(state.path_O.Slice(closest, state.path_O.Poses().size() - 1)),
                         /*wheels_off_path=*/true);
  }
  const bool drifts = drift != planner::PoseCheck::kValid;
  const bool found = Replan(job, c, reason, blocked, closest, blocked_index, !drifts);
  // The old path runs into something: drive only its valid part.
  if (!found && blocked) KeepValidPrefix(job, closest, blocked_index);
  if (!found && drifts) {
    ++job->plan_outcomes[std::string("current path ") + RolloutOutcome(drift)];
    job->follow = Job::Follow::kClear;
    state.path_O = planner::Path{};
  }
}

void Navigator::FindEdgeAhead(Job* job, const Cycle& c) const {
  PlanState& state = job->state;
  state.edge_O.reset();
  const double look = config_.path_choice.edge_look_m;
  if (look < 0.0 || box_.crest_margin_m < 0.0 || state.path_O.empty() || job->follow == Job::Follow::kClear) return;
  if (!job->following && job->follow != Job::Follow::kFollow) return;
  constexpr double kAheadM = 4.0;  // far enough to slow from the target speed
  planner::VehicleBox looking = box_;
  looking.crest_margin_m = look;
  const auto& poses = state.path_O.Poses();
  const std::size_t closest = ClosestPose(state.path_O, job->T_O_B.translation().head<2>());
  double arc = 0.0;
  for (std::size_t i = closest; i < poses.size() && arc <= kAheadM; ++i) {
    if (i > closest) {
      arc += (Eigen::Vector2d(poses[i].pose.x_m - poses[i - 1].pose.x_m, poses[i].pose.y_m - poses[i - 1].pose.y_m)).norm();
    }
    if (planner::IsGroundCheck(planner::CheckPose(*c.map, looking, c.frame.ToL(poses[i].pose)))) {
      state.edge_O = Eigen::Vector2d(poses[i].pose.x_m, poses[i].pose.y_m);
      return;
    }
  }
}

bool Navigator::PathBlocked(const Job& job, const Cycle& c, std::size_t* closest_out, std::size_t* blocked_index) const {
  if (!job.following) return false;
  // Poses already driven past do not count: check from the pose closest to the vehicle on.
  const planner::Path& path = job.state.path_O;
  const auto& poses = path.Poses();
  const std::size_t closest = ClosestPose(path, job.T_O_B.translation().head<2>());
  *closest_out = closest;
  const auto invalid = planner_->FirstInvalidPose(*c.map, c.frame.ToL(path), closest);
  if (!invalid) return false;
  // A planner's index past the path's end counts as its last pose.
  *blocked_index = std::min(*invalid, poses.size() - 1);
  return true;
}

bool Navigator::NewPathIsBetter(const PlanState& state, const planner::Path& new_path_L, const planner::LocalGoal& goal,
                                std::size_t closest) const {
  if (config_.path_choice.keep_path_within_m < 0.0 || !state.last_goal_O || state.path_O.empty()) return true;
  const planner::Path rest = state.path_O.Slice(closest, state.path_O.Poses().size() - 1);
  if (rest.empty()) return true;
  // The route left after the goal is the route's length less the goal's progress; the length is
  // the same on both sides.
  const auto cost = [&](const planner::Path& p, double goal_progress_m, bool turns_round) {
    return p.Length() + config_.path_choice.cusp_cost_m * (p.NumCusps() + (turns_round ? 1 : 0)) - goal_progress_m;
  };
  const bool turns_round = new_path_L.segments().front().direction != rest.segments().front().direction;
  return cost(new_path_L, goal.route_progress_m, turns_round) <
         cost(rest, state.last_goal_O->route_progress_m, false) - config_.path_choice.keep_path_within_m;
}

bool Navigator::Replan(Job* job, const Cycle& c, planner::ReplanReason reason, bool blocked, std::size_t closest,
                       std::size_t blocked_index, bool may_keep) {
  PlanState& state = job->state;
  std::optional<planner::LocalGoal> previous_L = state.last_goal_O;
  if (previous_L) previous_L->pose = c.frame.ToL(previous_L->pose);
  const std::vector<planner::LocalGoal> goals =
      planner::SelectLocalGoals(*c.map, box_, route_O_, c.T_L_O, c.vehicle_L, config_.local_goal,
                                previous_L, static_cast<std::size_t>(config_.path_choice.goal_candidates), job->progress_m);
  state.last_plan_s = c.time_s;
  PlanAttempt record = AttemptRecord(*job, c, reason, blocked, blocked_index);
  // The candidates in their order until one gives a path; each attempt is a row of plans.csv.
  bool found = false;
  for (const planner::LocalGoal& goal : goals) {
    const GoalTry result = TryGoal(job, c, record, goal, reason, closest, may_keep);
    found = result == GoalTry::kTaken;
    if (result != GoalTry::kNext) break;
  }
  if (!found && !goals.empty() && !job->following && config_.path_choice.nearer_goal_fraction > 0.0) {
    // Nothing found while standing: part of the way to the best candidate, where the sensor sees the
    // ground densely enough to stand on; from there it sees the rest.
    const double f = config_.path_choice.nearer_goal_fraction;
    const planner::LocalGoal& best = goals.front();
    const double dx = best.pose.x_m - c.vehicle_L.x_m, dy = best.pose.y_m - c.vehicle_L.y_m;
    const double d = std::hypot(dx, dy);
    if (f * d >= config_.local_goal.min_distance_m) {
      const planner::LocalGoal nearer{Pose2{c.vehicle_L.x_m + f * dx, c.vehicle_L.y_m + f * dy, std::atan2(dy, dx)},
                                      best.route_progress_m - (1.0 - f) * d, false};
      found = TryGoal(job, c, record, nearer, reason, closest, may_keep) == GoalTry::kTaken;
    }
  }
  if (goals.empty()) {
    ++job->plan_outcomes["no_local_goal"];
    record.outcome = "no_local_goal";
    job->plans.push_back(record);
    job->record.outcome = record.outcome;
  }
  if (!found) state.last_goal_O.reset();  // no path to it: do not hold on to it
  return found;
}

PlanAttempt Navigator::AttemptRecord(const Job& job, const Cycle& c, planner::ReplanReason reason, bool blocked,
                                     std::size_t blocked_index) const {
  PlanAttempt record;
  record.time_s = c.time_s;
  record.reason = planner::ReplanReasonName(reason);
  record.T_L_B = c.T_L_B;
  record.vehicle_L = c.vehicle_L;
  if (blocked) {
    const Pose2 at_L = c.frame.ToL(job.state.path_O.Poses()[blocked_index].pose);
    record.blocked_at_m = std::hypot(at_L.x_m - c.vehicle_L.x_m, at_L.y_m - c.vehicle_L.y_m);
    record.blocked_by = planner::PoseCheckName(planner::CheckPose(*c.map, box_, at_L));
  }
  return record;
}

// One planner call to `goal`, recorded as an attempt (a copy of `record` with the goal and outcome).
Navigator::GoalTry Navigator::TryGoal(Job* job, const Cycle& c, const PlanAttempt& record,
                                      const planner::LocalGoal& goal, planner::ReplanReason reason,
                                      std::size_t closest, bool may_keep) {
  PlanState& state = job->state;
  CycleRecord* cycle = &job->record;
  ++job->plan_calls;
  // Heading straight at the goal is a goal too: at the route's end only the position matters; just
  // past a hairpin, reaching the goal already turned takes a loop.
  const bool hairpin = !goal.is_look && std::abs(planner::NormalizeYaw(goal.pose.yaw_rad - c.vehicle_L.yaw_rad)) >
                                            config_.path_choice.direct_heading_turn_deg * kPi / 180.0;
  std::vector<double> other_yaws;
  if ((goal.is_route_end && config_.path_choice.route_end_any_heading) || (!goal.is_route_end && hairpin)) {
    const double dx = goal.pose.x_m - c.vehicle_L.x_m, dy = goal.pose.y_m - c.vehicle_L.y_m;
    if (std::hypot(dx, dy) > 0.5) other_yaws.push_back(std::atan2(dy, dx));
  }
  const planner::PlanResult plan = planner_->Plan(*c.map, c.vehicle_L, goal.pose, other_yaws);
  std::string outcome = planner::PlanStatusName(plan.status);
  if (plan.status == planner::PlanStatus::kStartInvalid) outcome += std::string(":") + planner::PoseCheckName(plan.start_check);
  if (plan.status == planner::PlanStatus::kGoalInvalid) outcome += std::string(":") + planner::PoseCheckName(plan.goal_check);
  ++job->plan_outcomes[outcome];
  PlanAttempt attempt = record;
  attempt.has_goal = true;
  attempt.goal_L = goal.pose;
  attempt.goal_progress_m = goal.route_progress_m;
  attempt.goal_is_look = goal.is_look;
  attempt.outcome = outcome;
  attempt.iterations = plan.iterations;
  attempt.state_checks = plan.state_checks;
  job->plans.push_back(attempt);
  cycle->outcome = outcome;
  if (plan.found() && !plan.path.empty() && reason == planner::ReplanReason::kPeriodElapsed && may_keep &&
      !NewPathIsBetter(state, plan.path, goal, closest)) {
    // The current path stands: what is left of it is as good.
    job->plans.back().outcome = cycle->outcome = "kept current";
    ++job->plan_outcomes["kept current"];
    return GoalTry::kTaken;
  }
  if (plan.found() && !plan.path.empty() && config_.path_choice.rollout_margin_m >= 0.0 && builtin_follower_) {
    const planner::PoseCheck rollout = RolloutCheck(*job, c, plan.path, /*wheels_off_path=*/false);
    if (rollout != planner::PoseCheck::kValid) {
      // The planner's poses are clear, but the follower would not keep to them.
      job->plans.back().outcome = cycle->outcome = RolloutOutcome(rollout);
      ++job->plan_outcomes[RolloutOutcome(rollout)];
      return GoalTry::kNext;
    }
  }
  if (plan.found() && !plan.path.empty()) {
    ++job->replans_found;
    state.path_O = c.frame.ToO(plan.path);
    job->follow = Job::Follow::kFollow;
    state.blocked_updates = 0;  // a new path
    state.last_goal_O = goal;
    state.last_goal_O->pose = c.frame.ToO(goal.pose);
    state.goal_O = Eigen::Vector2d(state.last_goal_O->pose.x_m, state.last_goal_O->pose.y_m);
    state.goal_is_route_end = goal.is_route_end;
    state.goal_is_look = goal.is_look;
    return GoalTry::kTaken;
  }
  // A start the planner rejects is rejected for every goal.
  return plan.status == planner::PlanStatus::kStartInvalid ? GoalTry::kStop : GoalTry::kNext;
}

// A blocked path that no new plan replaces is still valid up to the blocked pose: drive on to
// `blocked_stop_short_m` before it, or stand still if that is where the vehicle is.
void Navigator::KeepValidPrefix(Job* job, std::size_t closest, std::size_t blocked_index) const {
  PlanState* state = &job->state;
  const auto& poses = state->path_O.Poses();
  std::size_t last = blocked_index;
  double back = 0.0;
  while (last > closest && back < config_.path_choice.blocked_stop_short_m) {
    back += std::hypot(poses[last].pose.x_m - poses[last - 1].pose.x_m, poses[last].pose.y_m - poses[last - 1].pose.y_m);
    --last;
  }
  planner::Path prefix = back >= config_.path_choice.blocked_stop_short_m ? state->path_O.Slice(closest, last) : planner::Path{};
  if (prefix.empty() || prefix.Length() < config_.path_choice.min_prefix_m) {
    job->follow = Job::Follow::kClear;
    state->path_O = planner::Path{};
    return;
  }
  state->path_O = std::move(prefix);
  job->follow = Job::Follow::kFollow;
}

void Navigator::ClearRecords() {
  plan_log_.clear();
  cycles_.clear();
  t_buffer_ = t_mapper_ = t_planner_ = t_controller_ = StageTimer{};
  t_map_stages_.clear();
}

NavigatorStats Navigator::stats() const {
  NavigatorStats s = stats_;
  s.buffer = t_buffer_.Stats();
  s.mapper = t_mapper_.Stats();
  s.planner = t_planner_.Stats();
  s.controller = t_controller_.Stats();
  for (const auto& [name, timer] : t_map_stages_) s.map_stages.emplace_back(name, timer.Stats());
  return s;
}

}  // namespace ovpc::navigation
