// The OVPC map update: one call from a local cloud to the planner's map, with per-stage timings.
#pragma once

#include <string>

#include "ovpc/core/ghpr.h"
#include "ovpc/core/traversability.h"
#include "ovpc/core/vertex_cloud.h"
#include "ovpc/core/config_fields.h"

namespace ovpc {

/// Wall-clock milliseconds per stage of one update (for reports and benchmarks only; nothing in
/// the pipeline depends on them).
struct StageTimings {
  double sanitize_ms = 0.0;       ///< dropping NaN/inf points and points at the viewpoint
  double transform_ms = 0.0;      ///< GHPR image transform
  double hull_ms = 0.0;           ///< convex hull of the image set (CGAL, exact predicates)
  double mesh_ms = 0.0;           ///< hull back to a mesh on the original points
  double traversability_ms = 0.0; ///< face normals and flags
  double vertex_cloud_ms = 0.0;   ///< vertex normals (plane fits included), flags and the k-d tree
  double total_ms = 0.0;
};

struct InputStats {
  std::size_t input = 0;         ///< points given
  std::size_t non_finite = 0;    ///< dropped: a coordinate was NaN or inf
  std::size_t at_viewpoint = 0;  ///< dropped: closer than Config::min_range_m to the viewpoint
  std::size_t too_far = 0;       ///< dropped: a coordinate farther than kGhprMaxDistanceM from the viewpoint
  std::size_t used = 0;          ///< points that went into GHPR
};

struct OvpcMap {
  GhprStatus status = GhprStatus::kTooFewPoints;
  std::string message;
  InputStats input;
  FreeSpaceMesh mesh;          ///< classified free-space mesh (empty unless status is kOk)
  TraversabilityCloud cloud;   ///< the planner's map (empty unless status is kOk)
  StageTimings timings;
  bool ok() const { return status == GhprStatus::kOk; }
};

class OvpcMapper {
 public:
  struct Config {
    Ghpr::Config ghpr;
    Traversability::Config traversability;
    VertexNormals::Config vertex_normals;
    double min_range_m = 1e-3;  ///< points closer to the viewpoint are dropped as "at the viewpoint" (>= 1e-5)
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, ghpr), "the paper's hidden point removal");
      v.Section(OVPC_FIELD(c, traversability), "the paper's face test");
      v.Section(OVPC_FIELD(c, vertex_normals), "each visible point's normal");
      v.Field(OVPC_FIELD(c, min_range_m), "m", "closer points count as at the viewpoint");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  OvpcMapper() : OvpcMapper(Config{}) {}
  /// @throws std::invalid_argument if the config is invalid.
  explicit OvpcMapper(const Config& config);

  /// Builds the map from `points` (any frame whose z axis is gravity-up, see
  /// Traversability::Config::up) seen from `viewpoint`. Never throws on bad data: NaN/inf points and
  /// points at the viewpoint are dropped and counted; too few or degenerate points give a status.
  OvpcMap Update(const Points& points, const Vec3& viewpoint) const;

  const Config& config() const { return config_; }

 private:
  Config config_;
};

}  // namespace ovpc
