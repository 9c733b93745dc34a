// `ovpc mesh`: one OVPC map update on a point cloud file.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "ovpc/io/cloud_io.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/point_cloud_buffer.h"

namespace ovpc::apps {
namespace {

struct MeshOptions {
  std::string cloud_path;
  std::string viewpoint;
  std::string kernel = "exponential";
  double gamma = 0.0;
  double alpha_max_deg = 30.0;
  double dh_max_m = 0.25;
  double voxel_m = 0.0;
  int min_hits = 0;
  long long max_points = 0;
  int bin_fields = 4;
  double min_range_m = OvpcMapper::Config{}.min_range_m;
  std::string out_mesh;
  std::string out_points;
  std::string out_json;
  bool quiet = false;
  CLI::Option* gamma_opt = nullptr;
  CLI::Option* voxel_opt = nullptr;
  CLI::Option* min_hits_opt = nullptr;
};

Vec3 ParseVector(const std::string& text, const std::string& name) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
      values.push_back(v);
    } catch (const std::exception&) {
      throw BadInput(name + " must be x,y,z with three finite numbers, got '" + text + "'");
    }
  }
  if (values.size() != 3) throw BadInput(name + " must be x,y,z with three finite numbers, got '" + text + "'");
  return Vec3(values[0], values[1], values[2]);
}

// Creates the parent folder of an output file so that `--out out/mesh.ply` works on a fresh clone.
void MakeParentDir(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
}

double Round3(double v) { return std::round(v * 1000.0) / 1000.0; }

// What one `ovpc mesh` computed: the cloud before and after the buffer stage, and the map.
struct MeshRun {
  Vec3 viewpoint;
  OvpcMapper::Config config;
  Points raw, points;
  bool buffer = false;
  BufferStats buffer_stats;
  std::size_t non_finite_before_buffer = 0;
  OvpcMap map;
  MeshTopology topo;
  double face_fraction = 0.0, point_fraction = 0.0;
  std::size_t non_finite() const { return map.input.non_finite + non_finite_before_buffer; }
};

OvpcMapper::Config MapperConfig(const MeshOptions& o) {
  OvpcMapper::Config config;
  try {
    config.ghpr.kernel = ParseKernel(o.kernel);
  } catch (const std::invalid_argument& e) {
    throw BadInput(std::string("--kernel: ") + e.what());
  }
  config.traversability.alpha_max_rad = DegToRad(o.alpha_max_deg);
  config.traversability.delta_h_max_m = o.dh_max_m;
  if (o.max_points < 0) throw BadInput("--max-points must be >= 0, got " + std::to_string(o.max_points));
  if (o.bin_fields != 4 && o.bin_fields != 5) throw BadInput("--bin-fields must be 4 or 5");
  if (!(o.min_range_m >= 1e-5) || !(o.min_range_m <= 1e3)) throw BadInput("--min-range must be in [1e-5, 1000] m");
  config.min_range_m = o.min_range_m;
  return config;
}

// Optional buffer stage: drop NaN/inf, voxel filter with a hit threshold, subsample.
void BufferStage(const MeshOptions& o, MeshRun* run) {
  run->points = run->raw;
  run->buffer = o.voxel_opt->count() > 0 || o.min_hits_opt->count() > 0 || o.max_points > 0;
  if (!run->buffer) return;
  Points finite;
  finite.reserve(run->raw.size());
  for (const Vec3& p : run->raw) {
    if (p.allFinite()) finite.push_back(p); else ++run->non_finite_before_buffer;
  }
  const double voxel = o.voxel_opt->count() > 0 ? o.voxel_m : PointCloudBuffer::Config{}.voxel_size_m;
  const int min_hits = o.min_hits_opt->count() > 0 ? o.min_hits : PointCloudBuffer::Config{}.min_hits;
  if (min_hits < 1) throw BadInput("--min-hits must be >= 1");
  if (!(voxel >= 0.0)) throw BadInput("--voxel must be >= 0 (0 disables the voxel filter)");
  run->points = VoxelFilter(finite, voxel, min_hits, &run->buffer_stats);
  if (o.max_points > 0) run->points = Subsample(run->points, static_cast<std::size_t>(o.max_points), 1, &run->buffer_stats);
}

// Gamma: the paper's -0.03 for the exponential kernel; 100 x the cloud's extent for the linear one.
double DefaultGamma(const MeshRun& run) {
  if (run.config.ghpr.kernel == GhprKernel::kExponential) return -0.03;
  double max_d = 0.0;
  for (const Vec3& p : run.points) {
    if (p.allFinite()) max_d = std::max(max_d, (p - run.viewpoint).norm());
  }
  return 100.0 * std::max(max_d, 1.0);
}

// Reads the cloud, runs the buffer stage and the mapper; bad input as BadInput.
MeshRun Compute(const MeshOptions& o) {
  MeshRun run;
  run.viewpoint = ParseVector(o.viewpoint, "--viewpoint");
  run.config = MapperConfig(o);
  try {
    run.raw = ReadCloud(o.cloud_path, CloudFormat::kAuto, o.bin_fields);
  } catch (const CloudIoError& e) {
    throw BadInput(e.what());
  }
  BufferStage(o, &run);
  run.config.ghpr.gamma = o.gamma_opt->count() == 0 ? DefaultGamma(run) : o.gamma;
  try {
    run.config.Validate();
  } catch (const std::invalid_argument& e) {
    throw BadInput(e.what());
  }
  run.map = OvpcMapper(run.config).Update(run.points, run.viewpoint);
  if (!run.map.ok()) {
    std::ostringstream msg;
    msg << o.cloud_path << ": " << run.map.message;
    if (run.map.input.non_finite + run.map.input.at_viewpoint + run.map.input.too_far > 0) {
      msg << " (" << run.non_finite() << " NaN/inf, " << run.map.input.at_viewpoint << " viewpoint and "
          << run.map.input.too_far << " beyond 1e12 m points dropped)";
    }
    throw BadInput(msg.str());
  }
  run.topo = CheckTopology(run.map.mesh.triangles);
  std::size_t trav_faces = 0, trav_points = 0;
  for (auto t : run.map.mesh.face_traversable) trav_faces += t;
  for (auto t : run.map.cloud.traversable()) trav_points += t;
  run.face_fraction = run.map.mesh.triangles.empty() ? 0.0 : double(trav_faces) / run.map.mesh.triangles.size();
  run.point_fraction = run.map.cloud.empty() ? 0.0 : double(trav_points) / run.map.cloud.size();
  return run;
}

void PrintSummary(const MeshOptions& o, const MeshRun& run) {
  const OvpcMap& map = run.map;
  std::printf("cloud              %s\n", o.cloud_path.c_str());
  std::printf("input points       %zu\n", run.raw.size());
  std::printf("dropped            %zu NaN/inf, %zu at the viewpoint, %zu beyond 1e12 m\n", run.non_finite(),
              map.input.at_viewpoint, map.input.too_far);
  if (run.buffer) {
    std::printf("buffer stage       %zu voxels kept, %zu points in sparse voxels dropped, %zu subsampled out\n",
                run.buffer_stats.voxels_kept, run.buffer_stats.voxel_sparse, run.buffer_stats.subsampled_out);
  }
  std::printf("points used        %zu\n", map.input.used);
  std::printf("visible points     %zu (%.1f %%)\n", map.cloud.size(), 100.0 * map.cloud.size() / std::max<std::size_t>(1, map.input.used));
  std::printf("faces              %zu (%s kernel, gamma %g; viewpoint %s the hull)\n", map.mesh.triangles.size(),
              KernelName(run.config.ghpr.kernel), run.config.ghpr.gamma, map.mesh.viewpoint_vertex >= 0 ? "on" : "inside");
  std::printf("watertight         %s (V %zu, E %zu, F %zu, chi %d)\n", run.topo.watertight() ? "yes" : "NO",
              run.topo.num_vertices, run.topo.num_edges, run.topo.num_faces, run.topo.euler_characteristic);
  std::printf("enclosed volume    %.1f m^3\n", EnclosedVolume(map.mesh.vertices, map.mesh.triangles));
  std::printf("traversable        %.1f %% of faces, %.1f %% of points\n", 100.0 * run.face_fraction, 100.0 * run.point_fraction);
  const StageTimings& t = map.timings;
  std::printf("time [ms]          total %.2f = sanitize %.2f + transform %.2f + hull %.2f + mesh %.2f + "
              "traversability %.2f + vertex cloud %.2f\n",
              t.total_ms, t.sanitize_ms, t.transform_ms, t.hull_ms, t.mesh_ms, t.traversability_ms, t.vertex_cloud_ms);
}

nlohmann::json StatsJson(const MeshOptions& o, const MeshRun& run) {
  const OvpcMap& map = run.map;
  const StageTimings& t = map.timings;
  nlohmann::json j = {
      {"cloud", o.cloud_path},
      {"viewpoint", {run.viewpoint.x(), run.viewpoint.y(), run.viewpoint.z()}},
      {"kernel", KernelName(run.config.ghpr.kernel)},
      {"gamma", run.config.ghpr.gamma},
      {"alpha_max_deg", o.alpha_max_deg},
      {"dh_max_m", o.dh_max_m},
      {"input_points", run.raw.size()},
      {"dropped_non_finite", run.non_finite()},
      {"dropped_at_viewpoint", map.input.at_viewpoint},
      {"dropped_too_far", map.input.too_far},
      {"points_after_filtering", map.input.used},
      {"visible_points", map.cloud.size()},
      {"faces", map.mesh.triangles.size()},
      {"viewpoint_on_hull", map.mesh.viewpoint_vertex >= 0},
      {"watertight", run.topo.watertight()},
      {"euler_characteristic", run.topo.euler_characteristic},
      {"enclosed_volume_m3", EnclosedVolume(map.mesh.vertices, map.mesh.triangles)},
      {"traversable_face_fraction", run.face_fraction},
      {"traversable_point_fraction", run.point_fraction},
      {"ms", {{"sanitize", Round3(t.sanitize_ms)}, {"transform", Round3(t.transform_ms)},
              {"hull", Round3(t.hull_ms)}, {"mesh", Round3(t.mesh_ms)},
              {"traversability", Round3(t.traversability_ms)}, {"vertex_cloud", Round3(t.vertex_cloud_ms)},
              {"total", Round3(t.total_ms)}}},
  };
  if (run.buffer) {
    j["buffer"] = {{"voxels_kept", run.buffer_stats.voxels_kept},
                   {"dropped_sparse_voxels", run.buffer_stats.voxel_sparse},
                   {"subsampled_out", run.buffer_stats.subsampled_out}};
  }
  return j;
}

int RunMesh(const MeshOptions& o) {
  const MeshRun run = Compute(o);
  if (!o.quiet) PrintSummary(o, run);
  for (const std::string* out : {&o.out_mesh, &o.out_points, &o.out_json}) {
    if (!out->empty()) MakeParentDir(*out);
  }
  if (!o.out_mesh.empty()) {
    WriteMeshPly(o.out_mesh, run.map.mesh, run.map.cloud.normals());
    if (!o.quiet) std::printf("wrote mesh         %s\n", o.out_mesh.c_str());
  }
  if (!o.out_points.empty()) {
    WriteTraversabilityCloudPly(o.out_points, run.map.cloud);
    if (!o.quiet) std::printf("wrote points       %s\n", o.out_points.c_str());
  }
  if (!o.out_json.empty()) {
    std::ofstream out(o.out_json);
    if (!out) throw CloudIoError(o.out_json + ": cannot open for writing");
    out << StatsJson(o, run).dump(2) << "\n";
    if (!out) throw CloudIoError(o.out_json + ": write failed");
    if (!o.quiet) std::printf("wrote stats        %s\n", o.out_json.c_str());
  }
  return run.topo.watertight() ? kExitOk : kExitFailure;
}

}  // namespace

Runner RegisterMesh(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  CLI::App* cmd = app.add_subcommand("mesh", "Build the OVPC free-space mesh and the planner's vertex cloud from one point cloud");
  cmd->footer(
      "The cloud's z axis must point up (gravity). NaN/inf points and points closer than 1 mm to the\n"
      "viewpoint are dropped and counted in the summary and the JSON. Without --voxel/--min-hits/--max-points\n"
      "the cloud is used as given; with any of them the buffer stage filters it first (voxel 0.1 m,\n"
      "min hits 2 unless set). Exit codes: 0 ok, 1 the mesh failed its watertight check or an output\n"
      "could not be written, 2 bad input (missing/unreadable file, unknown or malformed format, fewer\n"
      "than 4 usable points, points coplanar with the viewpoint, gamma of the wrong sign for the kernel).");
  cmd->add_option("cloud", o->cloud_path, "Point cloud: .ply (ascii/binary), .pcd (ascii/binary), .bin (KITTI float32 x,y,z,i), .xyz")
      ->required();
  cmd->add_option("--viewpoint", o->viewpoint, "Sensor position x,y,z in the cloud's frame (metres)")->required();
  cmd->add_option("--kernel", o->kernel, "GHPR kernel: exponential (d^gamma) or linear (gamma - d)")
      ->capture_default_str();
  o->gamma_opt = cmd->add_option("--gamma", o->gamma,
                                 "Kernel parameter: in [-1, 0) for exponential (default -0.03, paper); above the max "
                                 "distance and at most 1e7 for linear (default 100 x the farthest point's distance)");
  cmd->add_option("--alpha-max", o->alpha_max_deg, "Max surface angle of a traversable face, degrees")->capture_default_str();
  cmd->add_option("--dh-max", o->dh_max_m, "Max height spread of a traversable face, metres")->capture_default_str();
  o->voxel_opt = cmd->add_option("--voxel", o->voxel_m, "Buffer stage: voxel edge in metres (0 disables)");
  o->min_hits_opt = cmd->add_option("--min-hits", o->min_hits, "Buffer stage: keep voxels with at least this many points");
  cmd->add_option("--max-points", o->max_points, "Buffer stage: subsample to at most this many points (0 = keep all)");
  cmd->add_option("--bin-fields", o->bin_fields, ".bin records: 4 float32 (KITTI x,y,z,i) or 5 (nuScenes x,y,z,i,ring)")
      ->capture_default_str();
  cmd->add_option("--min-range", o->min_range_m, "Drop points closer than this to the viewpoint, metres (self hits)")
      ->capture_default_str();
  cmd->add_option("--out", o->out_mesh, "Write the mesh as PLY (face colours: green traversable, red not)");
  cmd->add_option("--points", o->out_points, "Write the vertex cloud as PLY (normals, traversable flag)");
  cmd->add_option("--json", o->out_json, "Write statistics and per-stage milliseconds as JSON");
  cmd->add_flag("-q,--quiet", o->quiet, "Print nothing but errors");
  return [o]() { return RunMesh(*o); };
}

}  // namespace ovpc::apps
