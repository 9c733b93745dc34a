#include "ovpc/sim/ray_caster.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace ovpc::sim {
namespace {

constexpr int kMinSegments = 8;
constexpr int kMaxSegments = 512;

/// Segments of a circle of `radius_m` so that the chord stays within `tol_m` of the arc.
int SegmentsFor(double radius_m, double tol_m) {
  if (radius_m <= tol_m) return kMinSegments;
  const double half_angle = std::acos(1.0 - tol_m / radius_m);
  const int n = static_cast<int>(std::ceil(kPi / half_angle));
  return std::clamp(n, kMinSegments, kMaxSegments);
}

void AddBox(const Solid& solid, TriangleMesh* mesh) {
  const int base = static_cast<int>(mesh->vertices.size());
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner_X((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
    mesh->vertices.push_back(solid.T_W_X * corner_X.cwiseProduct(solid.half_extents));
  }
  // Two triangles per face, outward winding.
  static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : kFaces) {
    mesh->triangles.push_back({base + f[0], base + f[1], base + f[2]});
    mesh->triangles.push_back({base + f[0], base + f[2], base + f[3]});
  }
}

void AddCylinder(const Solid& solid, double tol_m, TriangleMesh* mesh) {
  const double radius = solid.half_extents.x();
  const double half_h = solid.half_extents.z();
  const int n = SegmentsFor(radius, tol_m);
  const int base = static_cast<int>(mesh->vertices.size());
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    const double x = radius * std::cos(a);
    const double y = radius * std::sin(a);
    mesh->vertices.push_back(solid.T_W_X * Vec3(x, y, -half_h));
    mesh->vertices.push_back(solid.T_W_X * Vec3(x, y, half_h));
  }
  const int bottom_centre = static_cast<int>(mesh->vertices.size());
  mesh->vertices.push_back(solid.T_W_X * Vec3(0.0, 0.0, -half_h));
  mesh->vertices.push_back(solid.T_W_X * Vec3(0.0, 0.0, half_h));
  const int top_centre = bottom_centre + 1;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const int b0 = base + 2 * i;
    const int t0 = b0 + 1;
    const int b1 = base + 2 * j;
    const int t1 = b1 + 1;
    mesh->triangles.push_back({b0, b1, t1});
    mesh->triangles.push_back({b0, t1, t0});
    mesh->triangles.push_back({bottom_centre, b1, b0});
    mesh->triangles.push_back({top_centre, t0, t1});
  }
}

void AddEllipsoid(const Solid& solid, double tol_m, TriangleMesh* mesh) {
  const Vec3& radii = solid.half_extents;
  // Half the tolerance each way: a quad's centre deviates in both directions.
  const int n_lon = SegmentsFor(radii.maxCoeff(), 0.5 * tol_m);
  const int n_lat = std::max(4, n_lon / 2);
  const int base = static_cast<int>(mesh->vertices.size());
  // Rings between the poles, then the two poles.
  for (int i = 1; i < n_lat; ++i) {
    const double polar = kPi * i / n_lat;
    for (int j = 0; j < n_lon; ++j) {
      const double az = 2.0 * kPi * j / n_lon;
      const Vec3 unit(std::sin(polar) * std::cos(az), std::sin(polar) * std::sin(az),
                      std::cos(polar));
      mesh->vertices.push_back(solid.T_W_X * unit.cwiseProduct(radii));
    }
  }
  const int north = static_cast<int>(mesh->vertices.size());
  mesh->vertices.push_back(solid.T_W_X * Vec3(0.0, 0.0, radii.z()));
  mesh->vertices.push_back(solid.T_W_X * Vec3(0.0, 0.0, -radii.z()));
  const int south = north + 1;
  auto ring = [&](int i, int j) { return base + (i - 1) * n_lon + (j % n_lon); };
  for (int j = 0; j < n_lon; ++j) {
    mesh->triangles.push_back({north, ring(1, j), ring(1, j + 1)});
    mesh->triangles.push_back({south, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)});
    for (int i = 1; i + 1 < n_lat; ++i) {
      mesh->triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      mesh->triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
}

[[noreturn]] void ThrowEmbree(RTCDevice device, const char* what) {
  const RTCError error = device != nullptr ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(std::string("Embree: ") + what + " (error " +
                           std::to_string(static_cast<int>(error)) + ")");
}

}  // namespace

void RayCaster::Config::Validate() const {
  if (!(max_chord_error_m > 0.0) || !std::isfinite(max_chord_error_m)) {
    throw std::invalid_argument("RayCaster::Config::max_chord_error_m must be > 0");
  }
  if (build_threads < 1) throw std::invalid_argument("RayCaster::Config::build_threads must be >= 1");
}

TriangleMesh TessellateSolid(const Solid& solid, double max_chord_error_m) {
  TriangleMesh mesh;
  switch (solid.shape) {
    case Solid::Shape::kBox:
      AddBox(solid, &mesh);
      break;
    case Solid::Shape::kCylinder:
      AddCylinder(solid, max_chord_error_m, &mesh);
      break;
    case Solid::Shape::kEllipsoid:
      AddEllipsoid(solid, max_chord_error_m, &mesh);
      break;
  }
  return mesh;
}

TriangleMesh TessellateTerrain(const Heightfield& terrain) {
  TriangleMesh mesh;
  const int rows = terrain.num_rows();
  const int cols = terrain.num_cols();
  mesh.vertices.reserve(static_cast<std::size_t>(rows) * cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) mesh.vertices.push_back(terrain.Vertex(r, c));
  }
  mesh.triangles.reserve(2 * static_cast<std::size_t>(rows - 1) * (cols - 1));
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      const int a = r * cols + c;  // (r, c)
      const int b = a + 1;         // (r, c + 1)
      const int cc = a + cols;     // (r + 1, c)
      const int d = cc + 1;        // (r + 1, c + 1)
      // Split along (r, c)-(r + 1, c + 1), like MuJoCo's heightfield prisms; upward winding.
      mesh.triangles.push_back({a, b, d});
      mesh.triangles.push_back({a, d, cc});
    }
  }
  return mesh;
}

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::size_t num_triangles = 0;
  /// Embree geometry id -> Hit::surface.
  std::vector<int> surface_of_geometry;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void Add(const TriangleMesh& mesh, int surface) {
    if (mesh.triangles.empty()) return;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (geometry == nullptr) ThrowEmbree(device, "rtcNewGeometry failed");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh.triangles.size()));
    if (vertices == nullptr || indices == nullptr) {
      rtcReleaseGeometry(geometry);
      ThrowEmbree(device, "buffer allocation failed");
    }
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
    }
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    if (surface_of_geometry.size() <= id) surface_of_geometry.resize(id + 1, Hit::kNone);
    surface_of_geometry[id] = surface;
    num_triangles += mesh.triangles.size();
  }
};

RayCaster::RayCaster(const Heightfield& terrain, const std::vector<Solid>& solids,
                     const Config& config)
    : impl_(std::make_unique<Impl>()) {
  config.Validate();
  const std::string device_config = "threads=" + std::to_string(config.build_threads) + ",verbose=0";
  impl_->device = rtcNewDevice(device_config.c_str());
  if (impl_->device == nullptr) ThrowEmbree(nullptr, "rtcNewDevice failed");
  impl_->scene = rtcNewScene(impl_->device);
  if (impl_->scene == nullptr) ThrowEmbree(impl_->device, "rtcNewScene failed");
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  // Watertight triangle tests: no ray slips between two terrain triangles.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  impl_->Add(TessellateTerrain(terrain), Hit::kTerrain);
  for (std::size_t i = 0; i < solids.size(); ++i) {
    impl_->Add(TessellateSolid(solids[i], config.max_chord_error_m), static_cast<int>(i));
  }
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) {
    ThrowEmbree(impl_->device, "building the scene failed");
  }
}

RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

std::size_t RayCaster::num_triangles() const { return impl_->num_triangles; }

RayCaster::Hit RayCaster::Cast(const Vec3& origin, const Vec3& direction,
                               double max_range_m) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  query.ray.org_x = static_cast<float>(origin.x());
  query.ray.org_y = static_cast<float>(origin.y());
  query.ray.org_z = static_cast<float>(origin.z());
  query.ray.dir_x = static_cast<float>(direction.x());
  query.ray.dir_y = static_cast<float>(direction.y());
  query.ray.dir_z = static_cast<float>(direction.z());
  query.ray.tnear = 0.0f;
  query.ray.tfar = static_cast<float>(max_range_m);
  query.ray.time = 0.0f;
  query.ray.mask = 0xFFFFFFFFu;
  query.ray.id = 0;
  query.ray.flags = 0;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &query);
  Hit hit;
  if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    hit.range_m = query.ray.tfar;
    hit.surface = impl_->surface_of_geometry[query.hit.geomID];
  }
  return hit;
}

void RayCaster::CastFan(const Vec3& origin, const Vec3* directions, int count, double max_range_m,
                        Hit* hits) const {
  if (count < 0 || count > kFanSize) {
    throw std::invalid_argument("RayCaster::CastFan: count must be in [0, kFanSize]");
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) int valid[kFanSize];
  alignas(64) RTCRayHit16 query;
  const auto ox = static_cast<float>(origin.x());
  const auto oy = static_cast<float>(origin.y());
  const auto oz = static_cast<float>(origin.z());
  for (int i = 0; i < kFanSize; ++i) {
    const bool active = i < count;
    valid[i] = active ? -1 : 0;
    query.ray.org_x[i] = ox;
    query.ray.org_y[i] = oy;
    query.ray.org_z[i] = oz;
    query.ray.dir_x[i] = active ? static_cast<float>(directions[i].x()) : 0.0f;
    query.ray.dir_y[i] = active ? static_cast<float>(directions[i].y()) : 0.0f;
    query.ray.dir_z[i] = active ? static_cast<float>(directions[i].z()) : 1.0f;
    query.ray.tnear[i] = 0.0f;
    query.ray.tfar[i] = static_cast<float>(max_range_m);
    query.ray.time[i] = 0.0f;
    query.ray.mask[i] = 0xFFFFFFFFu;
    query.ray.id[i] = static_cast<unsigned>(i);
    query.ray.flags[i] = 0;
    query.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, impl_->scene, &context, &query);
  for (int i = 0; i < count; ++i) {
    Hit hit;
    if (query.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID) {
      hit.range_m = query.ray.tfar[i];
      hit.surface = impl_->surface_of_geometry[query.hit.geomID[i]];
    }
    hits[i] = hit;
  }
}

}  // namespace ovpc::sim
