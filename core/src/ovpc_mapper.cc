#include "ovpc/core/ovpc_mapper.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "internal_util.h"

namespace ovpc {
namespace {

using internal::Clock;
using internal::MsSince;

}  // namespace

void OvpcMapper::Config::Validate() const {
  ghpr.Validate();
  traversability.Validate();
  vertex_normals.Validate();
  // ComputeGhpr rejects points within a few micrometres of the viewpoint; the mapper must drop them.
  if (!(min_range_m >= 1e-5) || !std::isfinite(min_range_m)) {
    throw std::invalid_argument("OvpcMapper::Config: min_range_m must be >= 1e-5 m");
  }
}

OvpcMapper::OvpcMapper(const Config& config) : config_(config) { config_.Validate(); }

OvpcMap OvpcMapper::Update(const Points& points, const Vec3& viewpoint) const {
  OvpcMap map;
  const auto start = Clock::now();
  map.input.input = points.size();
  if (!viewpoint.allFinite()) {
    map.status = GhprStatus::kDegenerate;
    map.message = "the viewpoint is not finite";
    return map;
  }

  auto t = Clock::now();
  Points usable;
  usable.reserve(points.size());
  const double min_range2 = config_.min_range_m * config_.min_range_m;
  for (const Vec3& p : points) {
    if (!p.allFinite()) {
      ++map.input.non_finite;
    } else if (!((p - viewpoint).cwiseAbs().maxCoeff() <= kGhprMaxDistanceM)) {
      ++map.input.too_far;
    } else if ((p - viewpoint).squaredNorm() < min_range2) {
      ++map.input.at_viewpoint;
    } else {
      usable.push_back(p);
    }
  }
  map.input.used = usable.size();
  map.timings.sanitize_ms = MsSince(t);

  GhprResult ghpr = ComputeGhpr(usable, viewpoint, config_.ghpr);
  map.timings.transform_ms = ghpr.transform_ms;
  map.timings.hull_ms = ghpr.hull_ms;
  map.timings.mesh_ms = ghpr.mesh_ms;
  map.status = ghpr.status;
  map.message = std::move(ghpr.message);
  if (ghpr.status != GhprStatus::kOk) {
    map.timings.total_ms = MsSince(start);
    return map;
  }
  map.mesh = std::move(ghpr.mesh);

  t = Clock::now();
  ClassifyFaces(config_.traversability, &map.mesh);
  map.timings.traversability_ms = MsSince(t);

  t = Clock::now();
  map.cloud = BuildTraversabilityCloud(map.mesh, config_.vertex_normals);
  map.timings.vertex_cloud_ms = MsSince(t);
  map.timings.total_ms = MsSince(start);
  return map;
}

}  // namespace ovpc
