#include "run_log.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "foxglove_json.h"
#include "ovpc/scenarios/diagnosis.h"

namespace ovpc::scenarios {
namespace {

using foxglove::Entity;
using foxglove::Json;
using foxglove::Nanoseconds;

constexpr int kLogInfo = 2, kLogWarning = 3, kLogError = 4;
constexpr std::size_t kChunkBytes = std::size_t{4} << 20;

mcap::McapWriter::Options WriterOptions() {
  mcap::McapWriter::Options o;
  o.chunk_size = kChunkBytes;
  o.zstd_level = 3;
  o.library = "ovpc";
  return o;
}

// A triangle list of `faces` of `vertices` (only the vertices they use), in one colour, placed by `pose`.
std::string Triangles(const std::vector<Eigen::Vector3d>& vertices, const std::vector<Triangle>& faces,
                      const float (&rgba)[4], const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity()) {
  std::vector<int> remap(vertices.size(), -1);
  Json points, indices;
  int used = 0;
  for (const Triangle& f : faces) {
    for (const int v : f) {
      if (remap[v] < 0) {
        remap[v] = used++;
        points.Raw(used > 1 ? "," : "").Vec3(vertices[v], 2);  // centimetres: what a viewer shows
      }
      indices.Raw(indices.str().empty() ? "" : ",").Int(remap[v]);
    }
  }
  Json j;
  j.Raw("{\"pose\":").Pose(pose).Raw(",\"points\":[").Raw(points.str()).Raw("],\"color\":");
  j.Color(rgba[0], rgba[1], rgba[2], rgba[3]).Raw(",\"colors\":[],\"indices\":[").Raw(indices.str()).Raw("]}");
  return j.str();
}

// A shape of the world as a primitive: pose, size and colour.
std::string Shape(const Eigen::Isometry3d& T, const Eigen::Vector3d& size, bool cylinder) {
  Json j;
  j.Raw("{\"pose\":").Pose(T).Raw(",\"size\":").Vec3(size).Raw(",\"color\":").Color(0.55f, 0.45f, 0.35f, 1.0f);
  if (cylinder) j.Raw(",\"bottom_scale\":1,\"top_scale\":1");
  return j.Raw("}").str();
}

// The terrain as a triangle list on a grid of at most ~200 x 200 of its vertices.
std::string Terrain(const sim::Heightfield& h) {
  const int step = std::max(1, static_cast<int>(std::ceil(std::max(h.num_rows(), h.num_cols()) / 200.0)));
  std::vector<int> rows, cols;
  for (int r = 0; r < h.num_rows(); r += step) rows.push_back(r);
  if (rows.back() != h.num_rows() - 1) rows.push_back(h.num_rows() - 1);
  for (int c = 0; c < h.num_cols(); c += step) cols.push_back(c);
  if (cols.back() != h.num_cols() - 1) cols.push_back(h.num_cols() - 1);
  std::vector<Eigen::Vector3d> vertices;
  for (const int r : rows) {
    for (const int c : cols) vertices.push_back(h.Vertex(r, c));
  }
  std::vector<Triangle> faces;
  const int nc = static_cast<int>(cols.size());
  for (int i = 0; i + 1 < static_cast<int>(rows.size()); ++i) {
    for (int k = 0; k + 1 < nc; ++k) {
      const int a = i * nc + k, b = a + 1, c = a + nc, d = c + 1;
      faces.push_back({a, b, d});
      faces.push_back({a, d, c});
    }
  }
  static const float kGround[4] = {0.6f, 0.6f, 0.55f, 0.6f};
  return Triangles(vertices, faces, kGround);
}

std::string Arrow(const Eigen::Isometry3d& T, float r, float g, float b) {
  Json j;
  j.Raw("{\"pose\":").Pose(T).Raw(",\"shaft_length\":1.2,\"shaft_diameter\":0.15,\"head_length\":0.5,\"head_diameter\":0.4,");
  return j.Raw("\"color\":").Color(r, g, b, 1.0f).Raw("}").str();
}

Eigen::Isometry3d PlanarPose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

}  // namespace

RunLog::RunLog(const std::string& path, const Recording::Config& config, const sim::Simulator& sim)
    : config_(config), writer_(path, WriterOptions()) {
  tf_ = Channel("/tf", "foxglove.FrameTransform");
  pose_true_ = Channel("/pose/true", "foxglove.PoseInFrame");
  pose_odom_ = Channel("/pose/odometry", "foxglove.PoseInFrame");
  command_ = Channel("/command", "ovpc.Command");
  scan_ = Channel("/lidar/points", "foxglove.PointCloud");
  map_mesh_ = Channel("/map/mesh", "foxglove.SceneUpdate");
  map_points_ = Channel("/map/points", "foxglove.PointCloud");
  plan_ = Channel("/plan", "foxglove.SceneUpdate");
  world_ = Channel("/world", "foxglove.SceneUpdate");
  log_ = Channel("/log", "foxglove.Log");
  World(sim);
}

std::uint16_t RunLog::Channel(const std::string& topic, const std::string& schema) {
  auto it = std::find_if(schemas_.begin(), schemas_.end(), [&schema](const auto& s) { return s.first == schema; });
  if (it == schemas_.end()) {
    schemas_.emplace_back(schema, writer_.AddSchema(schema, "jsonschema", foxglove::JsonSchema(schema)));
    it = schemas_.end() - 1;
  }
  return writer_.AddChannel(it->second, topic, "json");
}

void RunLog::World(const sim::Simulator& sim) {
  Entity terrain{"world", "terrain", {}, {}, {}, {}, {}, {}, Terrain(sim.terrain())};
  Entity objects{"world", "objects", {}, {}, {}, {}, {}, {}, {}};
  for (const sim::Solid& s : sim.solids()) {
    const Eigen::Vector3d size = 2.0 * s.half_extents;
    std::string* list = s.shape == sim::Solid::Shape::kBox ? &objects.cubes
                        : s.shape == sim::Solid::Shape::kCylinder ? &objects.cylinders
                                                                  : &objects.spheres;
    if (!list->empty()) *list += ",";
    *list += Shape(s.T_W_X, size, s.shape == sim::Solid::Shape::kCylinder);
    objects.metadata.emplace_back(s.name, s.shape == sim::Solid::Shape::kBox ? "box" : s.shape == sim::Solid::Shape::kCylinder ? "cylinder" : "ellipsoid");
  }
  writer_.Write(world_, 0, foxglove::SceneUpdate(0, {terrain, objects}));
}

void RunLog::Poses(double time_s, const sim::Simulator& sim, const controller::Command& command) {
  const std::uint64_t ns = Nanoseconds(time_s);
  const Eigen::Isometry3d T_W_B = sim.T_W_B(), T_O_B = sim.T_O_B();
  writer_.Write(tf_, ns, foxglove::FrameTransform(ns, "world", "odom", T_W_B * T_O_B.inverse()));
  writer_.Write(tf_, ns, foxglove::FrameTransform(ns, "odom", "base", T_O_B));
  writer_.Write(tf_, ns, foxglove::FrameTransform(ns, "base", "lidar", T_W_B.inverse() * sim.T_W_S()));
  writer_.Write(pose_true_, ns, foxglove::PoseInFrame(ns, "world", T_W_B));
  // What the robot believes: its odometry pose, drawn in the world (O is W when the run starts).
  writer_.Write(pose_odom_, ns, foxglove::PoseInFrame(ns, "world", T_O_B));
  Json j;
  j.Raw("{\"timestamp\":").Time(ns).Raw(",\"steering_rad\":").Num(command.steering_rad, 5);
  writer_.Write(command_, ns, j.Raw(",\"speed_mps\":").Num(command.speed_mps, 5).Raw("}").str());
}

void RunLog::Scan(const sim::Simulator::SensorScan& scan) {
  if (scan.scan.time_s + 1e-9 < next_scan_s_) return;
  next_scan_s_ = scan.scan.time_s + config_.mcap_scan_period_s;
  const std::uint64_t ns = Nanoseconds(scan.scan.time_s);
  writer_.Write(scan_, ns, foxglove::PointCloud(ns, "odom", scan.scan.T_O_S, scan.scan.points_S));
}

void RunLog::Plans(double time_s, const std::vector<navigation::PlanAttempt>& attempts, const navigation::Navigator& navigator) {
  if (attempts.empty()) return;
  const std::uint64_t ns = Nanoseconds(time_s);
  const Eigen::Isometry3d& T_O_L = navigator.map_T_O_L();
  for (const navigation::PlanAttempt& a : attempts) {
    Entity goal{"odom", "local_goal", {{"reason", a.reason}, {"outcome", a.outcome}, {"iterations", std::to_string(a.iterations)}},
                {}, {}, {}, {}, {}, {}};
    if (a.has_goal) {
      const bool found = a.outcome == "found";
      goal.arrows = Arrow(T_O_L * PlanarPose(a.goal_L.x_m, a.goal_L.y_m, a.T_L_B.translation().z(), a.goal_L.yaw_rad),
                          found ? 0.1f : 0.9f, found ? 0.4f : 0.5f, found ? 0.9f : 0.1f);
    }
    std::ostringstream line;
    line << "plan at t=" << Json().Num(a.time_s, 2).str() << " s (" << a.reason << "): " << a.outcome;
    if (a.has_goal) line << ", goal progress " << Json().Num(a.goal_progress_m, 2).str() << " m";
    writer_.Write(log_, ns, foxglove::Log(ns, a.outcome == "found" ? kLogInfo : kLogWarning, "planner", line.str()));
    writer_.Write(plan_, ns, foxglove::SceneUpdate(ns, {goal}));
  }
  // The path the navigator follows after the cycle, in the odometry frame.
  Entity path{"odom", "path", {}, {}, {}, {}, {}, {}, {}};
  Json points;
  for (const planner::PathPose& p : navigator.path_O().Poses()) {
    points.Raw(points.str().empty() ? "" : ",").Vec3(Eigen::Vector3d(p.pose.x_m, p.pose.y_m, p.z_m + 0.1), 3);
  }
  Json line;
  line.Raw("{\"type\":0,\"pose\":").Pose(Eigen::Isometry3d::Identity()).Raw(",\"thickness\":0.08,\"scale_invariant\":false,");
  line.Raw("\"points\":[").Raw(points.str()).Raw("],\"color\":").Color(0.1f, 0.3f, 1.0f, 1.0f).Raw(",\"colors\":[],\"indices\":[]}");
  path.lines = line.str();
  writer_.Write(plan_, ns, foxglove::SceneUpdate(ns, {path}));
}

void RunLog::Map(double time_s, const navigation::Navigator& navigator, const navigation::MapView& view) {
  if (!view.points_L || time_s + 1e-9 < next_map_s_) return;
  next_map_s_ = time_s + config_.mcap_map_period_s;
  const std::uint64_t ns = Nanoseconds(time_s);
  const Eigen::Isometry3d& T_O_L = navigator.map_T_O_L();
  writer_.Write(map_points_, ns, foxglove::PointCloud(ns, "odom", T_O_L, *view.points_L, view.traversable, "traversable"));
  if (!view.mesh_L) return;
  const FreeSpaceMesh& mesh = *view.mesh_L;
  std::vector<Triangle> ok, blocked;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const bool trav = f < mesh.face_traversable.size() && mesh.face_traversable[f] != 0;
    (trav ? ok : blocked).push_back(mesh.triangles[f]);
  }
  static const float kTraversable[4] = {0.1f, 0.8f, 0.1f, 0.8f}, kBlocked[4] = {0.9f, 0.1f, 0.1f, 0.8f};
  Entity traversable{"odom", "traversable", {}, {}, {}, {}, {}, {}, {}};
  Entity non_traversable{"odom", "non_traversable", {}, {}, {}, {}, {}, {}, {}};
  // The faces are in frame L: the primitive's pose places them in O.
  if (!ok.empty()) traversable.triangles = Triangles(mesh.vertices, ok, kTraversable, T_O_L);
  if (!blocked.empty()) non_traversable.triangles = Triangles(mesh.vertices, blocked, kBlocked, T_O_L);
  writer_.Write(map_mesh_, ns, foxglove::SceneUpdate(ns, {traversable, non_traversable}));
}

void RunLog::Finish(const RunResult& result) {
  const std::uint64_t ns = Nanoseconds(result.sim_time_s);
  for (const CriterionResult& c : result.criteria) {
    const std::string line = c.name + ": expected " + c.expected + ", actual " + c.actual + (c.passed ? " (pass)" : " (FAIL)");
    writer_.Write(log_, ns, foxglove::Log(ns, c.passed ? kLogInfo : kLogError, "criteria", line));
  }
  const Diagnosis diagnosis = Diagnose(result);
  writer_.Write(log_, ns, foxglove::Log(ns, result.passed ? kLogInfo : kLogWarning, "diagnosis",
                                        result.end_reason + "; " + diagnosis.summary));
  writer_.Close();
}

}  // namespace ovpc::scenarios
