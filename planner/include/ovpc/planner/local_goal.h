// The local goal on a global route (paper: "inside the mesh at a minimum distance ahead").
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ovpc/planner/planning_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

/// The local goal on the route (SelectLocalGoal, SelectLocalGoals).
struct LocalGoalSelection {
  struct Config {
    /// kRoute: the farthest qualifying point on the route or on a line beside it (the paper's rule,
    /// with offsets). kReachable: a cost-to-go field over a planar grid of the map, from the last
    /// route point ahead in the grid (which costs its remaining route length) through
    /// known-traversable and unknown cells around known non-traversable ones, and the goal is the
    /// place the vehicle can reach over known-traversable cells that has the least cost to go: when
    /// the route runs into a wall or a too-steep slope, the goal moves to the way round it that the
    /// map shows (a ramp's lane to the side), not to the foot of the wall.
    enum class Mode { kRoute, kReachable };
    Mode mode = Mode::kRoute;
    /// kReachable: grid cell edge length.
    double cell_m = 0.5;
    /// kReachable: candidates are ranked by cost to go plus this many metres per metre away from the
    /// route ahead, so that of two ways round an obstacle about as long the one nearer the route wins.
    double reach_offset_penalty = 0.0;
    /// kReachable: a cell is known traversable only if the visible point its centre projects onto lies
    /// within this distance of it (in the plane). The planner stands a wheel only within the vehicle's
    /// wheel_support_m of a visible point, so with that value the reach stays on ground the planner
    /// can plan over; far from the sensor the ground is sparse, and a goal reached over it is often
    /// one no path leads to. With the wheel rule (VehicleBox::FootprintCheck::kWheels) the distance is
    /// also at most the wheel's support at the cell (VehicleBox::WheelSupportAt, smaller near the
    /// sensor). Infinite: any distance (the nearest point decides).
    double reach_support_m = std::numeric_limits<double>::infinity();
    /// kReachable: candidates also score this many metres per metre away from the previous goal, so
    /// that of two ways round an obstacle about as good (a roof across the route, both sides unseen)
    /// the one already taken is kept: goals that alternate between the two sides, each a few metres
    /// ahead, make paths that undo each other. 0: no preference (the previous goal is still kept by
    /// keep_previous_within_m).
    double previous_goal_penalty = 0.0;
    /// kReachable: the cost to go counts a metre over unknown ground as this many metres (>= 1). With
    /// 1, unseen ground is as good as seen free ground, and the side of an obstacle the vehicle has
    /// not looked at yet always looks at least as good as the one it is driving to, whose obstacles it
    /// now sees: in front of a wide roof the goal then changes sides at each update. Counting the
    /// unseen dearer, ground the vehicle has seen to be free makes the way it took cheaper.
    double unknown_cost = 1.0;
    /// The goal is at least this far (straight line) from the vehicle, unless it is the route's end.
    double min_distance_m = 4.0;
    /// kRoute: route points this close (along the route) to its last waypoint count as its end: they
    /// qualify at any distance from the vehicle and are goals at the route's end. When noise makes the
    /// last waypoint's own pose fail, the vehicle then heads for the route just short of it instead of
    /// for a point beside the route at least min_distance_m away. 0: only the last waypoint.
    double end_zone_m = 0.0;
    /// The route is examined at this spacing between its waypoints.
    double step_m = 0.25;
    /// Also require that the vehicle box fits at the goal (CheckPose), not only that the place is
    /// known free, so that the planner does not reject the goal.
    bool require_vehicle_fit = true;
    /// Points this far to either side of the route (perpendicular to it) are candidates too: the route
    /// may run through a post's shadow, or under a roof too low to pass, while the ground beside it is
    /// known. Empty: the route only (the paper's rule).
    std::vector<double> lateral_offsets_m;
    /// Among the offsets, the goal with the most route progress less this many metres per metre of
    /// offset, and less the length the offset adds to the straight way to the route's end
    /// (hypot(remaining, offset) - remaining: about nothing far from the end, the whole offset at the
    /// end), wins (ties: the smaller offset): a wide detour is taken when it gets much further.
    double lateral_offset_penalty = 0.5;
    /// Keep the previous goal, if it still qualifies, unless the new one scores more than this much
    /// higher (kRoute: route progress less the offset's penalty and detour, as in the ranking below;
    /// a goal beside the route's end therefore gives way to the end itself once that qualifies):
    /// goals flickering between the two sides of a post make paths that undo each other. 0: always
    /// take the new goal (the paper's rule).
    double keep_previous_within_m = 0.0;
    /// Route points are candidates from the vehicle on until the route has run outside known free
    /// space for this long: past a longer gap the route may come back into the map further on (laps
    /// side by side, a loop), and a goal there would cut the route short. Infinite: the whole route
    /// ahead (the paper's rule).
    double max_gap_m = std::numeric_limits<double>::infinity();
    /// Route points are candidates only up to this much route length ahead of the vehicle's progress.
    /// Where the route comes back near itself inside known free space (a spiral's last laps), a goal
    /// further on would skip the part in between; max_gap_m does not stop that when no gap lies
    /// between. Infinite: the whole route ahead (the paper's rule).
    double max_ahead_m = std::numeric_limits<double>::infinity();
    /// Route points are candidates only while the route between the vehicle's place on it and the
    /// point strays at most this far from the straight line between the two: a route that goes away
    /// and comes back beside itself (a U-turn between lanes, laps, a figure of eight) is followed leg
    /// by leg, never cut across to its way back. A corner cut short strays less. Infinite: no such
    /// limit (the paper's rule).
    double max_detour_m = std::numeric_limits<double>::infinity();
    /// kReachable: when the best place the vehicle fits is nearer than min_distance_m (seen ground
    /// ends just ahead: a crest, an edge), it is a candidate too (LocalGoal::is_look), so that the
    /// vehicle can drive up to the rim and look over it. False: min_distance_m always holds (the
    /// paper's rule).
    bool look_at_rim = false;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Choice(OVPC_FIELD(c, mode), Choices<Mode>{{"route", Mode::kRoute}, {"reachable", Mode::kReachable}},
               "route: the farthest point on the route (paper); reachable: a cost-to-go field");
      v.Field(OVPC_FIELD(c, cell_m), "m", "reachable: grid cell edge");
      v.Field(OVPC_FIELD(c, reach_offset_penalty), "m/m", "reachable: per metre away from the route ahead");
      v.Field(OVPC_FIELD(c, reach_support_m), "m", "reachable: known ground lies this near a visible point");
      v.Field(OVPC_FIELD(c, min_distance_m), "m", "the goal is at least this far, unless the route's end");
      v.Field(OVPC_FIELD(c, end_zone_m), "m", "route: the route's last metres count as its end");
      v.Field(OVPC_FIELD(c, step_m), "m", "the route is examined at this spacing");
      v.Field(OVPC_FIELD(c, require_vehicle_fit), "", "the vehicle box fits at the goal too");
      v.Field(OVPC_FIELD(c, lateral_offsets_m), "m", "goals beside the route too; none: paper");
      v.Field(OVPC_FIELD(c, lateral_offset_penalty), "m/m", "per metre of offset");
      v.Field(OVPC_FIELD(c, previous_goal_penalty), "m/m", "reachable: per metre from the previous goal");
      v.Field(OVPC_FIELD(c, unknown_cost), "m/m", "reachable: a metre of unseen ground costs this many");
      v.Field(OVPC_FIELD(c, keep_previous_within_m), "m", "keep the previous goal unless beaten by this; 0: paper");
      v.Field(OVPC_FIELD(c, max_gap_m), "m", "candidates end past a longer gap in known space; inf: paper");
      v.Field(OVPC_FIELD(c, max_ahead_m), "m", "candidates up to this far ahead along the route; inf: paper");
      v.Field(OVPC_FIELD(c, max_detour_m), "m", "the route up to a candidate strays at most this far from the chord; inf: paper");
      v.Field(OVPC_FIELD(c, look_at_rim), "", "reachable: a nearer best place at the rim of seen ground is the goal");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

struct LocalGoal {
  Pose2 pose;                  ///< in the map frame L; yaw along the route
  double route_progress_m = 0; ///< distance along the route from its first waypoint
  bool is_route_end = false;   ///< the goal is the route's last waypoint
  double lateral_offset_m = 0; ///< kRoute: distance beside the route (left positive), 0 on it
  /// kReachable: the best place is nearer than min_distance_m, at the rim of what the map has seen
  /// (a crest, an edge, a shadow): the vehicle goes there and looks before it goes on.
  bool is_look = false;
};

/// The farthest point along the route, ahead of the vehicle, that is inside known free space and
/// traversable (and, by default, where the vehicle fits) and at least `min_distance_m` from the
/// vehicle. The route's last waypoint qualifies at any distance. With `lateral_offsets_m`, the same
/// search runs over points offset sideways, and the goal with the most progress less
/// `lateral_offset_penalty` per metre of offset wins. "Ahead" means past the route point
/// closest to the vehicle. Nothing if no route point qualifies.
///
/// @param route_O waypoints in the odometry frame O, in driving order.
/// @param T_L_O the odometry frame in the map frame (the mapper's frame L has the axes of O, so this is
///        usually a translation).
/// @param vehicle_L the vehicle pose in the map frame.
/// @param previous_L the goal chosen last time, in the map frame (see keep_previous_within_m).
std::optional<LocalGoal> SelectLocalGoal(const PlanningMap& map, const VehicleBox& vehicle,
                                         const std::vector<Eigen::Vector2d>& route_O,
                                         const Eigen::Isometry3d& T_L_O, const Pose2& vehicle_L,
                                         const LocalGoalSelection::Config& config,
                                         const std::optional<LocalGoal>& previous_L = std::nullopt);

/// The candidates SelectLocalGoal ranks, best first, at most `max_count`: the previous goal (if it
/// is kept), then the farthest qualifying point of the route and of each offset line by score. When
/// the planner finds no path to the first, the next is a different way round an obstacle. With
/// `vehicle_progress_m` (the caller's RouteProgress tracker), "ahead" starts there rather than at
/// the route point closest to the vehicle.
std::vector<LocalGoal> SelectLocalGoals(const PlanningMap& map, const VehicleBox& vehicle,
                                        const std::vector<Eigen::Vector2d>& route_O,
                                        const Eigen::Isometry3d& T_L_O, const Pose2& vehicle_L,
                                        const LocalGoalSelection::Config& config, const std::optional<LocalGoal>& previous_L,
                                        std::size_t max_count,
                                        std::optional<double> vehicle_progress_m = std::nullopt);

/// Arc length along the polyline `route` of its point closest to `p`, searched only over the part
/// between `from_m - back_m` and `from_m + ahead_m` of arc length, so that a tracker that moves the
/// window along with the vehicle is never fooled by a route that comes back near itself. With the
/// default (infinite) window, the closest point of the whole route.
double RouteProgress(const std::vector<Eigen::Vector2d>& route, const Eigen::Vector2d& p, double from_m = 0.0,
                     double back_m = std::numeric_limits<double>::infinity(),
                     double ahead_m = std::numeric_limits<double>::infinity());

}  // namespace ovpc::planner
