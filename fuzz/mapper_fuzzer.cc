// libFuzzer harness for the map update (core/): OvpcMapper::Update and the voxel filter on small
// arbitrary clouds. Byte 0 chooses the decoding and the configuration:
//   bit 0     points: raw float32 x, y, z (0) or one byte per coordinate (1) from a small table of
//             grid values and special ones (NaN, +-inf, 1e30, 1e300, ...), which makes duplicate,
//             collinear, coplanar and huge points common
//   bit 1     kernel: exponential (0) or linear (1)
//   bits 2-3  gamma: the default (0), or one of a table of valid extreme values
//   bit 4     CGAL's reference hull instead of the project's incremental one
//   bit 5     viewpoint: the origin (0) or the first decoded point (1)
//   bits 6-7  voxel size for the voxel filter run on the same points
// The mapper never throws on data and always returns a status; when it says kOk the mesh must be
// closed (every edge in two faces) with finite vertices, one planner point per visible vertex.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/point_cloud_buffer.h"

namespace {

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "mapper_fuzzer: %s\n", what.c_str());
  std::abort();
}

constexpr std::size_t kMaxPoints = 400;

double TableValue(std::uint8_t b) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kSpecial[16] = {std::numeric_limits<double>::quiet_NaN(), kInf, -kInf, 1e30, -1e30, 1e300, -1e300,
                                   1e-30, 1e-3, 1e-6, 3.4e38, 1e154, 1e-154, 0.1, 1e7, -1e7};
  if (b >= 240) return kSpecial[b - 240];
  return (static_cast<int>(b) - 120) * 0.25;  // a grid of 0.25 m from -30 m to 29.75 m
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t mode = data[0];
  ++data, --size;

  ovpc::Points points;
  if ((mode & 1) == 0) {
    for (std::size_t i = 0; i + 12 <= size && points.size() < kMaxPoints; i += 12) {
      float v[3];
      std::memcpy(v, data + i, sizeof(v));
      points.emplace_back(v[0], v[1], v[2]);
    }
  } else {
    for (std::size_t i = 0; i + 3 <= size && points.size() < kMaxPoints; i += 3) {
      points.emplace_back(TableValue(data[i]), TableValue(data[i + 1]), TableValue(data[i + 2]));
    }
  }

  ovpc::OvpcMapper::Config config;
  const bool linear = (mode & 2) != 0;
  config.ghpr.kernel = linear ? ovpc::GhprKernel::kLinear : ovpc::GhprKernel::kExponential;
  constexpr double kExponentialGamma[4] = {-0.03, -1.0, -1e-12, -0.5};
  constexpr double kLinearGamma[4] = {100.0, 1e7, 1e-9, 50.0};
  config.ghpr.gamma = (linear ? kLinearGamma : kExponentialGamma)[(mode >> 2) & 3];
  config.ghpr.reference_hull = (mode & 16) != 0;
  const ovpc::Vec3 viewpoint = (mode & 32) != 0 && !points.empty() ? points.front() : ovpc::Vec3::Zero();

  const ovpc::OvpcMapper mapper(config);
  const ovpc::OvpcMap map = mapper.Update(points, viewpoint);
  if (map.input.input != points.size()) Finding("input count differs from the points given");
  if (!viewpoint.allFinite()) {
    // Refused before any point is looked at.
    if (map.status != ovpc::GhprStatus::kDegenerate) Finding("a non-finite viewpoint was not refused");
  } else if (map.input.non_finite + map.input.at_viewpoint + map.input.too_far + map.input.used != map.input.input) {
    Finding("input counts do not add up");
  }
  if (map.ok()) {
    const ovpc::FreeSpaceMesh& mesh = map.mesh;
    if (mesh.vertices.size() < 4 || mesh.triangles.size() < 4) Finding("kOk with fewer than 4 vertices or faces");
    for (const ovpc::Vec3& v : mesh.vertices) {
      if (!v.allFinite()) Finding("kOk mesh with a non-finite vertex");
    }
    for (const ovpc::Triangle& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) {
        if (t[k] < 0 || static_cast<std::size_t>(t[k]) >= mesh.vertices.size()) Finding("face index out of range");
      }
    }
    if (!ovpc::CheckTopology(mesh.triangles).every_edge_in_two_faces) Finding("kOk mesh is not closed");
    if (map.cloud.size() != mesh.num_visible()) Finding("planner points differ from visible vertices");
  } else if (!map.mesh.triangles.empty() || !map.cloud.empty()) {
    Finding("a failed update left a mesh or a map");
  }

  // The voxel filter on the finite points, as the buffer calls it.
  constexpr double kVoxel[4] = {0.1, 1e-9, 1e-300, 0.0};
  ovpc::Points finite;
  for (const ovpc::Vec3& p : points) {
    if (p.allFinite()) finite.push_back(p);
  }
  ovpc::BufferStats stats;
  const ovpc::Points voxels = ovpc::VoxelFilter(finite, kVoxel[(mode >> 6) & 3], 1, &stats);
  if (voxels.size() > finite.size()) Finding("the voxel filter made points");
  for (const ovpc::Vec3& v : voxels) {
    if (!v.allFinite()) Finding("the voxel filter made a non-finite centroid");
  }
  return 0;
}
