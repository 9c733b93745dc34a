// The closed loop: the simulator and the robot's Navigator stepped together in simulated time, the
// Referee scoring the run from the truth and the Recorder keeping what a user looks at.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/scenario.h"

namespace ovpc::scenarios {

struct RunOptions {
  /// Plug-ins for the robot's stack, made for each run from its effective configuration: a user's
  /// own map backend, planner or follower. Unset, or a null plug-in: the navigator's default, but
  /// for the map backend, which is then the one the scenario's `navigator.map` names.
  std::function<navigation::Navigator::Plugins(const navigation::Navigator::Config&)> make_plugins;
  std::string out_dir;    ///< mesh snapshots and frames go here ("" writes none)
  bool frames = false;    ///< rendered chase-camera PNG frames (needs EGL)
  double frame_period_s = 0.5;
  bool progress = false;  ///< a progress line on stderr
  /// 2: the navigator's map-and-plan cycles run on a thread of their own when the configuration
  /// has a latency (navigator.latency_s > 0); the trajectory is the same with 1.
  int threads = 1;
};

/// Runs the scenario with `seed` feeding every random source (LiDAR noise and faults, odometry,
/// planner). The same scenario and seed give a bit-identical trajectory on the same machine.
/// @throws std::invalid_argument for an invalid scenario, std::runtime_error if the simulator fails.
RunResult RunClosedLoop(const Scenario& scenario, std::uint64_t seed, const RunOptions& options);

}  // namespace ovpc::scenarios
