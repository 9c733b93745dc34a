#include "ovpc/navigation/map_backend.h"

namespace ovpc::navigation {

void OvpcMapBackend::Config::Validate() const {
  mapper.Validate();
  map.Validate();
}

OvpcMapBackend::OvpcMapBackend(const Config& config) : config_(config), mapper_(config.mapper) { config_.Validate(); }

std::shared_ptr<const planner::PlanningMap> OvpcMapBackend::Update(const Points& points_L, const MapContext& context) {
  latest_ = mapper_.Update(points_L, Vec3::Zero());
  if (!latest_.ok()) return nullptr;
  planner::VertexCloudMap::Config map_config = config_.map;
  map_config.ground_reference_z_m = context.T_L_B.translation().z();
  map_config.known_support = context.known_support;
  return std::make_shared<const planner::VertexCloudMap>(latest_.cloud, map_config);
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
