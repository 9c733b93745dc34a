#include "ovpc/scenarios/closed_loop.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "ovpc/io/cloud_io.h"
#include "ovpc/sim/image.h"
#include "ovpc/sim/renderer.h"

namespace ovpc::scenarios {
namespace {

using Clock = std::chrono::steady_clock;
using planner::Pose2;

// Wall-clock samples of a stage, for the report only (nothing in the loop depends on them).
class StageTimer {
 public:
  void Add(double ms) { samples_.push_back(ms); }
  StageStats Stats() const {
    StageStats s;
    s.calls = samples_.size();
    if (samples_.empty()) return s;
    std::vector<double> v = samples_;
    std::sort(v.begin(), v.end());
    for (double x : v) s.total_ms += x;
    s.mean_ms = s.total_ms / v.size();
    s.median_ms = v[v.size() / 2];
    s.p90_ms = v[std::min(v.size() - 1, v.size() * 9 / 10)];
    s.max_ms = v.back();
    return s;
  }

 private:
  std::vector<double> samples_;
};

double MsSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

Pose2 ToPose2(const Eigen::Isometry3d& T) {
  const Vec3 x = T.linear().col(0);
  return Pose2{T.translation().x(), T.translation().y(), planner::NormalizeYaw(std::atan2(x.y(), x.x()))};
}

void RollPitchDeg(const Eigen::Isometry3d& T, double* roll_deg, double* pitch_deg) {
  const Eigen::Matrix3d& R = T.linear();
  *pitch_deg = RadToDeg(std::asin(std::clamp(-R(2, 0), -1.0, 1.0)));
  *roll_deg = RadToDeg(std::atan2(R(2, 1), R(2, 2)));
}

// A path in another frame with the same axes (the mapper's frame L and the odometry frame O differ
// by a translation).
planner::Path Shifted(const planner::Path& path, const Vec3& offset) {
  planner::Path out = path;
  for (auto& seg : out.segments) {
    for (auto& p : seg.poses) {
      p.pose.x_m += offset.x();
      p.pose.y_m += offset.y();
      p.z_m += offset.z();
    }
  }
  return out;
}

double RouteLength(const std::vector<Eigen::Vector2d>& route) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < route.size(); ++i) s += (route[i + 1] - route[i]).norm();
  return s;
}

// Does the vehicle footprint at the true pose touch the region? Checked on a grid of footprint points.
bool FootprintInRegion(const Eigen::Isometry3d& T_W_B, const sim::GatorParams& v, const Region& r) {
  const double x0 = -v.rear_overhang_m, x1 = v.length_m - v.rear_overhang_m;
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 2; ++j) {
      const Vec3 p_B(x0 + (x1 - x0) * i / 4.0, -v.width_m / 2 + v.width_m * j / 2.0, 0.0);
      const Vec3 p = T_W_B * p_B;
      if (p.x() >= r.min_m.x() && p.x() <= r.max_m.x() && p.y() >= r.min_m.y() && p.y() <= r.max_m.y()) return true;
    }
  }
  return false;
}

// The space the vehicle occupies is free, and the ground it stands on is ground, but the sensor sees
// neither. Measured points inside the vehicle's box (the body grown by the planner's margin, up to
// its top) are dropped: returns off the vehicle itself on a real robot, outliers in simulation. A
// 0.25 m grid on the footprint plane (z = 0 in B), over the footprint grown by `margin_m`, stands for
// the ground. Low points (below `ground_band_m` in B), measured ground: with kReplace they are dropped
// over the grown footprint plus a band and the grid is laid everywhere (mixing measured ground with
// the grid would put noisy points a few centimetres from exact ones and make steep slivers of faces);
// with kFill they stay, and a grid point is laid only where no low point lies within the grid's
// spacing, so that a measured ramp ahead of the bumper is not cut off by the flat grid. With kFill
// and `blend_m` > 0, a grid point with measured ground within `blend_m` takes that ground's height
// (inverse-distance mean), weighted down linearly with the distance to the nearest measured point:
// at a crest under the pitched vehicle the grid then meets the measured slope instead of standing
// off it by up to a few decimetres. Anything taller just outside the body (a post the vehicle passes
// close by) stays in the map.
void AddFootprintPrior(const Eigen::Isometry3d& T_L_B, const sim::GatorParams& v, double margin_m, double body_margin_m,
                       double ground_band_m, double top_m, LoopConfig::PriorMode mode, double blend_m,
                       Points* points_L) {
  const double x0 = -v.rear_overhang_m, x1 = v.length_m - v.rear_overhang_m;
  const double y0 = -v.width_m / 2, y1 = v.width_m / 2;
  const bool fill = mode == LoopConfig::PriorMode::kFill;
  // A clearance band keeps measured ground off the grid's edge.
  constexpr double kBand = 0.12;
  constexpr double kStep = 0.25;
  const double reach = std::max(kStep, blend_m);
  const double g = margin_m + kBand;
  const Eigen::Isometry3d T_B_L = T_L_B.inverse();
  std::vector<Vec3> low_B;  // kFill: measured ground near the grid, in B
  points_L->erase(std::remove_if(points_L->begin(), points_L->end(),
                                 [&](const Vec3& p_L) {
                                   const Vec3 p = T_B_L * p_L;
                                   if (p.z() >= top_m) return false;
                                   const bool low = p.z() < ground_band_m;
                                   if (low && fill) {
                                     if (p.x() >= x0 - margin_m - reach && p.x() <= x1 + margin_m + reach &&
                                         p.y() >= y0 - margin_m - reach && p.y() <= y1 + margin_m + reach) {
                                       low_B.push_back(p);
                                     }
                                     return false;
                                   }
                                   const double m = low ? g : body_margin_m;
                                   return p.x() >= x0 - m && p.x() <= x1 + m && p.y() >= y0 - m && p.y() <= y1 + m;
                                 }),
                  points_L->end());
  for (double x = x0 - margin_m; x <= x1 + margin_m + 1e-9; x += kStep) {
    for (double y = y0 - margin_m; y <= y1 + margin_m + 1e-9; y += kStep) {
      // Nearest measured ground and, when blending, the inverse-distance mean height of that within
      // `reach`.
      double nearest_sq = std::numeric_limits<double>::infinity(), weight_sum = 0.0, z_sum = 0.0;
      for (const Vec3& p : low_B) {
        const double d_sq = (p.x() - x) * (p.x() - x) + (p.y() - y) * (p.y() - y);
        nearest_sq = std::min(nearest_sq, d_sq);
        if (blend_m > 0.0 && d_sq < reach * reach) {
          const double w = 1.0 / (std::sqrt(d_sq) + 0.05);
          weight_sum += w;
          z_sum += w * p.z();
        }
      }
      if (fill && nearest_sq < kStep * kStep) continue;  // measured ground right here
      double z = 0.0;
      if (fill && blend_m > 0.0 && weight_sum > 0.0) z = (1.0 - std::sqrt(nearest_sq) / reach) * z_sum / weight_sum;
      points_L->push_back(T_L_B * Vec3(x, y, z));
    }
  }
}

std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

void DropIsolatedPoints(double radius_m, double reach_m, Points* points_L) {
  if (!(radius_m > 0.0) || points_L->empty()) return;
  const double inv = 1.0 / radius_m;
  const auto key = [inv](const Vec3& p) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x() * inv)),
                                       static_cast<std::int64_t>(std::floor(p.y() * inv)),
                                       static_cast<std::int64_t>(std::floor(p.z() * inv))};
  };
  struct KeyHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
      return static_cast<std::size_t>((static_cast<std::uint64_t>(k[0]) * 0x9e3779b97f4a7c15ULL) ^
                                      (static_cast<std::uint64_t>(k[1]) * 0xc2b2ae3d27d4eb4fULL) ^
                                      (static_cast<std::uint64_t>(k[2]) * 0x165667b19e3779f9ULL));
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::size_t>, KeyHash> cells;
  cells.reserve(points_L->size());
  for (std::size_t i = 0; i < points_L->size(); ++i) cells[key((*points_L)[i])].push_back(i);
  const double r2 = radius_m * radius_m, reach2 = reach_m * reach_m;
  std::vector<char> drop(points_L->size(), 0);
  for (std::size_t i = 0; i < points_L->size(); ++i) {
    const Vec3& p = (*points_L)[i];
    if (p.squaredNorm() > reach2) continue;
    const auto k = key(p);
    bool neighbour = false;
    for (int dx = -1; dx <= 1 && !neighbour; ++dx) {
      for (int dy = -1; dy <= 1 && !neighbour; ++dy) {
        for (int dz = -1; dz <= 1 && !neighbour; ++dz) {
          const auto it = cells.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == cells.end()) continue;
          for (std::size_t j : it->second) {
            if (j != i && ((*points_L)[j] - p).squaredNorm() <= r2) {
              neighbour = true;
              break;
            }
          }
        }
      }
    }
    drop[i] = neighbour ? 0 : 1;
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < points_L->size(); ++i) {
    if (!drop[i]) (*points_L)[out++] = (*points_L)[i];
  }
  points_L->resize(out);
}

RunResult RunClosedLoop(const Scenario& scenario, std::uint64_t seed, const RunOptions& options) {
  scenario.Validate();
  const auto wall_start = Clock::now();
  RunResult result;
  result.scenario = scenario.name;
  result.seed = seed;
  result.route_length_m = RouteLength(scenario.route_m);

  // One seed feeds every random source.
  sim::Simulator::Config sim_config = scenario.sim;
  sim_config.lidar.seed = seed * 1000003ULL + 1;
  sim_config.odometry.seed = seed * 1000003ULL + 2;
  sim::Simulator sim(sim_config);
  planner::LocalPlanner::Config planner_config = scenario.planner;
  planner_config.seed = static_cast<std::uint32_t>(seed);
  const planner::LocalPlanner local_planner(planner_config);
  PointCloudBuffer buffer(scenario.buffer);
  const OvpcMapper mapper(scenario.mapper);
  const std::vector<Eigen::Vector2d>& route_O = scenario.route_m;  // O = W when the run starts

  std::unique_ptr<sim::Renderer> renderer;
  if (options.frames) renderer = std::make_unique<sim::Renderer>(sim);
  if (!options.out_dir.empty()) std::filesystem::create_directories(options.out_dir);

  StageTimer t_physics, t_buffer, t_mapper, t_planner, t_controller;
  std::optional<controller::PurePursuit> follower;
  planner::Path path_O;
  std::optional<Eigen::Vector2d> goal_O;
  std::optional<planner::LocalGoal> last_goal_O;
  // Route progress of the true pose (scoring) and of the odometry pose (the robot's local goal).
  constexpr double kProgressBackM = 5.0, kProgressAheadM = 10.0;
  double truth_progress_m = 0.0, odom_progress_m = 0.0;  // the last goal a path was found to, frame O
  bool goal_is_route_end = false;
  std::optional<double> last_plan_s;
  int blocked_updates = 0;  // map updates in a row that found the current path blocked
  controller::Command command;
  std::optional<TraversabilityCloud> last_map_cloud;  // for frames
  Eigen::Isometry3d last_T_W_L = Eigen::Isometry3d::Identity();

  const double dt_map = 1.0 / scenario.loop.map_rate_hz;
  const double dt_control = 1.0 / scenario.loop.control_rate_hz;
  const double dt_record = 1.0 / scenario.loop.record_rate_hz;
  double next_map = dt_map, next_control = 0.0, next_record = 0.0, next_snapshot = scenario.loop.mesh_snapshot_period_s;
  double next_frame = 0.0, next_progress = 5.0;
  double max_roll = 0.0, max_pitch = 0.0;
  std::optional<double> goal_time_s;
  std::vector<bool> region_entered(scenario.criteria.forbidden.size(), false);
  Vec3 last_position = sim.T_W_B().translation();
  const sim::GatorParams& vehicle = sim_config.vehicle;
  const double step_s = sim.timestep_s();
  int snapshot_index = 0;

  result.end_reason = "time limit";
  while (sim.time_s() + 0.5 * step_s < scenario.time_limit_s) {
    const double now = sim.time_s();

    // Control at its rate, from the odometry pose only.
    if (now + 1e-9 >= next_control) {
      next_control += dt_control;
      const auto t = Clock::now();
      if (follower) {
        command = follower->Update(ToPose2(sim.T_O_B()), sim.forward_speed_mps());
      } else {
        command = controller::Command{0.0, 0.0, true};
      }
      sim.SetCommand(command.steering_rad, command.speed_mps);
      t_controller.Add(MsSince(t));
    }

    auto t = Clock::now();
    sim.Step();
    std::vector<sim::Simulator::SensorScan> scans = sim.TakeScans();
    t_physics.Add(MsSince(t));
    t = Clock::now();
    for (auto& s : scans) buffer.Push(std::move(s.scan));
    const double time = sim.time_s();

    // Truth for the criteria.
    const Eigen::Isometry3d T_W_B = sim.T_W_B();
    result.distance_m += (T_W_B.translation() - last_position).norm();
    last_position = T_W_B.translation();
    double roll, pitch;
    RollPitchDeg(T_W_B, &roll, &pitch);
    max_roll = std::max(max_roll, std::abs(roll));
    max_pitch = std::max(max_pitch, std::abs(pitch));
    const Eigen::Vector2d xy = T_W_B.translation().head<2>();
    // Progress is tracked in a window that moves with the vehicle, so that a route passing near
    // itself (laps side by side) is not scored as done when the vehicle cuts across.
    truth_progress_m = planner::RouteProgress(scenario.route_m, xy, truth_progress_m, kProgressBackM, kProgressAheadM);
    result.route_progress_m = std::max(result.route_progress_m, truth_progress_m);
    odom_progress_m = planner::RouteProgress(route_O, sim.T_O_B().translation().head<2>(), odom_progress_m,
                                             kProgressBackM, kProgressAheadM);
    const std::vector<sim::BodyContact> contacts = sim.BodyContacts();
    if (!contacts.empty()) {
      ++result.collision_steps;
      if (result.collisions.size() < 5) {
        result.collisions.push_back("t=" + Fixed(time, 2) + " s: " + contacts.front().vehicle_geom + " touched " +
                                    contacts.front().world_geom);
      }
    }
    for (std::size_t i = 0; i < region_entered.size(); ++i) {
      if (!region_entered[i] && FootprintInRegion(T_W_B, vehicle, scenario.criteria.forbidden[i])) region_entered[i] = true;
    }
    if (now + 1e-9 >= next_record) {
      next_record += dt_record;
      result.trajectory.push_back({time, T_W_B, sim.T_O_B(), sim.forward_speed_mps(), command.steering_rad, command.speed_mps});
    }
    t_buffer.Add(MsSince(t));

    // Map update, re-planning triggers and planning, at the map rate.
    if (time + 1e-9 >= next_map) {
      next_map += dt_map;
      t = Clock::now();
      PointCloudBuffer::LocalCloud cloud = buffer.Build();
      DropIsolatedPoints(scenario.loop.isolated_point_radius_m, scenario.loop.isolated_point_reach_m, &cloud.points_L);
      if (scenario.loop.footprint_prior_margin_m > 0.0 && !cloud.points_L.empty()) {
        const planner::VehicleBox& box = planner_config.vehicle;
        AddFootprintPrior(cloud.T_O_L.inverse() * sim.T_O_B(), vehicle, scenario.loop.footprint_prior_margin_m,
                          box.margin_m + 0.02, box.ground_clearance_m, box.height_m + box.margin_m + 0.05,
                          scenario.loop.footprint_prior_mode, scenario.loop.footprint_prior_blend_m, &cloud.points_L);
      }
      t_buffer.Add(MsSince(t));
      t = Clock::now();
      const OvpcMap map = mapper.Update(cloud.points_L, Vec3::Zero());
      t_mapper.Add(MsSince(t));
      ++result.map_updates;
      if (!map.ok()) {
        ++result.map_failures;
      } else {
        t = Clock::now();
        const Eigen::Isometry3d T_L_O = cloud.T_O_L.inverse();
        const Eigen::Isometry3d T_L_B = T_L_O * sim.T_O_B();
        const Pose2 vehicle_L = ToPose2(T_L_B);
        planner::VertexCloudMap::Config map_config = scenario.map;
        map_config.ground_reference_z_m = T_L_B.translation().z();
        if (scenario.loop.known_support_margin_m >= 0.0) {
          const planner::VehicleBox& box = planner_config.vehicle;
          const double grow = scenario.loop.known_support_margin_m;
          map_config.known_support.pose = vehicle_L;
          map_config.known_support.min_x_m = box.centre_ahead_m - 0.5 * box.length_m - grow;
          map_config.known_support.max_x_m = box.centre_ahead_m + 0.5 * box.length_m + grow;
          map_config.known_support.half_width_m = 0.5 * box.width_m + grow;
        }
        const planner::VertexCloudMap vmap(map.cloud, map_config);
        const Vec3 L_to_O = cloud.T_O_L.translation();

        bool blocked = false;
        std::size_t path_closest = 0, blocked_index = 0;
        if (follower && !follower->done()) {
          // Poses already driven past do not count: check from the pose closest to the vehicle on.
          const auto poses = path_O.Poses();
          std::size_t closest = 0;
          double best = 1e300;
          const Eigen::Vector2d v(sim.T_O_B().translation().head<2>());
          for (std::size_t i = 0; i < poses.size(); ++i) {
            const double d = (Eigen::Vector2d(poses[i].pose.x_m, poses[i].pose.y_m) - v).norm();
            if (d < best) best = d, closest = i;
          }
          path_closest = closest;
          const auto invalid = local_planner.FirstInvalidPose(vmap, Shifted(path_O, -L_to_O), closest);
          blocked = invalid.has_value();
          if (invalid) blocked_index = *invalid;
        }
        // A blocked path that no new plan replaces is still valid up to the blocked pose: drive on to
        // `kStopShortM` before it, or stand still if that is where the vehicle is.
        const auto keep_valid_prefix = [&]() {
          constexpr double kStopShortM = 0.5;
          const auto poses = path_O.Poses();
          std::size_t last = blocked_index;
          double back = 0.0;
          while (last > path_closest && back < kStopShortM) {
            back += std::hypot(poses[last].pose.x_m - poses[last - 1].pose.x_m, poses[last].pose.y_m - poses[last - 1].pose.y_m);
            --last;
          }
          planner::Path prefix = back >= kStopShortM ? path_O.Slice(path_closest, last) : planner::Path{};
          if (prefix.empty() || prefix.Length() < 0.3) {
            follower.reset();
            return;
          }
          path_O = std::move(prefix);
          follower.emplace(scenario.controller, path_O);
        };
        planner::ReplanInputs in;
        in.now_s = time;
        in.last_plan_s = last_plan_s;
        in.has_path = follower.has_value() && !follower->done();
        in.path_blocked = blocked;
        blocked_updates = blocked ? blocked_updates + 1 : 0;
        in.blocked_updates = blocked_updates;
        if (blocked) {
          const planner::PathPose at = path_O.Poses()[blocked_index];
          in.blocked_distance_m = (Eigen::Vector2d(at.pose.x_m, at.pose.y_m) - sim.T_O_B().translation().head<2>()).norm();
        }
        in.distance_to_goal_m = goal_O ? (sim.T_O_B().translation().head<2>() - *goal_O).norm() : 0.0;
        in.goal_is_route_end = goal_is_route_end;
        const planner::ReplanReason reason = planner::CheckReplan(scenario.replan, in);
        if (reason != planner::ReplanReason::kNone) {
          std::optional<planner::LocalGoal> previous_L;
          if (last_goal_O) {
            previous_L = *last_goal_O;
            const Vec3 p_L = T_L_O * Vec3(last_goal_O->pose.x_m, last_goal_O->pose.y_m, 0.0);
            previous_L->pose.x_m = p_L.x();
            previous_L->pose.y_m = p_L.y();
          }
          const std::vector<planner::LocalGoal> goals = planner::SelectLocalGoals(
              vmap, planner_config.vehicle, route_O, T_L_O, vehicle_L, scenario.local_goal, previous_L,
              static_cast<std::size_t>(scenario.loop.goal_candidates), odom_progress_m);
          last_plan_s = time;
          const Eigen::Isometry3d T_W_L = T_W_B * T_L_B.inverse();
          const auto to_world = [&T_W_L](const Pose2& p) {
            const Vec3 p_W = T_W_L * Vec3(p.x_m, p.y_m, 0.0);
            const Vec3 x_axis = T_W_L.linear() * Vec3(std::cos(p.yaw_rad), std::sin(p.yaw_rad), 0.0);
            return Eigen::Vector3d(p_W.x(), p_W.y(), std::atan2(x_axis.y(), x_axis.x()));
          };
          PlanRecord record;
          record.time_s = time;
          record.reason = planner::ReplanReasonName(reason);
          record.vehicle_W = to_world(vehicle_L);
          if (blocked) {
            const planner::PathPose at = path_O.Poses()[blocked_index];
            const Pose2 at_L{at.pose.x_m - L_to_O.x(), at.pose.y_m - L_to_O.y(), at.pose.yaw_rad};
            record.blocked_at_m = std::hypot(at_L.x_m - vehicle_L.x_m, at_L.y_m - vehicle_L.y_m);
            record.blocked_by = planner::PoseCheckName(planner::CheckPose(vmap, planner_config.vehicle, at_L));
          }
          // The candidates in their order until one gives a path; each attempt is a row of plans.csv.
          bool found = false;
          for (const planner::LocalGoal& goal : goals) {
            ++result.plans;
            // At the route's end only the position matters: heading straight there is a goal too.
            std::vector<double> other_yaws;
            if (goal.is_route_end && scenario.loop.route_end_any_heading) {
              const double dx = goal.pose.x_m - vehicle_L.x_m, dy = goal.pose.y_m - vehicle_L.y_m;
              if (std::hypot(dx, dy) > 0.5) other_yaws.push_back(std::atan2(dy, dx));
            }
            const planner::PlanResult plan = local_planner.Plan(vmap, vehicle_L, goal.pose, other_yaws);
            std::string outcome = planner::PlanStatusName(plan.status);
            if (plan.status == planner::PlanStatus::kStartInvalid) outcome += std::string(":") + planner::PoseCheckName(plan.start_check);
            if (plan.status == planner::PlanStatus::kGoalInvalid) outcome += std::string(":") + planner::PoseCheckName(plan.goal_check);
            ++result.plan_outcomes[outcome];
            PlanRecord attempt = record;
            attempt.has_goal = true;
            attempt.goal_W = to_world(goal.pose);
            attempt.goal_progress_m = goal.route_progress_m;
            attempt.outcome = outcome;
            attempt.iterations = plan.iterations;
            attempt.state_checks = plan.state_checks;
            result.plan_log.push_back(attempt);
            if (plan.found()) {
              ++result.replans_found;
              path_O = Shifted(plan.path, L_to_O);
              follower.emplace(scenario.controller, path_O);
              blocked_updates = 0;  // a new path
              goal_O = Eigen::Vector2d(goal.pose.x_m + L_to_O.x(), goal.pose.y_m + L_to_O.y());
              goal_is_route_end = goal.is_route_end;
              last_goal_O = goal;
              last_goal_O->pose.x_m = goal_O->x();
              last_goal_O->pose.y_m = goal_O->y();
              found = true;
              break;
            }
            // A start the planner rejects is rejected for every goal.
            if (plan.status == planner::PlanStatus::kStartInvalid) break;
          }
          if (goals.empty()) {
            ++result.plan_outcomes["no_local_goal"];
            record.outcome = "no_local_goal";
            result.plan_log.push_back(record);
          }
          if (!found) {
            last_goal_O.reset();  // no path to it: do not hold on to it
            if (blocked) keep_valid_prefix();  // the old path runs into something: drive only its valid part
          }
        }
        t_planner.Add(MsSince(t));

        // What the robot mapped, in the world frame (by the truth at this time) for pictures.
        const Eigen::Isometry3d T_W_L = T_W_B * (T_L_B.inverse());
        last_T_W_L = T_W_L;
        const auto& pts = map.cloud.points();
        for (std::size_t i = 0; i < pts.size(); i += 7) result.map_points.push_back({T_W_L * pts[i], map.cloud.traversable()[i] != 0});
        if (renderer) last_map_cloud = map.cloud;
        if (!options.out_dir.empty() && scenario.loop.mesh_snapshot_period_s > 0 && time + 1e-9 >= next_snapshot) {
          next_snapshot += scenario.loop.mesh_snapshot_period_s;
          FreeSpaceMesh mesh_W = map.mesh;
          for (Vec3& v : mesh_W.vertices) v = T_W_L * v;
          std::ostringstream name;
          name << "mesh_" << std::setw(3) << std::setfill('0') << snapshot_index++ << "_t" << Fixed(time, 1) << ".ply";
          const std::string file = (std::filesystem::path(options.out_dir) / name.str()).string();
          std::vector<Vec3> normals_W = map.cloud.normals();
          for (Vec3& n : normals_W) n = T_W_L.linear() * n;
          WriteMeshPly(file, mesh_W, normals_W);
          result.files.push_back(file);
        }
      }
    }

    if (renderer && time + 1e-9 >= next_frame) {
      next_frame += options.frame_period_s;
      sim::Overlay overlay;
      if (last_map_cloud) {
        for (std::size_t i = 0; i < last_map_cloud->size(); i += 2) {
          const bool trav = last_map_cloud->traversable()[i] != 0;
          overlay.points.push_back({last_T_W_L * last_map_cloud->points()[i],
                                    trav ? sim::Rgba{0.1f, 0.8f, 0.1f, 1.0f} : sim::Rgba{0.9f, 0.1f, 0.1f, 1.0f}});
        }
      }
      if (follower) {
        sim::Overlay::Polyline line;
        const Eigen::Isometry3d T_W_O = T_W_B * sim.T_O_B().inverse();
        for (const auto& p : path_O.Poses()) line.vertices_W.push_back(T_W_O * Vec3(p.pose.x_m, p.pose.y_m, p.z_m + 0.1));
        overlay.polylines.push_back(line);
      }
      const sim::Image image = renderer->Render(sim::ChaseCamera{}, overlay);
      std::ostringstream name;
      name << "frame_" << std::setw(5) << std::setfill('0') << static_cast<int>(std::lround(time * 100)) << ".png";
      const std::string file = (std::filesystem::path(options.out_dir) / name.str()).string();
      sim::WritePng(image, file);
      result.files.push_back(file);
    }

    if (options.progress && time >= next_progress) {
      next_progress += 5.0;
      std::fprintf(stderr, "\r%s: t=%5.1f / %.0f s, progress %5.1f / %.1f m, re-plans %zu   ", scenario.name.c_str(), time,
                   scenario.time_limit_s, result.route_progress_m, result.route_length_m, result.replans_found);
      std::fflush(stderr);
    }

    // The run ends when the goal region is reached (by the true pose).
    if (scenario.criteria.goal_m && (xy - *scenario.criteria.goal_m).norm() <= scenario.criteria.goal_radius_m) {
      goal_time_s = time;
      result.end_reason = "goal reached";
      break;
    }
    if (!scenario.criteria.goal_m && follower && follower->done() && goal_is_route_end) {
      goal_time_s = time;
      result.end_reason = "route end reached";
      break;
    }
  }
  if (options.progress) std::fprintf(stderr, "\n");

  result.sim_time_s = sim.time_s();
  result.wall_time_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  result.real_time_factor = result.wall_time_s > 0 ? result.sim_time_s / result.wall_time_s : 0.0;
  result.physics_lidar = t_physics.Stats();
  result.buffer = t_buffer.Stats();
  result.mapper = t_mapper.Stats();
  result.planner = t_planner.Stats();
  result.controller = t_controller.Stats();

  // Scoring.
  const Criteria& c = scenario.criteria;
  auto add = [&](std::string name, std::string expected, std::string actual, bool passed) {
    result.criteria.push_back({std::move(name), std::move(expected), std::move(actual), passed});
  };
  if (c.goal_m) {
    const double d = (Eigen::Vector2d(last_position.head<2>()) - *c.goal_m).norm();
    add("goal_reached", "within " + Fixed(c.goal_radius_m, 1) + " m of (" + Fixed(c.goal_m->x(), 1) + ", " + Fixed(c.goal_m->y(), 1) + ")",
        goal_time_s ? "at t=" + Fixed(*goal_time_s, 1) + " s" : "no, " + Fixed(d, 1) + " m away", goal_time_s.has_value());
  }
  if (c.no_collision) {
    add("no_collision", "0 body contacts", result.collision_steps == 0 ? "none" : result.collisions.front(),
        result.collision_steps == 0);
  }
  if (c.max_roll_deg) add("max_roll", "<= " + Fixed(*c.max_roll_deg, 1) + " deg", Fixed(max_roll, 1) + " deg", max_roll <= *c.max_roll_deg);
  if (c.max_pitch_deg) add("max_pitch", "<= " + Fixed(*c.max_pitch_deg, 1) + " deg", Fixed(max_pitch, 1) + " deg", max_pitch <= *c.max_pitch_deg);
  if (c.max_time_s) {
    add("completion_time", "<= " + Fixed(*c.max_time_s, 0) + " s", goal_time_s ? Fixed(*goal_time_s, 1) + " s" : "not completed",
        goal_time_s && *goal_time_s <= *c.max_time_s);
  }
  if (c.min_progress_m) {
    add("min_progress", ">= " + Fixed(*c.min_progress_m, 1) + " m", Fixed(result.route_progress_m, 1) + " m",
        result.route_progress_m >= *c.min_progress_m);
  }
  for (std::size_t i = 0; i < c.forbidden.size(); ++i) {
    add("never_enter:" + c.forbidden[i].name, "never entered", region_entered[i] ? "entered" : "never entered", !region_entered[i]);
  }
  result.passed = std::all_of(result.criteria.begin(), result.criteria.end(), [](const CriterionResult& r) { return r.passed; });
  return result;
}

}  // namespace ovpc::scenarios
