#include "ovpc/navigation/ovpc_map_backend.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "ovpc/core/internal/clock.h"

namespace ovpc::navigation {
namespace {

using ovpc::internal::Clock;
using ovpc::internal::MsSince;

// Ground is remembered within this radius of the sensor: the ring the sensor never sees around its
// mast, and the ground the vehicle may turn over next, lie well within it.
constexpr double kMemoryRadiusM = 8.0;
constexpr double kMemoryCellM = 0.2;

}  // namespace

void OvpcMapBackend::Config::Validate() const {
  mapper.Validate();
  map.Validate();
  if (!(ground_memory_s >= 0.0) || ground_memory_s > 600.0) {
    throw std::invalid_argument("navigator.ovpc.ground_memory_s must be in [0, 600] s");
  }
}

OvpcMapBackend::OvpcMapBackend(const Config& config) : config_(config), mapper_(config.mapper) { config_.Validate(); }

std::shared_ptr<const planner::PlanningMap> OvpcMapBackend::Update(const Points& points_L, const MapContext& context) {
  latest_ = mapper_.Update(points_L, Vec3::Zero());
  planning_map_ms_ = 0.0;
  if (!latest_.ok()) return nullptr;
  planner::GroundContext ground;
  ground.ground_reference_z_m = context.T_L_B.translation().z();
  ground.known_support = context.known_support;
  const auto t = Clock::now();
  if (config_.ground_memory_s > 0.0) {
    // What was remembered before this update and not yet forgotten, in L (one pass: forgetting
    // and copying); then this update's points join it.
    const double forget_before_s = context.time_s - config_.ground_memory_s;
    std::vector<Vec3> remembered_L;
    std::vector<std::uint8_t> traversable;
    remembered_L.reserve(memory_.size());
    traversable.reserve(memory_.size());
    for (auto it = memory_.begin(); it != memory_.end();) {
      const Remembered& r = it->second;
      if (r.time_s < forget_before_s) {
        it = memory_.erase(it);
        continue;
      }
      const Vec3 p_L = r.p_O - context.L_in_O;
      if (p_L.head<2>().squaredNorm() <= kMemoryRadiusM * kMemoryRadiusM) {
        remembered_L.push_back(p_L);
        traversable.push_back(r.traversable);
      }
      ++it;
    }
    ground.remembered = std::make_shared<const planner::RememberedGround>(remembered_L, traversable);
    Remember(context);
  }
  auto map = std::make_shared<const planner::VertexCloudMap>(latest_.cloud, config_.map, ground);
  planning_map_ms_ = MsSince(t);
  return map;
}

void OvpcMapBackend::Remember(const MapContext& context) {
  const TraversabilityCloud& cloud = latest_.cloud;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p_L = cloud.points()[i];
    if (p_L.head<2>().squaredNorm() > kMemoryRadiusM * kMemoryRadiusM) continue;
    // Ground under the vehicle's own footprint is the footprint prior's, not seen.
    if (context.known_support.Contains(p_L.x(), p_L.y())) continue;
    const Vec3 p_O = p_L + context.L_in_O;
    const auto ix = static_cast<std::int64_t>(std::floor(p_O.x() / kMemoryCellM));
    const auto iy = static_cast<std::int64_t>(std::floor(p_O.y() / kMemoryCellM));
    const std::uint64_t key = (static_cast<std::uint64_t>(ix) << 32) ^ static_cast<std::uint64_t>(iy & 0xffffffff);
    memory_[key] = Remembered{p_O, context.time_s, cloud.traversable()[i]};
  }
}

std::vector<MapStageTime> OvpcMapBackend::StageTimes() const {
  const StageTimings& t = latest_.timings;
  return {{"sanitize", t.sanitize_ms},       {"transform", t.transform_ms},
          {"hull", t.hull_ms},               {"mesh", t.mesh_ms},
          {"traversability", t.traversability_ms}, {"vertex_cloud", t.vertex_cloud_ms},
          {"planning_map", planning_map_ms_}};
}

MapView OvpcMapBackend::View() const {
  MapView view;
  if (!latest_.ok()) return view;
  view.points_L = &latest_.cloud.points();
  view.traversable = &latest_.cloud.traversable();
  view.mesh_L = &latest_.mesh;
  view.normals_L = &latest_.cloud.normals();
  return view;
}

}  // namespace ovpc::navigation
