// The local-planner seam: a path between two poses on the planner's map, and the check that a path
// still holds on a newer map.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "ovpc/planner/local_planner.h"
#include "ovpc/planner/path.h"
#include "ovpc/planner/planning_map.h"

namespace ovpc::navigation {

/// One narrow job: plan on a map, in the map's frame. Must be deterministic (same map, poses and
/// configuration: same result) and never throw on a bad problem (an invalid start or goal, or no
/// path, is a status).
class PathPlanner {
 public:
  virtual ~PathPlanner() = default;
  /// A path from `start` to `goal`; `other_goal_yaws`: the goal position with these headings is a
  /// goal too (the route's end, where only the position matters).
  virtual planner::PlanResult Plan(const planner::PlanningMap& map, const planner::Pose2& start,
                                   const planner::Pose2& goal, const std::vector<double>& other_goal_yaws) const = 0;
  /// Index (in Path::Poses() order) of the first pose at or after `from_index` the vehicle cannot
  /// take on `map`, or nothing: the re-planning trigger "the path collides after a map update".
  virtual std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap& map, const planner::Path& path,
                                                      std::size_t from_index) const = 0;
};

/// The paper's planner: OMPL RRTConnect in a Reeds-Shepp space (planner::LocalPlanner).
class RrtConnectPlanner final : public PathPlanner {
 public:
  /// @throws std::invalid_argument for an invalid config.
  /// `vehicle` gives the box's size and turning radius; `seed` seeds each plan's random sources.
  explicit RrtConnectPlanner(const planner::LocalPlanner::Config& config, const VehicleModel& vehicle = {},
                             std::uint32_t seed = 1)
      : planner_(config, vehicle, seed) {}
  planner::PlanResult Plan(const planner::PlanningMap& map, const planner::Pose2& start, const planner::Pose2& goal,
                           const std::vector<double>& other_goal_yaws) const override {
    return planner_.Plan(map, start, goal, other_goal_yaws);
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap& map, const planner::Path& path,
                                              std::size_t from_index) const override {
    return planner_.FirstInvalidPose(map, path, from_index);
  }

 private:
  planner::LocalPlanner planner_;
};

}  // namespace ovpc::navigation
