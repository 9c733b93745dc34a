// Uses the installed ovpc package (see CMakeLists.txt beside this file): one map update on a
// generated outdoor cloud, the planner's map written and read back as PLY, and one Navigator cycle
// on scans of a generated scene; built with OVPC_CONSUMER_BACKENDS, one more cycle with the OctoMap
// backend of the package's backends component. Exit 0 when every check holds, 1 otherwise, with one
// line per failed check.
//
//   ovpc_consumer OUT_DIR
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/io/cloud_io.h"
#include "ovpc/navigation/navigator.h"
#include "ovpc/synth/synthetic_scene.h"
#ifdef OVPC_CONSUMER_BACKENDS
#include "ovpc/backends/map_selection.h"
#endif

namespace {

int failures = 0;

void Check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "ovpc_consumer: FAILED: %s\n", what.c_str());
    ++failures;
  }
}

// One Navigator cycle (buffer, map, local goal, plan) on 25 scans of a vehicle standing on flat
// ground with a post ahead, with the map backend in `plugins` (the default when null).
void CheckNavigatorCycle(ovpc::navigation::Navigator::Plugins plugins, const std::string& backend) {
  ovpc::synth::Scene scene;
  scene.cylinders.push_back({ovpc::Vec3(9.0, 3.0, 0.0), 0.2, 2.0});
  const Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  ovpc::navigation::Navigator::Config config;
  config.ovpc.mapper.traversability.noise_floor_m = 0.05;
  config.ovpc.map.normal_neighbours = 32;
  config.planner.vehicle.footprint_check = ovpc::planner::VehicleBox::FootprintCheck::kWheels;
  config.planner.range_m = 1.0;
  ovpc::navigation::Navigator navigator(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  Check(navigator.map_backend().name() == backend, "the navigator maps with " + backend);
  for (ovpc::Scan& scan : ovpc::synth::SimulateScans(scene, ovpc::SpinningLidarMount{}, T_O_B, 0.0, 25, 0.01, 1)) {
    navigator.AddScan(std::move(scan));
  }
  Check(navigator.Update(0.2, T_O_B), "a map cycle runs at 1 / map_rate_hz");
  Check(navigator.map() != nullptr, "the navigator made a map (" + backend + ")");
  Check(navigator.has_path(), "the navigator planned a path (" + backend + ")");
  const ovpc::controller::Command command = navigator.Control(0.2, T_O_B, 0.0);
  Check(!command.done && command.speed_mps >= 0.0, "the navigator commands the vehicle forward (" + backend + ")");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: ovpc_consumer OUT_DIR\n");
    return 2;
  }
  const std::string out_dir = argv[1];
  try {
    // The mapping pipeline: a cloud in the sensor's local frame, viewpoint at the origin.
    const ovpc::Points cloud = ovpc::synth::MakeOutdoorCloud(6000, 1);
    const ovpc::OvpcMapper mapper;
    const ovpc::OvpcMap map = mapper.Update(cloud, ovpc::Vec3::Zero());
    if (!map.ok()) {
      std::fprintf(stderr, "ovpc_consumer: FAILED: map update: %s\n", map.message.c_str());
      return 1;
    }
    Check(ovpc::CheckTopology(map.mesh.triangles).watertight(), "the free-space mesh is watertight");
    const auto& traversable = map.cloud.traversable();
    const auto num_traversable = std::count(traversable.begin(), traversable.end(), 1);
    Check(num_traversable > 0, "some map points are traversable");
    Check(num_traversable < static_cast<long>(map.cloud.size()), "some map points are not traversable");

    // Files: the planner's map as PLY, read back.
    const std::string points_file = out_dir + "/map_points.ply";
    ovpc::WriteTraversabilityCloudPly(points_file, map.cloud);
    Check(ovpc::ReadCloud(points_file).size() == map.cloud.size(), "the map's PLY reads back whole");

    // Navigation with the default map backend, OVPC's.
    CheckNavigatorCycle({}, "ovpc");
#ifdef OVPC_CONSUMER_BACKENDS
    ovpc::backends::MapSelection selection;
    selection.map = ovpc::backends::MapSelection::Kind::kOctoMap;
    ovpc::navigation::Navigator::Plugins plugins;
    plugins.map = ovpc::backends::MakeMapBackend(selection, ovpc::Traversability::Config{});
    CheckNavigatorCycle(std::move(plugins), "octomap");
#endif

    std::printf("ovpc_consumer: %zu points in, mesh of %zu faces, %ld of %zu map points traversable\n",
                cloud.size(), map.mesh.triangles.size(), static_cast<long>(num_traversable),
                map.cloud.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc_consumer: FAILED: %s\n", e.what());
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
