// Progress along a route in the route's order, for a vehicle that follows it.
#pragma once

#include <algorithm>
#include <vector>

#include <Eigen/Core>

#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

/// Tracks how far along a route (arc length, metres) a moving point is. The search moves with the
/// point: it looks `back_m` behind and `ahead_m` ahead of the last progress, so that a route that
/// comes back beside itself (a U-turn, laps side by side, a figure of eight) is followed leg by leg,
/// never scored as done from its way out. A point that left the route (a vehicle cutting a corner)
/// is placed where it rejoins it: while it is off the route, the window ahead grows by `cut_ratio`
/// times the distance it moved off the route, and a route point within `on_route_m` of it in that
/// longer window is taken.
class RouteTracker {
 public:
  struct Config {
    double back_m = 5.0;
    double ahead_m = 10.0;
    double on_route_m = 1.5;  ///< nearer than this to the route is on it
    double cut_ratio = 3.0;   ///< route length a cut corner may skip, per metre moved off the route
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, back_m), "m", "progress is searched this far back");
      v.Field(OVPC_FIELD(c, ahead_m), "m", "... and this far ahead of the last progress");
      v.Field(OVPC_FIELD(c, on_route_m), "m", "nearer than this to the route is on it");
      v.Field(OVPC_FIELD(c, cut_ratio), "m/m", "route a cut corner may skip per metre moved off the route");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// @throws std::invalid_argument for a route of fewer than two points or a bad config.
  RouteTracker(std::vector<Eigen::Vector2d> route, const Config& config);
  explicit RouteTracker(std::vector<Eigen::Vector2d> route) : RouteTracker(std::move(route), Config{}) {}

  /// Takes the point's next position; returns its progress.
  double Update(const Eigen::Vector2d& p);
  double progress_m() const { return progress_m_; }
  /// Raises the progress to at least `progress_m` (a caller that knows better, e.g. from the goal
  /// it drives to).
  void Advance(double progress_m) { progress_m_ = std::max(progress_m_, progress_m); }
  /// The route's point at arc length `s_m` (clamped to the route).
  Eigen::Vector2d PointAt(double s_m) const;

 private:
  std::vector<Eigen::Vector2d> route_;
  Config config_;
  double progress_m_ = 0.0;
  double off_route_m_ = 0.0;  ///< moved since the point was last on the route
  Eigen::Vector2d last_;
  bool has_last_ = false;
};

}  // namespace ovpc::planner
