// A scenario: the world, the vehicle's start and route, faults, the robot's configuration and the success
// criteria of one closed-loop run. Filled from YAML by LoadScenario (scenario_yaml.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ovpc/backends/map_selection.h"
#include "ovpc/navigation/navigator.h"
#include "ovpc/sim/simulator.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::scenarios {

/// An axis-aligned rectangle in the world frame the vehicle must never enter (any part of its
/// footprint), e.g. the ground under a low roof.
struct Region {
  std::string name;
  Eigen::Vector2d min_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_m = Eigen::Vector2d::Zero();
  /// What may not enter it: any part of the vehicle's footprint (a roof too low to pass under), or
  /// a wheel's contact point (ground a wheel must not be on: a ditch, a steep face; the body may
  /// overhang it).
  enum class By { kFootprint, kWheels };
  By by = By::kFootprint;
};

/// Success criteria with expected values (CARLA ScenarioRunner style). Unset ones are not checked.
struct Criteria {
  std::optional<Eigen::Vector2d> goal_m;  ///< goal region centre, world frame
  double goal_radius_m = 2.0;
  bool no_collision = true;               ///< no contact of a non-wheel vehicle body with the world
  std::optional<double> max_roll_deg;
  std::optional<double> max_pitch_deg;
  std::optional<double> max_time_s;       ///< the goal must be reached by then
  std::optional<double> min_progress_m;   ///< distance driven along the route
  std::vector<Region> forbidden;
};

/// What the testbed records of a run (the Recorder; not the robot's settings), in simulated time.
struct Recording {
  struct Config {
    double record_rate_hz = 10.0;          ///< trajectory rows
    double mesh_snapshot_period_s = 10.0;  ///< mesh_*.ply snapshots (0: none)
    bool mcap = false;                     ///< run.mcap, the run log for Foxglove (docs/RUN_LOGS.md)
    double mcap_scan_period_s = 0.5;       ///< a LiDAR scan in run.mcap at most this often (0: every scan)
    double mcap_map_period_s = 1.0;        ///< the map in run.mcap at most this often (0: every map cycle)
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, record_rate_hz), "Hz", "trajectory.csv rows per simulated second");
      v.Field(OVPC_FIELD(c, mesh_snapshot_period_s), "s", "mesh_*.ply snapshots; 0: none");
      v.Field(OVPC_FIELD(c, mcap), "", "run.mcap, a run log that Foxglove opens (ovpc run --mcap)");
      v.Field(OVPC_FIELD(c, mcap_scan_period_s), "s", "a LiDAR scan in run.mcap at most this often; 0: every scan");
      v.Field(OVPC_FIELD(c, mcap_map_period_s), "s", "the map in run.mcap at most this often; 0: every map cycle");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

struct Scenario {
  std::string name;
  std::string description;
  std::string path;                 ///< the file it came from
  std::uint64_t seed = 1;           ///< default seed; `ovpc run --seed` overrides
  double time_limit_s = 60.0;
  sim::Simulator::Config sim;       ///< world, vehicle, start pose, sensor faults, odometry faults
  std::vector<Eigen::Vector2d> route_m;  ///< global route, world frame (= odometry frame at start)
  navigation::Navigator::Config navigator;  ///< the robot's stack
  /// The map backend the run uses, for comparisons (`navigator.map`; its sections sit under
  /// `navigator:` beside the robot's own settings). The robot's stack knows only its plug-in.
  backends::MapSelection map_backends;
  Recording::Config record;
  Criteria criteria;
  std::vector<std::string> labels;  ///< e.g. "long": kept out of the default suite

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

}  // namespace ovpc::scenarios
