// The default map backend: the OVPC Mesh map of the paper behind the MapBackend seam.
#pragma once

#include <memory>
#include <vector>

#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/types.h"
#include "ovpc/navigation/map_backend.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/planner/vertex_cloud_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::navigation {

/// The OVPC Mesh map (the paper): GHPR visible set, free-space mesh, traversable vertex cloud, and
/// the planner's VertexCloudMap on it.
class OvpcMapBackend final : public MapBackend {
 public:
  struct Config {
    OvpcMapper::Config mapper;
    /// The planner's view of the vertex cloud (where the vehicle stands comes per update, from
    /// the MapContext).
    planner::VertexCloudMap::Config map;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, mapper), "the paper's OVPC Mesh");
      v.Section(OVPC_FIELD(c, map), "the planner's view of the vertex cloud");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument for an invalid config.
  explicit OvpcMapBackend(const Config& config);

  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext& context) override;
  MapView View() const override;
  const char* name() const override { return "ovpc"; }
  /// sanitize, transform, hull, mesh, traversability, vertex_cloud (OvpcMapper's StageTimings) and
  /// planning_map (the VertexCloudMap's grid).
  std::vector<MapStageTime> StageTimes() const override;

  /// The latest OVPC map (mesh, vertex cloud, stage timings); status not ok before the first update.
  const OvpcMap& latest() const { return latest_; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  OvpcMapper mapper_;
  OvpcMap latest_;
  double planning_map_ms_ = 0.0;
};

}  // namespace ovpc::navigation
