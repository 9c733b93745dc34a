#include "ovpc/navigation/map_backend.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ovpc/backends/elevation_columns.h"
#include "stage_clock.h"

namespace ovpc::navigation {
namespace {

using internal::Clock;
using internal::MsSince;

// The per-update inputs of a column map.
backends::ColumnMap::Config ColumnConfigFor(const backends::ColumnMap::Config& config, const MapContext& context) {
  backends::ColumnMap::Config c = config;
  c.ground_reference_z_m = context.T_L_B.translation().z();
  c.known_support = context.known_support;
  return c;
}

// What a person looks at of a column map: its ground candidates with their verdicts.
void ViewOf(const backends::ColumnMap& map, std::vector<Vec3>* points, std::vector<std::uint8_t>* traversable) {
  *points = map.GroundPoints();
  *traversable = map.ground_traversable();
}

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
  planner::VertexCloudMap::Config map_config = config_.map;
  map_config.ground_reference_z_m = context.T_L_B.translation().z();
  map_config.known_support = context.known_support;
  const auto t = Clock::now();
  auto map = std::make_shared<const planner::VertexCloudMap>(latest_.cloud, map_config);
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

void OctoMapBackend::Config::Validate() const {
  if (!(resolution_m >= 0.01 && resolution_m <= 10.0)) {
    throw std::invalid_argument("octomap.resolution_m must be in [0.01, 10], got " + std::to_string(resolution_m));
  }
  map.Validate();
}

OctoMapBackend::OctoMapBackend(const Config& config) : config_(config), tree_(config.resolution_m) { config_.Validate(); }

std::shared_ptr<const planner::PlanningMap> OctoMapBackend::Update(const Points& points_L, const MapContext& context) {
  stages_.clear();
  view_points_.clear();
  view_traversable_.clear();
  auto t = Clock::now();
  tree_.Insert(points_L, Vec3::Zero());
  stages_.push_back({"insert", MsSince(t)});
  t = Clock::now();
  backends::ColumnGrid columns = tree_.Columns();
  stages_.push_back({"columns", MsSince(t)});
  if (columns.ground_z.empty()) return nullptr;  // nothing seen with free space above it
  t = Clock::now();
  auto map = std::make_shared<const backends::ColumnMap>(std::move(columns), ColumnConfigFor(config_.map, context));
  stages_.push_back({"traversability", MsSince(t)});
  ViewOf(*map, &view_points_, &view_traversable_);
  return map;
}

MapView OctoMapBackend::View() const {
  MapView view;
  if (view_points_.empty()) return view;
  view.points_L = &view_points_;
  view.traversable = &view_traversable_;
  return view;
}

void ElevationMapBackend::Config::Validate() const {
  grid.Validate();
  map.Validate();
}

ElevationMapBackend::ElevationMapBackend(const Config& config) : config_(config), grid_(config.grid) { config_.Validate(); }

std::shared_ptr<const planner::PlanningMap> ElevationMapBackend::Update(const Points& points_L, const MapContext& context) {
  stages_.clear();
  view_points_.clear();
  view_traversable_.clear();
  const double base_z = context.T_L_B.translation().z();
  if (!std::isfinite(base_z)) return nullptr;
  auto t = Clock::now();
  grid_.Clear();
  grid_.Update(points_L, Vec3::Zero(), base_z);
  stages_.push_back({"fuse", MsSince(t)});
  t = Clock::now();
  backends::ColumnGrid columns = backends::ElevationColumns(grid_);
  stages_.push_back({"columns", MsSince(t)});
  if (columns.ground_z.empty()) return nullptr;
  t = Clock::now();
  auto map = std::make_shared<const backends::ColumnMap>(std::move(columns), ColumnConfigFor(config_.map, context));
  stages_.push_back({"traversability", MsSince(t)});
  ViewOf(*map, &view_points_, &view_traversable_);
  return map;
}

MapView ElevationMapBackend::View() const {
  MapView view;
  if (view_points_.empty()) return view;
  view.points_L = &view_points_;
  view.traversable = &view_traversable_;
  return view;
}

}  // namespace ovpc::navigation
