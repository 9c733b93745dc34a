// Runs scenario files (seeds 1 and 2) with a path follower of your own: ovpc_example_own_follower FILE...
#include <cmath>
#include <iostream>

#include "ovpc/scenarios/closed_loop.h"
#include "ovpc/scenarios/report.h"
#include "ovpc/scenarios/scenario_yaml.h"

using namespace ovpc;

class Carrot : public navigation::PathFollower {  // steers for the path pose 2 m on, at 0.8 m/s, forward only
 public:
  explicit Carrot(double wheelbase_m) : wheelbase_m_(wheelbase_m) {}
  void Follow(const planner::Path& path_O) override { poses_ = path_O.Poses(), done_ = false; }
  void Clear() override { poses_.clear(); }
  bool has_path() const override { return !poses_.empty(); }
  bool done() const override { return done_; }
  controller::Command Update(const planner::Pose2& p, double /*speed_mps*/) override {
    const auto dist = [&p](const planner::PathPose& q) { return std::hypot(q.pose.x_m - p.x_m, q.pose.y_m - p.y_m); };
    std::size_t i = 0;
    for (std::size_t k = 1; k < poses_.size(); ++k) i = dist(poses_[k]) < dist(poses_[i]) ? k : i;
    while (i + 1 < poses_.size() && dist(poses_[i]) < 2.0) ++i;
    const double bearing = std::atan2(poses_[i].pose.y_m - p.y_m, poses_[i].pose.x_m - p.x_m) - p.yaw_rad;
    if ((done_ = done_ || dist(poses_.back()) < 0.3)) return {0.0, 0.0, true};
    return {std::atan(2.0 * wheelbase_m_ * std::sin(bearing) / std::max(dist(poses_[i]), 0.5)), 0.8, false};
  }
 private:
  double wheelbase_m_; std::vector<planner::PathPose> poses_; bool done_ = false;
};

int main(int argc, char** argv) try {
  scenarios::RunOptions options;  // a fresh follower for every run; map and planner stay the default
  options.make_plugins = [](const auto& config) {
    return navigation::Navigator::Plugins{nullptr, nullptr, std::make_unique<Carrot>(config.vehicle.wheelbase_m)};
  };
  int failed = 0;  // runs that failed a criterion
  for (int i = 1; i < argc; ++i) {
    const scenarios::Scenario scenario = scenarios::LoadScenario(argv[i]);
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      const scenarios::RunResult result = scenarios::RunClosedLoop(scenario, seed, options);
      std::cout << scenarios::FormatScorecard(scenario, result);
      failed += result.passed ? 0 : 1;
    }
  }
  return failed == 0 ? 0 : 1;
} catch (const scenarios::ScenarioError& e) {
  std::cerr << e.what() << "\n";
  return 2;
}
