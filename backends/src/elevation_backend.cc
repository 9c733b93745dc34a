#include "ovpc/backends/elevation_backend.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "column_backend.h"
#include "ovpc/backends/elevation_columns.h"
#include "ovpc/core/internal/clock.h"

namespace ovpc::backends {
namespace {

using ovpc::internal::Clock;
using ovpc::internal::MsSince;

// Checked before the grid is allocated: a bad length would allocate first.
const ElevationMapBackend::Config& Validated(const ElevationMapBackend::Config& config) {
  config.Validate();
  return config;
}

}  // namespace

void ElevationMapBackend::Config::Validate() const {
  grid.Validate();
  const double cells = grid.length_m / grid.resolution_m;
  if (!(cells <= kMaxCellsPerSide)) {
    throw std::invalid_argument("elevation.grid.length_m / resolution_m must be at most " +
                                internal::Number(kMaxCellsPerSide) + " cells a side, got " + internal::Number(cells));
  }
  map.Validate();
  internal::CheckNormalRadius(map, grid.resolution_m, "elevation");
}

ElevationMapBackend::ElevationMapBackend(const Config& config, const Traversability::Config& faces)
    : config_(Validated(config)), faces_(faces), grid_(config.grid) {}

std::shared_ptr<const planner::PlanningMap> ElevationMapBackend::Update(const Points& points_L,
                                                                        const navigation::MapContext& context) {
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
  ColumnGrid columns = ElevationColumns(grid_);
  stages_.push_back({"columns", MsSince(t)});
  if (columns.ground_z.empty()) return nullptr;
  t = Clock::now();
  auto map = std::make_shared<const ColumnMap>(std::move(columns), config_.map, internal::GroundOf(context), faces_);
  stages_.push_back({"traversability", MsSince(t)});
  internal::ViewOf(*map, &view_points_, &view_traversable_);
  return map;
}

navigation::MapView ElevationMapBackend::View() const { return internal::ViewOf(view_points_, view_traversable_); }

}  // namespace ovpc::backends
