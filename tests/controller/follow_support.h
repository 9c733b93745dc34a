// Paths and a closed loop of PurePursuit and BicycleModel for the controller tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "ovpc/controller/bicycle_model.h"
#include "ovpc/controller/pure_pursuit.h"

namespace ovpc::controller::testing {

using planner::Direction;
using planner::Path;
using planner::PathPose;
using planner::PathSegment;
using planner::Pose2;

/// A segment along the curve p(s), s in [0, length], sampled every `step_m`. The heading is the
/// curve's tangent when driving forward and its opposite when reversing.
inline PathSegment Segment(Direction direction, double length_m, const std::function<Eigen::Vector2d(double)>& p,
                           double step_m = 0.1) {
  PathSegment segment{direction, {}};
  const int n = std::max(1, static_cast<int>(std::ceil(length_m / step_m)));
  for (int i = 0; i <= n; ++i) {
    const double s = length_m * i / n;
    const double ds = 1e-4;
    const Eigen::Vector2d tangent = (p(std::min(length_m, s + ds)) - p(std::max(0.0, s - ds))).normalized();
    double yaw = std::atan2(tangent.y(), tangent.x());
    if (direction == Direction::kReverse) yaw += kPi;
    segment.poses.push_back(PathPose{Pose2{p(s).x(), p(s).y(), planner::NormalizeYaw(yaw)}, 0.0});
  }
  return segment;
}

inline PathSegment Straight(Direction direction, Eigen::Vector2d from, Eigen::Vector2d to) {
  const Eigen::Vector2d d = to - from;
  return Segment(direction, d.norm(), [=](double s) { return Eigen::Vector2d(from + s / d.norm() * d); });
}

/// Counter-clockwise arc of radius r around `centre` from angle a0 over `sweep` radians.
inline PathSegment Arc(Direction direction, Eigen::Vector2d centre, double r, double a0, double sweep) {
  return Segment(direction, r * std::abs(sweep), [=](double s) {
    const double a = a0 + std::copysign(s / r, sweep);
    return Eigen::Vector2d(centre + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  });
}

/// Distance from `p` to the polyline through the poses.
inline double DistanceToPolyline(const std::vector<PathPose>& poses, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    const Eigen::Vector2d a(poses[i].pose.x_m, poses[i].pose.y_m);
    const Eigen::Vector2d b(poses[i + 1].pose.x_m, poses[i + 1].pose.y_m);
    const Eigen::Vector2d ab = b - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

/// The vehicle standing at (x, y) with heading yaw, wheels straight.
inline BicycleModel::State At(double x, double y, double yaw) {
  BicycleModel::State s;
  s.pose = Pose2{x, y, yaw};
  return s;
}

struct Step {
  double t_s;
  BicycleModel::State state;
  Command command;
};

/// Runs the follower on the model at `dt_s` until the path is done and the vehicle stands, or
/// `max_time_s` passes.
inline std::vector<Step> Follow(const Path& path, const BicycleModel::State& start, double max_time_s,
                                const PurePursuit::Config& config = PurePursuit::Config{}, double dt_s = 0.02) {
  PurePursuit follower(config, path);
  const BicycleModel model(BicycleModel::Config{});
  std::vector<Step> log;
  BicycleModel::State state = start;
  for (double t = 0.0; t < max_time_s; t += dt_s) {
    const Command command = follower.Update(state.pose, state.speed_mps, state.steering_rad);
    log.push_back({t, state, command});
    if (command.done && std::abs(state.speed_mps) < 1e-3) break;
    state = model.Step(state, command, dt_s);
  }
  return log;
}

inline Eigen::Vector2d Position(const BicycleModel::State& s) { return {s.pose.x_m, s.pose.y_m}; }

}  // namespace ovpc::controller::testing
