// The reachable local goals (LocalGoalSelection::Config::Mode::kReachable): a grid over the map,
// the places the vehicle can reach over known ground, each place's cost to go along the route,
// and the best reachable places as goals. Private to the planner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ovpc/planner/local_goal.h"
#include "ovpc/planner/planning_map.h"

namespace ovpc::planner::internal {

/// A point of the route resampled in frame L, with its leg's heading and its progress along it.
struct RoutePoint {
  Eigen::Vector2d position;
  double yaw_rad;
  double progress_m;
  bool is_end;
};

/// The stages of the selection, one method each, over one grid. Use once: `Select`.
class ReachableGoals {
 public:
  /// `route[closest, end)` is the route ahead (AheadRange in local_goal.cc).
  ReachableGoals(const PlanningMap& map, const VehicleBox& vehicle, const std::vector<RoutePoint>& route,
                 std::size_t closest, std::size_t end, const Pose2& vehicle_L, const LocalGoalSelection::Config& config,
                 const std::optional<LocalGoal>& previous_L);

  /// At most `max_count` goals, the best first: the route's end when it is reached, else the
  /// previous goal when it is still nearly as good, then the reached cells by cost to go.
  std::vector<LocalGoal> Select(std::size_t max_count);

 private:
  enum : std::uint8_t { kUnknown, kFree, kBlocked, kOverhead };

  bool MakeGrid();
  void ClassifyCells();
  void GrowBlocked();
  void Dijkstra(std::vector<double>* cost, const std::function<bool(std::size_t)>& passable) const;
  void CostToGo();
  bool Reach();
  void Score();
  void AddRouteEndOrPrevious(std::vector<LocalGoal>* goals) const;
  void AddBestCells(std::size_t max_count, std::vector<LocalGoal>* goals) const;

  bool Qualifies(const Pose2& pose, bool is_end, const VehicleBox* vehicle = nullptr) const;
  bool FrontOnSlopeWithinTilt(const Pose2& pose) const;
  double OffRoute(const Eigen::Vector2d& p) const;
  double CostAt(const Eigen::Vector2d& p, const std::vector<double>& field) const;
  bool Interior(int ix, int iy, int rim) const;
  double DownhillYaw(std::size_t i, int ix, int iy, int around) const;
  std::size_t Index(int ix, int iy) const { return static_cast<std::size_t>(iy) * nx_ + ix; }
  Eigen::Vector2d Centre(int ix, int iy) const { return Eigen::Vector2d(x0_ + (ix + 0.5) * cell_, y0_ + (iy + 0.5) * cell_); }
  Eigen::Vector2d CentreOf(std::size_t i) const { return Centre(static_cast<int>(i % nx_), static_cast<int>(i / nx_)); }
  bool CellOf(const Eigen::Vector2d& p, int* ix, int* iy) const;
  bool Impassable(std::size_t j) const { return state_[j] == kBlocked || state_[j] == kOverhead; }

  const PlanningMap& map_;
  const VehicleBox& vehicle_;
  const std::vector<RoutePoint>& route_;
  const std::size_t closest_, end_;
  const Pose2 vehicle_L_;
  const LocalGoalSelection::Config& config_;
  const std::optional<LocalGoal>& previous_L_;
  const Eigen::Vector2d here_;
  const double route_length_;

  MapBounds bounds_{};
  double cell_ = 0.0, x0_ = 0.0, y0_ = 0.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> state_;    // per cell: kUnknown, kFree, kBlocked or kOverhead
  std::vector<std::uint8_t> blocked_;  // the vehicle's centre cannot be there
  std::vector<Eigen::Vector2d> blocking_;  // the non-traversable point of each kBlocked cell
  std::vector<std::size_t> blocking_cell_;
  std::vector<double> to_go_, reach_, score_;
  std::vector<std::size_t> order_;  // reached cells by score
  std::vector<Eigen::Vector2d> route_ahead_;
  double best_score_ = 0.0;
};

}  // namespace ovpc::planner::internal
