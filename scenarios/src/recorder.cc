#include "ovpc/scenarios/recorder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "ovpc/io/cloud_io.h"
#include "ovpc/sim/image.h"
#include "format.h"
#include "run_log.h"

namespace ovpc::scenarios {
namespace {

using internal::Fixed;

}  // namespace

bool IsRecorderPicture(const std::string& name) {
  const auto digits = [&name](std::size_t from, std::size_t to) {
    if (from >= to) return false;
    for (std::size_t i = from; i < to; ++i) {
      if (!std::isdigit(static_cast<unsigned char>(name[i])) && name[i] != '.') return false;
    }
    return true;
  };
  const auto ends = [&name](const std::string& tail) {
    return name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (name.rfind("frame_", 0) == 0 && ends(".png")) return digits(6, name.size() - 4);
  if (name.rfind("mesh_", 0) != 0) return false;
  const std::size_t t = name.find("_t", 5);
  if (t == std::string::npos || !digits(5, t)) return false;
  if (ends(".ply")) return digits(t + 2, name.size() - 4);
  return ends(".ply.partial") && digits(t + 2, name.size() - 12);
}

void RemoveRecorderPictures(const std::string& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (IsRecorderPicture(name) && entry.is_regular_file(ec)) std::filesystem::remove(entry.path(), ec);
  }
}

MapPointSampler::MapPointSampler(std::size_t max_points) : max_points_(std::max<std::size_t>(max_points, 16)) {}

void MapPointSampler::Add(const std::vector<Vec3>& points_L, const Eigen::Isometry3d& T_W_L,
                          const std::function<bool(std::size_t)>& traversable, std::vector<MapPoint>* kept) {
  // At the first stride each map starts at its point 0; after a thinning the points are taken
  // across maps (a stride may then exceed a map's size).
  const std::size_t n = points_L.size();
  const auto count = [this, n] {
    const std::size_t first = stride_ == kFirstStride ? 0 : phase_;
    return first < n ? (n - first + stride_ - 1) / stride_ : 0;
  };
  while (kept->size() + count() > max_points_ && kept->size() > 1) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < kept->size(); i += 2) (*kept)[k++] = (*kept)[i];
    kept->resize(k);
    stride_ *= 2;
  }
  std::size_t i = stride_ == kFirstStride ? 0 : phase_;
  for (; i < n && kept->size() < max_points_; i += stride_) kept->push_back({T_W_L * points_L[i], traversable(i)});
  phase_ = i >= n ? i - n : 0;
}

Recorder::Recorder(const Scenario& scenario, const RunOptions& options, const sim::Simulator& sim, RunResult* result)
    : scenario_(scenario), options_(options), result_(result), next_snapshot_s_(scenario.record.mesh_snapshot_period_s) {
  if (options.frames) renderer_ = std::make_unique<sim::Renderer>(sim);
  if (options.out_dir.empty()) return;
  std::filesystem::create_directories(options.out_dir);
  RemoveRecorderPictures(options.out_dir);  // an earlier run's, which would sit beside this one's
  const std::filesystem::path log = std::filesystem::path(options.out_dir) / kRunLogName;
  std::filesystem::remove(log);  // an earlier run's, likewise
  if (!scenario.record.mcap) return;
  run_log_part_ = log.string() + ".part";
  ToRunLog([&] { run_log_ = std::make_unique<RunLog>(run_log_part_, scenario.record, sim); });
}

template <class F>
void Recorder::ToRunLog(const F& write) {
  if (run_log_part_.empty()) return;
  try {
    write();
  } catch (const std::exception& e) {
    Warn(std::string("run log: ") + e.what());  // the log lost, not the run
    run_log_.reset();
    std::error_code ec;
    std::filesystem::remove(run_log_part_, ec);
    run_log_part_.clear();
  }
}

void Recorder::Scan(const sim::Simulator::SensorScan& scan) {
  if (run_log_) ToRunLog([&] { run_log_->Scan(scan); });
}

void Recorder::Finish(const RunResult& result) {
  if (!run_log_) return;
  ToRunLog([&] {
    run_log_->Finish(result);
    run_log_.reset();
    const std::string part = run_log_part_;
    std::filesystem::rename(part, part.substr(0, part.size() - 5));  // drop ".part": complete
  });
}

Recorder::~Recorder() = default;

void Recorder::Trajectory(double now_s, double time_s, const sim::Simulator& sim, const controller::Command& command) {
  if (!(now_s + 1e-9 >= next_record_s_)) return;
  next_record_s_ += 1.0 / scenario_.record.record_rate_hz;
  result_->trajectory.push_back(
      {time_s, sim.T_W_B(), sim.T_O_B(), sim.forward_speed_mps(), command.steering_rad, command.speed_mps});
  if (run_log_) ToRunLog([&] { run_log_->Poses(time_s, sim, command); });
}

void Recorder::MapCycle(double time_s, const Eigen::Isometry3d& T_W_O, const navigation::Navigator& navigator) {
  // The planner's calls of this cycle, placed in the world by the odometry's error now (the cycle
  // may have started a latency earlier: its frame L is placed through O, not through the vehicle).
  const Eigen::Isometry3d T_W_L = T_W_O * navigator.map_T_O_L();
  const auto& log = navigator.plan_log();
  if (run_log_ && plans_seen_ < log.size()) {
    const std::vector<navigation::PlanAttempt> attempts(log.begin() + static_cast<std::ptrdiff_t>(plans_seen_), log.end());
    ToRunLog([&] { run_log_->Plans(time_s, attempts, navigator); });
  }
  for (; plans_seen_ < log.size(); ++plans_seen_) {
    result_->plan_log.push_back({log[plans_seen_], T_W_L});
  }
  if (navigator.map_count() == maps_seen_) return;  // no new map this cycle
  maps_seen_ = navigator.map_count();
  const navigation::MapView view = navigator.map_backend().View();
  if (run_log_) ToRunLog([&] { run_log_->Map(time_s, navigator, view); });
  if (!view.points_L) return;
  const auto& pts = *view.points_L;
  // A map without flags (a user's backend may have none) is drawn as traversable.
  const auto traversable = [&view](std::size_t i) {
    return !view.traversable || i >= view.traversable->size() || (*view.traversable)[i] != 0;
  };
  map_points_.Add(pts, T_W_L, traversable, &result_->map_points);
  // What the robot saw around it (the map frame's origin is the sensor, near the vehicle).
  result_->last_map_points.clear();
  const double r2 = RunResult::kLastMapRadiusM * RunResult::kLastMapRadiusM;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (pts[i].head<2>().squaredNorm() <= r2) result_->last_map_points.push_back({T_W_L * pts[i], traversable(i)});
  }
  if (renderer_) {
    frame_points_L_ = pts;
    frame_traversable_.resize(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) frame_traversable_[i] = traversable(i) ? 1 : 0;
    frame_T_W_L_ = T_W_L;
  }
  const double period = scenario_.record.mesh_snapshot_period_s;
  if (!options_.out_dir.empty() && view.mesh_L && period > 0 && time_s + 1e-9 >= next_snapshot_s_) {
    next_snapshot_s_ += period;
    FreeSpaceMesh mesh_W = *view.mesh_L;
    for (Vec3& v : mesh_W.vertices) v = T_W_L * v;
    std::ostringstream name;
    name << "mesh_" << std::setw(3) << std::setfill('0') << snapshot_index_++ << "_t" << Fixed(time_s, 1) << ".ply";
    const std::string file = (std::filesystem::path(options_.out_dir) / name.str()).string();
    std::vector<Vec3> normals_W = view.normals_L ? *view.normals_L : std::vector<Vec3>{};
    for (Vec3& n : normals_W) n = T_W_L.linear() * n;
    try {
      WriteMeshPly(file, mesh_W, normals_W);
      result_->files.push_back(file);
    } catch (const std::exception& e) {
      Warn(e.what());  // a picture lost, not the run
    }
  }
}

void Recorder::Warn(const std::string& what) {
  constexpr int kMaxWarnings = 3;
  if (warnings_ < kMaxWarnings) std::fprintf(stderr, "ovpc: warning: %s (the run goes on)\n", what.c_str());
  if (++warnings_ == kMaxWarnings) std::fprintf(stderr, "ovpc: warning: further write failures of pictures are not shown\n");
}

void Recorder::Frame(double time_s, const sim::Simulator& sim, const navigation::Navigator& navigator) {
  if (!renderer_ || !(time_s + 1e-9 >= next_frame_s_)) return;
  next_frame_s_ += options_.frame_period_s;
  sim::Overlay overlay;
  for (std::size_t i = 0; i < frame_points_L_.size(); i += 2) {
    const bool trav = frame_traversable_[i] != 0;
    overlay.points.push_back({frame_T_W_L_ * frame_points_L_[i],
                              trav ? sim::Rgba{0.1f, 0.8f, 0.1f, 1.0f} : sim::Rgba{0.9f, 0.1f, 0.1f, 1.0f}});
  }
  if (navigator.has_path()) {
    sim::Overlay::Polyline line;
    const Eigen::Isometry3d T_W_O = sim.T_W_B() * sim.T_O_B().inverse();
    for (const auto& p : navigator.path_O().Poses()) line.vertices_W.push_back(T_W_O * Vec3(p.pose.x_m, p.pose.y_m, p.z_m + 0.1));
    overlay.polylines.push_back(line);
  }
  const sim::Image image = renderer_->Render(sim::ChaseCamera{}, overlay);
  std::ostringstream name;
  name << "frame_" << std::setw(5) << std::setfill('0') << static_cast<int>(std::lround(time_s * 100)) << ".png";
  const std::string file = (std::filesystem::path(options_.out_dir) / name.str()).string();
  try {
    sim::WritePng(image, file);
    result_->files.push_back(file);
  } catch (const std::exception& e) {
    Warn(e.what());
  }
}

}  // namespace ovpc::scenarios
