// Uses the installed ovpc package (see CMakeLists.txt beside this file): one map update on a
// generated outdoor cloud, the planner's map written and read back as PLY. Exit 0 when every
// check holds, 1 otherwise, with one line per failed check.
//
//   ovpc_consumer OUT_DIR
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/io/cloud_io.h"
#include "ovpc/synth/synthetic_scene.h"

namespace {

int failures = 0;

void Check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "ovpc_consumer: FAILED: %s\n", what.c_str());
    ++failures;
  }
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

    // Navigation (ovpc::navigation): one Navigator cycle on this map goes here.

    std::printf("ovpc_consumer: %zu points in, mesh of %zu faces, %ld of %zu map points traversable\n",
                cloud.size(), map.mesh.triangles.size(), static_cast<long>(num_traversable),
                map.cloud.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc_consumer: FAILED: %s\n", e.what());
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
