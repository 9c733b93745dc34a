// What the navigator does to the buffered cloud before the map backend sees it: drop lone outliers,
// drop returns off the vehicle itself, and lay the ground the vehicle stands on (the footprint
// prior), which the sensor never sees.
#pragma once

#include <limits>

#include <Eigen/Geometry>

#include "ovpc/core/types.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::navigation {

struct MapPreparation {
  /// What the footprint prior does with measured ground (points below the box's ground clearance)
  /// over the grown footprint. kReplace drops it and lays the grid everywhere: right on flat ground,
  /// but at a ramp's foot or crest the flat grid cuts off the measured slope and leaves a step. kFill
  /// keeps it and lays grid points only where no measured point lies within the grid's spacing, so
  /// the grid fills the sensor's blind zone and never sits next to a measured point.
  enum class PriorMode { kReplace, kFill };

  struct Config {
    /// The ground under the vehicle is never in view (the sensor sees no closer than about 1.1 m
    /// from the mast), yet the vehicle stands on it. When > 0, a grid on the vehicle's footprint
    /// plane, grown by this margin, is added to each cloud from the odometry pose, so that the
    /// planner's start pose projects onto known ground. 0 disables.
    double footprint_prior_margin_m = 0.3;
    PriorMode footprint_prior_mode = PriorMode::kReplace;
    /// kFill only: a grid point with measured ground within this distance takes its height from that
    /// ground (inverse-distance mean), weighted by 1 - d/blend with d the distance to the nearest
    /// measured point, instead of sitting on the vehicle's plane: at a ramp's crest under the pitched
    /// vehicle a flat grid makes steep slivers. 0 disables.
    double footprint_prior_blend_m = 0.0;
    /// Spacing of the footprint grid.
    double footprint_grid_m = 0.25;
    /// Measured ground is kept this far off the grid's edge (kReplace).
    double footprint_edge_band_m = 0.12;
    /// Returns inside the vehicle's box grown by this much are dropped (returns off the vehicle).
    double body_margin_m = 0.02;
    /// When > 0, points within `isolated_point_reach_m` of the sensor with no other point within
    /// this radius are dropped: LiDAR outliers that survive the voxel filter (two in one voxel) float
    /// alone in free space and block every path through them. It can also drop a far, thinly hit
    /// post until the vehicle is nearer. 0 disables.
    double isolated_point_radius_m = 0.0;
    double isolated_point_reach_m = 12.0;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, footprint_prior_margin_m), "m", "lay the unseen ground under the vehicle, grown by this; 0: off");
      v.Choice(OVPC_FIELD(c, footprint_prior_mode), Choices<PriorMode>{{"replace", PriorMode::kReplace}, {"fill", PriorMode::kFill}},
               "replace: a flat grid; fill: only where nothing was measured");
      v.Field(OVPC_FIELD(c, footprint_prior_blend_m), "m", "fill: the grid blends into measured ground within this");
      v.Field(OVPC_FIELD(c, footprint_grid_m), "m", "spacing of the footprint grid");
      v.Field(OVPC_FIELD(c, footprint_edge_band_m), "m", "replace: measured ground kept this far off the grid's edge");
      v.Field(OVPC_FIELD(c, body_margin_m), "m", "returns inside the vehicle's box grown by this are the vehicle");
      v.Field(OVPC_FIELD(c, isolated_point_radius_m), "m", "lone points near the sensor are dropped; 0: off");
      v.Field(OVPC_FIELD(c, isolated_point_reach_m), "m", "... within this of the sensor");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

/// Drops the points within `reach_m` of the viewpoint (the origin) that have no other point within
/// `radius_m`; the others keep their order. `radius_m <= 0` does nothing.
void DropIsolatedPoints(double radius_m, double reach_m, Points* points_L);

/// The vehicle's box for the footprint prior, in frame B: the footprint (x from -rear overhang to
/// the front, y across the width) and the band heights.
struct FootprintBox {
  double min_x_m = 0.0, max_x_m = 0.0, half_width_m = 0.0;
  double ground_band_m = 0.0;  ///< points lower than this (in B) are ground
  double top_m = 0.0;          ///< points at or above this (in B) are never the vehicle
  double body_margin_m = 0.0;  ///< returns within the footprint grown by this are the vehicle
  /// The ground grid ends here (in B) when that is short of the grown footprint's front: the ground
  /// under the nose is in the sensor's view, and where nothing was measured there (past a ditch's
  /// lip, over a crest) the grid would lay ground the sensor has not seen.
  double ground_max_x_m = std::numeric_limits<double>::infinity();
};

/// The footprint prior (MapPreparation::Config): drops returns off the vehicle's body (inside the
/// footprint grown by `box.body_margin_m`, between the ground band and `box.top_m`) and lays a grid
/// of ground points over the footprint grown by the configured margin, by the configured mode.
/// Anything taller just outside the body (a post the vehicle passes close by) stays.
void AddFootprintPrior(const Eigen::Isometry3d& T_L_B, const FootprintBox& box, const MapPreparation::Config& config,
                       Points* points_L);

}  // namespace ovpc::navigation
