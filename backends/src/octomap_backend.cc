#include "ovpc/backends/octomap_backend.h"

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>

#include "column_backend.h"
#include "ovpc/core/internal/clock.h"

namespace ovpc::backends {
namespace {

using ovpc::internal::Clock;
using ovpc::internal::MsSince;

const OctoMapBackend::Config& Validated(const OctoMapBackend::Config& config) {
  config.Validate();
  return config;
}

}  // namespace

void OctoMapBackend::Config::Validate() const {
  if (!(resolution_m >= 0.01 && resolution_m <= 10.0)) {
    throw std::invalid_argument("octomap.resolution_m must be in [0.01, 10], got " + std::to_string(resolution_m));
  }
  map.Validate();
  internal::CheckNormalRadius(map, resolution_m, "octomap");
}

OctoMapBackend::OctoMapBackend(const Config& config, const Traversability::Config& faces)
    : config_(Validated(config)), faces_(faces), tree_(config.resolution_m) {}

std::shared_ptr<const planner::PlanningMap> OctoMapBackend::Update(const Points& points_L,
                                                                   const navigation::MapContext& context) {
  stages_.clear();
  view_points_.clear();
  view_traversable_.clear();
  auto t = Clock::now();
  tree_.Insert(points_L, Vec3::Zero());
  stages_.push_back({"insert", MsSince(t)});
  t = Clock::now();
  ColumnGrid columns = tree_.Columns();
  stages_.push_back({"columns", MsSince(t)});
  if (columns.ground_z.empty()) return nullptr;  // nothing seen with free space above it
  t = Clock::now();
  auto map = std::make_shared<const ColumnMap>(std::move(columns), config_.map, internal::GroundOf(context), faces_);
  stages_.push_back({"traversability", MsSince(t)});
  internal::ViewOf(*map, &view_points_, &view_traversable_);
  return map;
}

navigation::MapView OctoMapBackend::View() const { return internal::ViewOf(view_points_, view_traversable_); }

}  // namespace ovpc::backends
