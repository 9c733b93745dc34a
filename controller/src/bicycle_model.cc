#include "ovpc/controller/bicycle_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ovpc::controller {

void BicycleModel::Config::Validate() const {
  const auto positive = [](double value, const char* field) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("BicycleModel::Config: ") + field + " must be > 0, got " +
                                  std::to_string(value));
    }
  };
  positive(wheelbase_m, "wheelbase_m");
  positive(max_steering_rate_radps, "max_steering_rate_radps");
  positive(max_accel_mps2, "max_accel_mps2");
  if (!(max_steering_rad > 0.0 && max_steering_rad < kPi / 2)) {
    throw std::invalid_argument("BicycleModel::Config: max_steering_rad must be in (0, pi/2)");
  }
}

BicycleModel::BicycleModel(const Config& config) : config_(config) { config_.Validate(); }

BicycleModel::State BicycleModel::Step(const State& state, const Command& command, double dt_s) const {
  State next = state;
  const double dv = std::clamp(command.speed_mps - state.speed_mps, -config_.max_accel_mps2 * dt_s,
                               config_.max_accel_mps2 * dt_s);
  next.speed_mps = state.speed_mps + dv;
  const double steering_goal = std::clamp(command.steering_rad, -config_.max_steering_rad, config_.max_steering_rad);
  const double max_change = config_.max_steering_rate_radps * dt_s;
  next.steering_rad = state.steering_rad + std::clamp(steering_goal - state.steering_rad, -max_change, max_change);

  // Exact integration along the arc of the new steering angle at the mean speed of the step.
  const double distance = 0.5 * (state.speed_mps + next.speed_mps) * dt_s;
  const double curvature = std::tan(next.steering_rad) / config_.wheelbase_m;
  const double yaw = state.pose.yaw_rad;
  const double turn = distance * curvature;
  if (std::abs(turn) < 1e-9) {
    next.pose.x_m += distance * std::cos(yaw);
    next.pose.y_m += distance * std::sin(yaw);
  } else {
    next.pose.x_m += (std::sin(yaw + turn) - std::sin(yaw)) / curvature;
    next.pose.y_m += (std::cos(yaw) - std::cos(yaw + turn)) / curvature;
  }
  next.pose.yaw_rad = planner::NormalizeYaw(yaw + turn);
  return next;
}

}  // namespace ovpc::controller
