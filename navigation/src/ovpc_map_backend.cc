#include "ovpc/navigation/ovpc_map_backend.h"

#include <chrono>

#include "ovpc/core/internal/clock.h"

namespace ovpc::navigation {
namespace {

using ovpc::internal::Clock;
using ovpc::internal::MsSince;

}  // namespace

void OvpcMapBackend::Config::Validate() const {
  mapper.Validate();
  map.Validate();
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
  auto map = std::make_shared<const planner::VertexCloudMap>(latest_.cloud, config_.map, ground);
  planning_map_ms_ = MsSince(t);
  return map;
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
