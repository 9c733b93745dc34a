// The run log: run.mcap, an MCAP file that Foxglove opens (docs/RUN_LOGS.md), written beside the
// Recorder's files when `record.mcap` is on. Timestamps are the simulated time, so the same
// scenario and seed give the same bytes; it reads the run and changes nothing in it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/mcap/mcap_writer.h"
#include "ovpc/navigation/navigator.h"
#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/scenario.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::scenarios {

class RunLog {
 public:
  /// Opens `path` and writes the schemas, the channels and the world (terrain and objects, at t = 0).
  /// @throws mcap::McapError if the file cannot be written.
  RunLog(const std::string& path, const Recording::Config& config, const sim::Simulator& sim);

  /// The frames world -> odom -> base -> lidar, the true and odometry poses and the command, at `time_s`.
  void Poses(double time_s, const sim::Simulator& sim, const controller::Command& command);
  /// A LiDAR scan, in the odometry frame through its pose T_O_S, when one is due (record.mcap_scan_period_s).
  void Scan(const sim::Simulator::SensorScan& scan);
  /// The planner's calls `attempts` of the cycle recorded at `time_s` (local goal, outcome) and the
  /// path the navigator follows after it.
  void Plans(double time_s, const std::vector<navigation::PlanAttempt>& attempts, const navigation::Navigator& navigator);
  /// The map of the cycle recorded at `time_s` when one is due (record.mcap_map_period_s): mesh faces by
  /// traversability and the vertex cloud.
  void Map(double time_s, const navigation::Navigator& navigator, const navigation::MapView& view);
  /// The criteria and the diagnosis as log lines at the run's end, then the summary; closes the file.
  /// @throws mcap::McapError if the file could not be written.
  void Finish(const RunResult& result);

 private:
  std::uint16_t Channel(const std::string& topic, const std::string& schema);
  void World(const sim::Simulator& sim);

  Recording::Config config_;
  mcap::McapWriter writer_;
  std::vector<std::pair<std::string, std::uint16_t>> schemas_;
  std::uint16_t tf_ = 0, pose_true_ = 0, pose_odom_ = 0, command_ = 0, scan_ = 0, map_mesh_ = 0, map_points_ = 0, plan_ = 0,
                world_ = 0, log_ = 0;
  double next_scan_s_ = 0.0, next_map_s_ = 0.0;
};

}  // namespace ovpc::scenarios
