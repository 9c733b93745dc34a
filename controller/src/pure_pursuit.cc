#include "ovpc/controller/pure_pursuit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::controller {
namespace {

Eigen::Vector2d Position(const planner::PathPose& p) { return {p.pose.x_m, p.pose.y_m}; }

// A value in a message: 1e+308, not its 309 digits.
std::string Shown(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void PurePursuit::Config::Validate() const {
  const auto positive = [](double value, const char* field) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("PurePursuit::Config: ") + field + " must be > 0, got " + Shown(value));
    }
  };
  // Speeds far beyond any ground vehicle's are a typo (1e308), not a setting.
  const auto speed = [](double value, const char* field) {
    if (!(value > 0.0) || !(value <= kMaxSpeedMps)) {
      throw std::invalid_argument(std::string("PurePursuit::Config: ") + field + " must be in (0, " + Shown(kMaxSpeedMps) +
                                  "] m/s, got " + Shown(value));
    }
  };
  speed(target_speed_mps, "target_speed_mps");
  speed(reverse_speed_mps, "reverse_speed_mps");
  speed(creep_speed_mps, "creep_speed_mps");
  positive(lookahead_min_m, "lookahead_min_m");
  positive(max_lateral_accel_mps2, "max_lateral_accel_mps2");
  positive(stop_decel_mps2, "stop_decel_mps2");
  positive(stop_tolerance_m, "stop_tolerance_m");
  speed(standstill_mps, "standstill_mps");
  positive(presteer_tolerance_rad, "presteer_tolerance_rad");
  if (!(lookahead_gain_s >= 0.0) || !std::isfinite(lookahead_gain_s)) {
    throw std::invalid_argument("PurePursuit::Config: lookahead_gain_s must be >= 0");
  }
  if (!(lookahead_max_m >= lookahead_min_m) || !std::isfinite(lookahead_max_m)) {
    throw std::invalid_argument("PurePursuit::Config: lookahead_max_m must be >= lookahead_min_m");
  }
}

void SteeringGeometry::Validate() const {
  if (!(wheelbase_m > 0.0) || !std::isfinite(wheelbase_m)) {
    throw std::invalid_argument("SteeringGeometry: wheelbase_m must be > 0, got " + Shown(wheelbase_m));
  }
  if (!(max_steering_rad > 0.0 && max_steering_rad < kPi / 2)) {
    throw std::invalid_argument("SteeringGeometry: max_steering_rad must be in (0, pi/2)");
  }
}

PurePursuit::PurePursuit(const Config& config, planner::Path path, const SteeringGeometry& steering)
    : config_(config), steering_(steering), path_(std::move(path)) {
  config_.Validate();
  steering_.Validate();
  // Drop degenerate segments; a path without a segment of two poses is already done.
  std::vector<planner::PathSegment> kept;
  for (const planner::PathSegment& s : path_.segments()) {
    if (s.poses.size() >= 2 && s.Length() > 1e-6) kept.push_back(s);
  }
  path_ = planner::Path(std::move(kept));
  done_ = path_.empty();
  segment_ = 0;
  if (!done_) {
    const auto& poses = path_.segments().front().poses;
    arc_m_.assign(poses.size(), 0.0);
    for (std::size_t i = 1; i < poses.size(); ++i) {
      arc_m_[i] = arc_m_[i - 1] + (Position(poses[i]) - Position(poses[i - 1])).norm();
    }
  }
}

double PurePursuit::Project(const Eigen::Vector2d& position) {
  const auto& poses = path_.segments()[segment_].poses;
  const double window_end = arc_m_[progress_] + config_.lookahead_max_m + 2.0;
  double best_distance = std::numeric_limits<double>::infinity();
  double best_s = arc_m_[progress_];
  std::size_t best_piece = progress_;
  for (std::size_t k = progress_; k + 1 < poses.size() && arc_m_[k] <= window_end; ++k) {
    const Eigen::Vector2d a = Position(poses[k]);
    const Eigen::Vector2d ab = Position(poses[k + 1]) - a;
    const double length2 = ab.squaredNorm();
    const double t = length2 > 0.0 ? std::clamp((position - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
    const double distance = (a + t * ab - position).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best_s = arc_m_[k] + t * (arc_m_[k + 1] - arc_m_[k]);
      best_piece = k;
    }
  }
  progress_ = best_piece;
  return best_s;
}

Eigen::Vector2d PurePursuit::PointAt(double s) const {
  const auto& poses = path_.segments()[segment_].poses;
  const std::size_t n = poses.size();
  if (s >= arc_m_.back()) {
    // Past the end: continue along the direction of travel of the last piece, so that the vehicle
    // aims straight at the stop.
    const Eigen::Vector2d end = Position(poses[n - 1]);
    std::size_t k = n - 2;  // the last pose apart from the end (the segment is longer than zero)
    while (k > 0 && (end - Position(poses[k])).norm() < 1e-9) --k;
    const Eigen::Vector2d travel = (end - Position(poses[k])).normalized();
    return end + (s - arc_m_.back()) * travel;
  }
  const auto it = std::upper_bound(arc_m_.begin(), arc_m_.end(), s);
  const std::size_t k = it == arc_m_.begin() ? 0 : static_cast<std::size_t>(it - arc_m_.begin()) - 1;
  const double piece = arc_m_[k + 1] - arc_m_[k];
  const double t = piece > 0.0 ? (s - arc_m_[k]) / piece : 0.0;
  return Position(poses[k]) + t * (Position(poses[k + 1]) - Position(poses[k]));
}

Command PurePursuit::Update(const planner::Pose2& pose, double speed_mps, std::optional<double> steering_rad) {
  Command command;
  if (done_) {
    command.done = true;
    return command;
  }
  const Eigen::Vector2d position(pose.x_m, pose.y_m);
  double s = 0.0;
  for (;;) {
    // A vehicle past the end projects onto the end itself, so the remaining arc length covers both.
    s = Project(position);
    if (arc_m_.back() - s > config_.stop_tolerance_m) break;
    // At a cusp or the end: stand still first (steering held), then take the next segment.
    if (std::abs(speed_mps) > config_.standstill_mps) {
      command.steering_rad = last_steering_rad_;
      return command;
    }
    if (segment_ + 1 >= path_.segments().size()) {
      done_ = true;
      command.done = true;
      return command;
    }
    ++segment_;
    progress_ = 0;
    const auto& next = path_.segments()[segment_].poses;
    arc_m_.assign(next.size(), 0.0);
    for (std::size_t i = 1; i < next.size(); ++i) {
      arc_m_[i] = arc_m_[i - 1] + (Position(next[i]) - Position(next[i - 1])).norm();
    }
  }

  const bool forward = path_.segments()[segment_].direction == planner::Direction::kForward;
  const double lookahead = std::clamp(config_.lookahead_gain_s * std::abs(speed_mps) + config_.lookahead_min_m,
                                      config_.lookahead_min_m, config_.lookahead_max_m);
  const Eigen::Vector2d offset_L = PointAt(s + lookahead) - position;
  const double c = std::cos(pose.yaw_rad), sn = std::sin(pose.yaw_rad);
  const double x_B = c * offset_L.x() + sn * offset_L.y();
  const double y_B = -sn * offset_L.x() + c * offset_L.y();
  const double d2 = x_B * x_B + y_B * y_B;
  // The circle through the rear axle, tangent to the heading, through the look-ahead point: the same
  // formula whether the point lies ahead (forward) or behind (reverse).
  const double curvature = d2 > 1e-12 ? 2.0 * y_B / d2 : 0.0;
  command.steering_rad =
      std::clamp(std::atan(steering_.wheelbase_m * curvature), -steering_.max_steering_rad, steering_.max_steering_rad);
  last_steering_rad_ = command.steering_rad;

  double speed = forward ? config_.target_speed_mps : config_.reverse_speed_mps;
  if (std::abs(curvature) > 1e-9) speed = std::min(speed, std::sqrt(config_.max_lateral_accel_mps2 / std::abs(curvature)));
  const double to_stop = std::max(0.0, arc_m_.back() - s);
  speed = std::min(speed, std::sqrt(2.0 * config_.stop_decel_mps2 * to_stop));
  speed = std::max(speed, std::min(config_.creep_speed_mps, forward ? config_.target_speed_mps : config_.reverse_speed_mps));
  command.speed_mps = forward ? speed : -speed;
  if (steering_rad && std::abs(speed_mps) <= config_.standstill_mps &&
      std::abs(*steering_rad - command.steering_rad) > config_.presteer_tolerance_rad) {
    command.speed_mps = 0.0;  // steer first
  }
  return command;
}

}  // namespace ovpc::controller
