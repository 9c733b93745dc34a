// The robot's stack between the sensor and the wheels: buffer, map preparation, map backend, local
// goal and re-planning, planner and follower, driven by the time the caller gives it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/controller/command.h"
#include "ovpc/controller/pure_pursuit.h"
#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/navigation/map_backend.h"
#include "ovpc/navigation/map_preparation.h"
#include "ovpc/navigation/ovpc_map_backend.h"
#include "ovpc/navigation/path_follower.h"
#include "ovpc/navigation/path_planner.h"
#include "ovpc/navigation/records.h"
#include "ovpc/navigation/task_thread.h"
#include "ovpc/core/vehicle_model.h"
#include "ovpc/planner/local_goal.h"
#include "ovpc/planner/local_planner.h"
#include "ovpc/planner/replan.h"
#include "ovpc/planner/route_tracker.h"

namespace ovpc::navigation {

/// The robot's stack. Inputs are what a robot has: LiDAR scans with their odometry poses, the
/// odometry pose, the global route (in the odometry frame O), and the time; the output is a command.
/// Everything runs on the caller's time (simulated time in the testbed): the same inputs give the
/// same commands, bit for bit.
///
/// Call per odometry update, in this order: Control (at any rate; it runs the follower at
/// Timing::control_rate_hz and otherwise repeats the last command), AddScan for each new scan,
/// Update (it tracks route progress and, at Timing::map_rate_hz, runs one map-and-plan cycle).
class Navigator {
 public:
  /// When the stack runs, on the caller's clock.
  struct Timing {
    double map_rate_hz = 5.0;        ///< map-and-plan cycles per second (at most 100; the paper gives none)
    double control_rate_hz = 50.0;   ///< follower commands per second (at most 1000)
    /// The map-and-plan cycle started from the data up to time t takes effect (its path is driven)
    /// at t + latency_s, as on a robot that maps and plans while it drives; in between, the vehicle
    /// follows the previous path. The trajectory depends on this value, never on whether the cycle
    /// ran on another thread (RunCyclesOnAWorkerThread). 0: at once (the cycle costs no time). At
    /// most the map period.
    double latency_s = 0.0;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, map_rate_hz), "Hz", "map-and-plan cycles per second (the paper gives none)");
      v.Field(OVPC_FIELD(c, control_rate_hz), "Hz", "follower commands per second");
      v.Field(OVPC_FIELD(c, latency_s), "s", "a cycle takes effect this long after its data; 0: at once");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// Which path the vehicle drives: the goals tried, the support it stands on, when a new path
  /// replaces the current one, and what is left of a blocked one.
  struct PathChoice {
    /// Local goal candidates tried per re-plan, best first, until one gives a path.
    int goal_candidates = 3;
    /// A plan to the route's end may also arrive heading straight from the vehicle to it.
    bool route_end_any_heading = true;
    /// A goal short of the route's end whose heading turns more than this from the vehicle's may also
    /// be reached heading straight from the vehicle to it. Just past a sharp corner the route's
    /// heading asks the vehicle to have turned already, which with its turning circle takes a loop or
    /// a three-point turn; the next goals turn it further. Infinite: off (the goal's heading only).
    double direct_heading_turn_deg = std::numeric_limits<double>::infinity();
    /// When no candidate gives a path and the vehicle has none, a goal this fraction of the way to
    /// the best candidate (heading straight at it, at least local_goal.min_distance_m away) is tried
    /// too. Far ground is seen sparsely; from nearer, the sensor sees it well enough to stand on.
    /// 0: off.
    double nearer_goal_fraction = 0.0;
    /// The planner takes the ground under the vehicle's footprint, grown by this margin, as support
    /// for the wheels (the vehicle stands on it, though the sensor never sees it). Negative disables.
    double known_support_margin_m = 0.3;
    /// A periodic re-plan (the current path still valid) replaces the current path only if the new
    /// one is shorter by more than this, counting for each path its length, `cusp_cost_m` per change
    /// of direction (one more when it starts the other way than the vehicle is driving) and the
    /// route left after its goal. A new path each second that starts the other way rocks the vehicle
    /// on the spot. Negative: every new path replaces the current one (the paper's rule).
    double keep_path_within_m = -1.0;
    double cusp_cost_m = 0.0;
    /// A new path is taken only if the built-in follower, driven along it from where the vehicle
    /// will be (controller::Rollout), keeps the vehicle box grown by this margin clear of every map
    /// point (a collision; the ground checks are the path's own). The planner checks the path's
    /// poses; the vehicle drives the follower's: a cusp segment shorter than the follower's stop
    /// tolerance is skipped and a corner is cut. The current path is kept only if, besides, no
    /// rollout pose farther than planner.check_resolution_m from it puts a wheel on ground the
    /// planner rejects (ground under footprint): a vehicle that has drifted off an older path does
    /// not follow it over an edge. Negative: off (the paper's rule). With a follower plug-in there
    /// is no rollout (its behaviour is not known).
    double rollout_margin_m = -1.0;
    /// A blocked path that no new plan replaces is driven up to this far before its first blocked
    /// pose; a remaining prefix shorter than `min_prefix_m` is dropped and the vehicle stands.
    double blocked_stop_short_m = 0.5;
    double min_prefix_m = 0.3;
    /// Creep and look. With the planner's crest test on (planner.vehicle.crest_margin_m), the first
    /// pose of the path ahead (up to 4 m of it) whose wheels would fail the crest test taken this far
    /// beyond them (the sensor has seen the ground fall away there and nothing under it) is a place to
    /// arrive at no faster than edge_speed_mps: the command's speed is capped at
    /// sqrt(edge_speed^2 + 2 a d), d the distance to that pose and a the follower's stop_decel_mps2.
    /// At that speed the vehicle stops within centimetres when the next map shows the edge. Negative:
    /// off.
    double edge_look_m = -1.0;
    double edge_speed_mps = 0.3;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, goal_candidates), "goals", "local goals tried per re-plan until one gives a path");
      v.Field(OVPC_FIELD(c, route_end_any_heading), "", "the route's end may be reached at any heading");
      v.Field(OVPC_FIELD(c, direct_heading_turn_deg), "deg", "a goal turned more than this may be reached heading straight at it; inf: off");
      v.Field(OVPC_FIELD(c, nearer_goal_fraction), "", "with no path found while standing, try this fraction of the way to the best goal; 0: off");
      v.Field(OVPC_FIELD(c, known_support_margin_m), "m", "the vehicle stands on its unseen footprint grown by this");
      v.Field(OVPC_FIELD(c, keep_path_within_m), "m", "a periodic re-plan must be this much shorter; < 0: paper");
      v.Field(OVPC_FIELD(c, cusp_cost_m), "m", "a change of direction counts this many metres");
      v.Field(OVPC_FIELD(c, rollout_margin_m), "m", "the follower's rollout keeps the box grown by this clear; < 0: off");
      v.Field(OVPC_FIELD(c, blocked_stop_short_m), "m", "a blocked path is driven up to this far before the block");
      v.Field(OVPC_FIELD(c, min_prefix_m), "m", "a shorter remaining prefix is dropped");
      v.Field(OVPC_FIELD(c, edge_look_m), "m", "slow down before a pose with an unseen drop this far past its wheels; < 0: off");
      v.Field(OVPC_FIELD(c, edge_speed_mps), "m/s", "... to this speed");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  struct Config {
    Timing timing;
    VehicleModel vehicle;
    PointCloudBuffer::Config buffer;
    MapPreparation::Config preparation;
    /// The default map backend (a Plugins::map replaces it).
    OvpcMapBackend::Config ovpc;
    /// The default planner: the box check's rules and the search (the box's size and the turning
    /// radius come from `vehicle`).
    planner::LocalPlanner::Config planner;
    planner::LocalGoalSelection::Config local_goal;
    planner::Replanning::Config replan;
    PathChoice path_choice;
    /// Route progress in the route's order (planner::RouteTracker): a route that comes back beside
    /// itself is followed leg by leg.
    planner::RouteTracker::Config progress;
    /// The default follower (its steering geometry comes from `vehicle`).
    controller::PurePursuit::Config follower;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, timing), "when the stack runs");
      v.Section(OVPC_FIELD(c, vehicle), "the robot's own geometry");
      v.Section(OVPC_FIELD(c, buffer), "the paper's point cloud buffer");
      v.Section(OVPC_FIELD(c, preparation), "what happens to the buffered cloud before the map is made");
      v.Section(OVPC_FIELD(c, ovpc), "the OVPC Mesh map backend");
      v.Section(OVPC_FIELD(c, planner), "RRTConnect in Reeds-Shepp space (the paper's)");
      v.Section(OVPC_FIELD(c, local_goal), "where each plan goes");
      v.Section(OVPC_FIELD(c, replan), "the paper's triggers");
      v.Section(OVPC_FIELD(c, path_choice), "which path is driven");
      v.Section(OVPC_FIELD(c, progress), "route progress");
      v.Section(OVPC_FIELD(c, follower), "pure pursuit");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
    /// The box the default planner checks: `vehicle`'s size with `planner.vehicle`'s rules.
    planner::VehicleBox Box() const { return planner::VehicleBox::Of(vehicle, planner.vehicle); }
  };

  /// Plug-ins; a null one is the default (OvpcMapBackend, RrtConnectPlanner, PurePursuitFollower
  /// from the config). backends/ has the comparison map backends (OctoMap, a 2.5D elevation map).
  struct Plugins {
    std::unique_ptr<MapBackend> map;
    std::unique_ptr<PathPlanner> planner;
    std::unique_ptr<PathFollower> follower;
  };

  /// @param route_O the global route in the odometry frame, in driving order (at least one point).
  /// @param planner_seed seeds the default planner's random sources (the testbed gives the run's seed).
  /// @throws std::invalid_argument for an invalid config or route.
  Navigator(const Config& config, std::vector<Eigen::Vector2d> route_O, Plugins plugins = {},
            std::uint32_t planner_seed = 1);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// The command at `time_s` for the vehicle at odometry pose `T_O_B` moving at `speed_mps`: the
  /// follower's at the control rate, otherwise the last one. Stand (done) when there is no path.
  controller::Command Control(double time_s, const Eigen::Isometry3d& T_O_B, double speed_mps);
  /// Buffers one LiDAR scan (points in the sensor frame with the sensor's odometry pose).
  void AddScan(Scan scan);
  /// Tracks route progress at `T_O_B`; when a map cycle is due at `time_s`, starts one (mapping and
  /// planning from the scans so far), and when a cycle's Timing::latency_s has passed, waits for it
  /// and puts its result into effect. Returns true if a cycle's result took effect.
  bool Update(double time_s, const Eigen::Isometry3d& T_O_B);
  /// With `on` and a latency, each map-and-plan cycle runs on a thread of its own while the caller
  /// goes on (Control, AddScan, Update); the result is the same as without. Off by default.
  void RunCyclesOnAWorkerThread(bool on) { worker_thread_ = on; }
  /// A map-and-plan cycle is running on the worker thread right now (it has not finished its
  /// work; whether it has taken effect is another matter). A hint for sharing the cores: the answer
  /// depends on thread timing, so nothing that shapes the trajectory may depend on it.
  bool CycleRunning() const;

  // What a user looks at.
  const controller::Command& command() const { return command_; }
  /// The current path (odometry frame O); empty when the vehicle stands.
  const planner::Path& path_O() const { return state_.path_O; }
  bool has_path() const { return follower_->has_path(); }
  /// The vehicle has reached the end of a path whose goal is the route's end.
  bool route_end_reached() const { return follower_->has_path() && follower_->done() && state_.goal_is_route_end; }
  /// The current local goal (odometry frame), if a path leads to one.
  const std::optional<Eigen::Vector2d>& goal_O() const { return state_.goal_O; }
  /// The latest map (null before the first good cycle), in the frame of its cycle, T_O_L.
  const std::shared_ptr<const planner::PlanningMap>& map() const { return map_; }
  const Eigen::Isometry3d& map_T_O_L() const { return map_T_O_L_; }
  /// The vehicle in the latest good map's frame L, at that cycle.
  const Eigen::Isometry3d& map_T_L_B() const { return map_T_L_B_; }
  /// Good maps so far (changes when a new map is made).
  std::size_t map_count() const { return stats_.map_updates - stats_.map_failures; }
  const MapBackend& map_backend() const { return *backend_; }
  /// Route progress of the odometry pose, m.
  double route_progress_m() const { return progress_m_; }
  /// Every planner call and every cycle since the start or the last ClearRecords (cycles whose result
  /// has taken effect).
  const std::vector<PlanAttempt>& plan_log() const { return plan_log_; }
  const std::vector<CycleRecord>& cycles() const { return cycles_; }
  /// Drops the records and stage timings kept so far (a robot that logs them elsewhere calls this
  /// now and then: they grow with every cycle). Counters in stats() are kept.
  void ClearRecords();
  /// Counters and stage timings.
  NavigatorStats stats() const;
  const Config& config() const { return config_; }
  /// The box the default planner and the checks use (Config::Box()).
  const planner::VehicleBox& box() const { return box_; }

 private:
  // The re-planning state (odometry frame O). The navigator keeps the one in effect; a cycle starts
  // from a copy of it and, when its result takes effect, its copy replaces it.
  struct PlanState {
    planner::Path path_O;
    std::optional<Eigen::Vector2d> goal_O;          // the local goal the current path leads to
    std::optional<planner::LocalGoal> last_goal_O;  // kept for the next goal selection
    bool goal_is_route_end = false;
    bool goal_is_look = false;      // the goal is a place to look from at a rim
    std::optional<double> last_plan_s;
    int blocked_updates = 0;                        // map cycles in a row that found the path blocked
    std::optional<Eigen::Vector2d> edge_O;          // the path's first pose near an unseen drop (edge_look_m)
  };
  struct Job;    // one cycle: its inputs, state and results
  struct Cycle;  // map-frame helpers of one cycle
  void Launch(double time_s, const Eigen::Isometry3d& T_O_B);
  planner::PoseCheck RolloutCheck(const Job& job, const Cycle& c, const planner::Path& path_L, bool wheels_off_path) const;
  void Finish();
  void MapCycle(Job* job);
  // MapCycle's steps: the buffered cloud made ready for the map; the re-plan triggers checked and acted on.
  PointCloudBuffer::LocalCloud PrepareCloud(const Job& job);
  void CheckAndReplan(Job* job, const Cycle& c);
  // The path's first pose ahead near an unseen drop (PathChoice::edge_look_m), into the job's state.
  void FindEdgeAhead(Job* job, const Cycle& c) const;
  bool PathBlocked(const Job& job, const Cycle& c, std::size_t* closest, std::size_t* blocked_index) const;
  // `may_keep`: a periodic re-plan may keep the current path when the new one is no better.
  bool Replan(Job* job, const Cycle& c, planner::ReplanReason reason, bool blocked, std::size_t closest,
              std::size_t blocked_index, bool may_keep);
  // Replan's steps: the record its attempts share; one goal tried.
  PlanAttempt AttemptRecord(const Job& job, const Cycle& c, planner::ReplanReason reason, bool blocked,
                            std::size_t blocked_index) const;
  enum class GoalTry { kNext, kTaken, kStop };  // try the next goal; the cycle has its path; no goal will do
  GoalTry TryGoal(Job* job, const Cycle& c, const PlanAttempt& record, const planner::LocalGoal& goal,
                  planner::ReplanReason reason, std::size_t closest, bool may_keep);
  /// Periodic re-plans: is the new path (to `goal`) worth more than what is left of the current one?
  bool NewPathIsBetter(const PlanState& state, const planner::Path& new_path_L, const planner::LocalGoal& goal,
                       std::size_t closest) const;
  void KeepValidPrefix(Job* job, std::size_t closest, std::size_t blocked_index) const;

  Config config_;
  planner::VehicleBox box_;  // config_.Box()
  std::vector<Eigen::Vector2d> route_O_;
  std::unique_ptr<MapBackend> backend_;
  std::unique_ptr<PathPlanner> planner_;
  std::unique_ptr<PathFollower> follower_;
  PointCloudBuffer buffer_;

  // Timing of the cycles (simulated or robot time).
  double next_map_s_ = 0.0, next_control_s_ = 0.0;
  controller::Command command_;
  double speed_mps_ = 0.0;  // measured, at the last control tick
  bool builtin_follower_ = true;  // no follower plug-in: the rollout models the follower
  PlanState state_;  // the re-planning state in effect
  std::optional<planner::RouteTracker> tracker_;  // routes of two or more points
  double progress_m_ = 0.0;
  // The cycle started and not yet in effect, and the scans that arrived meanwhile.
  std::unique_ptr<Job> job_;
  std::vector<Scan> incoming_;
  bool worker_thread_ = false;
  std::unique_ptr<TaskThread> worker_;  // the thread cycles run on (RunCyclesOnAWorkerThread)
  // The latest map.
  std::shared_ptr<const planner::PlanningMap> map_;
  Eigen::Isometry3d map_T_O_L_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d map_T_L_B_ = Eigen::Isometry3d::Identity();
  // Records.
  NavigatorStats stats_;
  std::vector<PlanAttempt> plan_log_;
  std::vector<CycleRecord> cycles_;
  StageTimer t_buffer_, t_mapper_, t_planner_, t_controller_;
  std::vector<std::pair<std::string, StageTimer>> t_map_stages_;
};

/// The pose's planar part: position and the heading of its x axis.
planner::Pose2 ToPose2(const Eigen::Isometry3d& T);

}  // namespace ovpc::navigation
