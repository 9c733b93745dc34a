// The 2.5D elevation-map backend: baselines::ElevationMap behind the navigator's MapBackend seam.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ovpc/backends/column_map.h"
#include "ovpc/baselines/elevation_map.h"
#include "ovpc/core/types.h"
#include "ovpc/navigation/map_backend.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::backends {

/// Per update the grid is cleared and the buffered cloud fused into it (the vehicle's ground height
/// as the robot base), its cells read into columns (ElevationColumns) and answered by a ColumnMap.
/// One height per cell: a roof over a cell is that cell's height (the 2.5D limitation, kept as it
/// is).
class ElevationMapBackend final : public navigation::MapBackend {
 public:
  struct Config {
    /// Rebuilt every update: at most kMaxCellsPerSide cells a side (baselines allows more).
    baselines::ElevationMap::Config grid;
    /// As OctoMapBackend::Config::map.
    ColumnMap::Config map;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, grid), "baselines::ElevationMap, rebuilt per update");
      v.Section(OVPC_FIELD(c, map), "the planner's view of the cells");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
  /// 2,000 cells of 0.1 m cover 200 m, four times the default 50 m, in 4 million cells.
  static constexpr double kMaxCellsPerSide = 2000.0;

  /// @throws std::invalid_argument for an invalid config.
  /// `faces`: the OVPC face test's thresholds, which the ColumnMap judges with.
  explicit ElevationMapBackend(const Config& config, const Traversability::Config& faces = {});
  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L,
                                                     const navigation::MapContext& context) override;
  navigation::MapView View() const override;
  const char* name() const override { return "elevation"; }
  /// fuse (the height grid), columns (reading it), traversability (ColumnMap: planes, steps).
  std::vector<navigation::MapStageTime> StageTimes() const override { return stages_; }
  const Config& config() const { return config_; }
  const Traversability::Config& faces() const { return faces_; }

 private:
  Config config_;
  Traversability::Config faces_;
  baselines::ElevationMap grid_;
  std::vector<navigation::MapStageTime> stages_;
  std::vector<Vec3> view_points_;
  std::vector<std::uint8_t> view_traversable_;
};

}  // namespace ovpc::backends
