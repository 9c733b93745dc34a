// The OctoMap map backend: OctoMap (Debian's liboctomap) behind the navigator's MapBackend seam.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ovpc/backends/column_map.h"
#include "ovpc/backends/octomap_columns.h"
#include "ovpc/core/types.h"
#include "ovpc/navigation/map_backend.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::backends {

/// Per update a fresh octomap::OcTree from the buffered cloud, inserted as one scan from the
/// viewpoint (OcTree::insertPointCloud, OctoMap's default sensor model), read into columns
/// (OctoMapColumns) and answered by a ColumnMap. The tree is rebuilt from the buffer each update
/// rather than kept: the buffer already fuses the last scans by odometry, as it does for OVPC, so
/// both maps see the same points; a kept tree would also keep what odometry drift smeared.
class OctoMapBackend final : public navigation::MapBackend {
 public:
  struct Config {
    double resolution_m = 0.2;  ///< voxel edge
    /// The planner's view (its thresholds are the OVPC face test's, given to the constructor).
    ColumnMap::Config map;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, resolution_m), "m", "voxel edge (0.1 costs about 4x the update time)");
      v.Section(OVPC_FIELD(c, map), "the planner's view of the columns");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
  /// @throws std::invalid_argument for an invalid config.
  /// `faces`: the OVPC face test's thresholds, which the ColumnMap judges with.
  explicit OctoMapBackend(const Config& config, const Traversability::Config& faces = {});
  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L,
                                                     const navigation::MapContext& context) override;
  navigation::MapView View() const override;
  const char* name() const override { return "octomap"; }
  /// insert (the OcTree), columns (reading it), traversability (ColumnMap: planes, steps).
  std::vector<navigation::MapStageTime> StageTimes() const override { return stages_; }
  const Config& config() const { return config_; }
  const Traversability::Config& faces() const { return faces_; }

 private:
  Config config_;
  Traversability::Config faces_;
  OctoMapColumns tree_;
  std::vector<navigation::MapStageTime> stages_;
  std::vector<Vec3> view_points_;
  std::vector<std::uint8_t> view_traversable_;
};

}  // namespace ovpc::backends
