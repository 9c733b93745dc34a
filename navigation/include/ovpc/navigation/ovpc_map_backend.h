// The default map backend: the OVPC Mesh map of the paper behind the MapBackend seam.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
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
    /// The map's points within 8 m of the sensor are remembered (in the odometry frame, the latest
    /// per 0.2 m cell, with its traversability) this long after they were last seen, for wheels
    /// the present map has no point near (planner::RememberedGround). 0: off (the paper's map
    /// holds only the buffer).
    double ground_memory_s = 0.0;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, mapper), "the paper's OVPC Mesh");
      v.Section(OVPC_FIELD(c, map), "the planner's view of the vertex cloud");
      v.Field(OVPC_FIELD(c, ground_memory_s), "s", "wheels with no point near: ground seen this recently carries them; 0: off");
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
  // Remembered ground (Config::ground_memory_s): per 0.2 m cell of O, the latest point seen there
  // (in O), when, and whether it was traversable.
  struct Remembered {
    Vec3 p_O;
    double time_s;
    std::uint8_t traversable;
  };
  void Remember(const MapContext& context);

  Config config_;
  OvpcMapper mapper_;
  OvpcMap latest_;
  double planning_map_ms_ = 0.0;
  std::unordered_map<std::uint64_t, Remembered> memory_;
};

}  // namespace ovpc::navigation
