#include "ovpc/controller/rollout.h"

#include <cmath>
#include <stdexcept>

namespace ovpc::controller {

std::vector<planner::Pose2> Rollout(const PurePursuit::Config& follower_config, const BicycleModel& model,
                                    const planner::Path& path, const BicycleModel::State& start, double dt_s,
                                    double spacing_m, double max_time_s) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(dt_s) || !positive(spacing_m) || !positive(max_time_s)) {
    throw std::invalid_argument("Rollout: dt_s, spacing_m and max_time_s must be > 0 and finite");
  }
  PurePursuit follower(follower_config, path, {model.config().wheelbase_m, model.config().max_steering_rad});
  std::vector<planner::Pose2> poses{start.pose};
  BicycleModel::State state = start;
  double since_last = 0.0;
  const auto steps = static_cast<long>(std::ceil(max_time_s / dt_s));
  for (long i = 0; i < steps; ++i) {
    const Command command = follower.Update(state.pose, state.speed_mps);
    if (command.done && std::abs(state.speed_mps) < 1e-6) break;
    const BicycleModel::State next = model.Step(state, command, dt_s);
    since_last += std::hypot(next.pose.x_m - state.pose.x_m, next.pose.y_m - state.pose.y_m);
    state = next;
    if (since_last >= spacing_m) {
      poses.push_back(state.pose);
      since_last = 0.0;
    }
  }
  if (since_last > 0.0) poses.push_back(state.pose);
  return poses;
}

}  // namespace ovpc::controller
