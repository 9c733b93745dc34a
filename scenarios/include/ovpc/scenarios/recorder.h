// The recorder: what a run leaves for a user to look at, sampled in simulated time — trajectory
// rows, the planner's calls in the world frame, the mapped points, mesh snapshots and frames.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ovpc/navigation/navigator.h"
#include "ovpc/scenarios/closed_loop.h"
#include "ovpc/scenarios/scenario.h"
#include "ovpc/sim/renderer.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::scenarios {

class RunLog;

/// The run log's name in the output folder (written as run.mcap.part and renamed when complete).
inline constexpr const char* kRunLogName = "run.mcap";

/// The map points a run keeps for its top-down picture (RunResult::map_points), in memory bounded
/// whatever the run's length: every 7th point of each map while they are at most `max_points`
/// (about 5 minutes of simulated time at the default bound: such a run's picture is what it always
/// was); when the next map's would exceed that, every other point kept so far is dropped and the
/// stride doubles, counted on across maps from then on. Deterministic: the same maps give the same
/// points.
class MapPointSampler {
 public:
  static constexpr std::size_t kDefaultMaxPoints = std::size_t{1} << 22;  ///< 128 MiB of MapPoint
  explicit MapPointSampler(std::size_t max_points = kDefaultMaxPoints);

  /// Adds the sampled points of one map, `points_L` placed in the world through `T_W_L`;
  /// `traversable(i)` is point i's flag.
  void Add(const std::vector<Vec3>& points_L, const Eigen::Isometry3d& T_W_L, const std::function<bool(std::size_t)>& traversable,
           std::vector<MapPoint>* kept);
  std::size_t stride() const { return stride_; }

 private:
  static constexpr std::size_t kFirstStride = 7;
  std::size_t max_points_;
  std::size_t stride_ = kFirstStride;
  std::size_t phase_ = 0;  ///< where the next map starts, after a thinning
};

/// True for the names the recorder gives its snapshots and frames: mesh_<iii>_t<time>.ply (and its
/// .partial while written) and frame_<ccccc>.png.
bool IsRecorderPicture(const std::string& name);
/// Removes the files of `dir` (not of its subfolders) that IsRecorderPicture names; nothing else.
/// A recorder does this to its folder first, so that a folder never mixes two runs' pictures.
void RemoveRecorderPictures(const std::string& dir);

class Recorder {
 public:
  /// @param result where the records go (trajectory, plan_log, map_points, files). `scenario`,
  /// `options` and `result` must outlive the recorder.
  Recorder(const Scenario& scenario, const RunOptions& options, const sim::Simulator& sim, RunResult* result);
  ~Recorder();

  /// A trajectory row when one is due (`now_s`: the step's start; the row carries `time_s`, after it).
  void Trajectory(double now_s, double time_s, const sim::Simulator& sim, const controller::Command& command);
  /// After a map cycle took effect: the plans it made and the map it built, placed in the world through
  /// `T_W_O`, the odometry frame in the world now.
  void MapCycle(double time_s, const Eigen::Isometry3d& T_W_O, const navigation::Navigator& navigator);
  /// A chase-camera frame when one is due (RunOptions::frames).
  void Frame(double time_s, const sim::Simulator& sim, const navigation::Navigator& navigator);
  /// A LiDAR scan as the simulator gave it (for the run log).
  void Scan(const sim::Simulator::SensorScan& scan);
  /// At the run's end, once `result` is scored: the run log's last lines, and run.mcap complete.
  void Finish(const RunResult& result);

 private:
  const Scenario& scenario_;
  const RunOptions& options_;
  RunResult* result_;
  std::unique_ptr<sim::Renderer> renderer_;
  double next_record_s_ = 0.0, next_snapshot_s_ = 0.0, next_frame_s_ = 0.0;
  int snapshot_index_ = 0;
  MapPointSampler map_points_;
  std::size_t plans_seen_ = 0, maps_seen_ = 0;
  // The latest map's points and where its frame was in the world, for frames.
  std::vector<Vec3> frame_points_L_;
  std::vector<std::uint8_t> frame_traversable_;
  Eigen::Isometry3d frame_T_W_L_ = Eigen::Isometry3d::Identity();
  // A snapshot or frame that cannot be written is a warning (on stderr, the first few), not the
  // end of the run: the result files are what must be whole.
  void Warn(const std::string& what);
  int warnings_ = 0;
  // The run log (record.mcap), null when off or after a write failed (a warning, not the run's end).
  std::unique_ptr<RunLog> run_log_;
  std::string run_log_part_;
  template <class F>
  void ToRunLog(const F& write);
};

}  // namespace ovpc::scenarios
