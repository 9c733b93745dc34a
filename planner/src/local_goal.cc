#include "ovpc/planner/local_goal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <stdexcept>
#include <string>

#include "ovpc/planner/path.h"
#include "reachable_goals.h"

namespace ovpc::planner {
namespace {

using internal::RoutePoint;

// The route in frame L, resampled every `step_m` along each leg, each point with the leg's heading.
std::vector<RoutePoint> Resample(const std::vector<Eigen::Vector2d>& route_O, const Eigen::Isometry3d& T_L_O,
                                 double step_m) {
  std::vector<Eigen::Vector2d> route_L;
  route_L.reserve(route_O.size());
  for (const Eigen::Vector2d& p_O : route_O) route_L.push_back((T_L_O * Vec3(p_O.x(), p_O.y(), 0.0)).head<2>());
  std::vector<RoutePoint> out;
  double progress = 0.0;
  double yaw = 0.0;
  for (std::size_t i = 0; i < route_L.size(); ++i) {
    if (i + 1 < route_L.size()) {
      const Eigen::Vector2d leg = route_L[i + 1] - route_L[i];
      const double length = leg.norm();
      if (length > 1e-9) yaw = std::atan2(leg.y(), leg.x());
      const int steps = std::max(1, static_cast<int>(std::ceil(length / step_m)));
      for (int k = 0; k < steps; ++k) {
        const double f = static_cast<double>(k) / steps;
        out.push_back({route_L[i] + f * leg, NormalizeYaw(yaw), progress + f * length, false});
      }
      progress += length;
    } else {
      out.push_back({route_L[i], NormalizeYaw(yaw), progress, true});
    }
  }
  // A route of one waypoint has no direction; the goal heading is then 0.
  return out;
}

// The first route index in (first, end) whose route from `first` strays more than `max_detour_m`
// from the chord between the two; `end` if none does.
std::size_t DetourEnd(const std::vector<RoutePoint>& route, std::size_t first, std::size_t end, double max_detour_m) {
  for (std::size_t i = first + 2; i < end; ++i) {
    for (std::size_t j = first + 1; j < i; ++j) {
      if (DistanceToSegment(route[j].position, route[first].position, route[i].position) > max_detour_m) return i;
    }
  }
  return end;
}

// Where along the resampled route "ahead" starts (the vehicle's progress, or else the route point
// closest to the vehicle), and where it ends: once the route has been outside known free space for
// more than max_gap_m.
std::pair<std::size_t, std::size_t> AheadRange(const PlanningMap& map, const std::vector<RoutePoint>& route,
                                               const Eigen::Vector2d& here, const LocalGoalSelection::Config& config,
                                               std::optional<double> vehicle_progress_m) {
  std::size_t closest = 0;
  if (vehicle_progress_m) {
    while (closest + 1 < route.size() && route[closest + 1].progress_m <= *vehicle_progress_m) ++closest;
  } else {
    double closest_distance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < route.size(); ++i) {
      const double d = (route[i].position - here).norm();
      if (d < closest_distance) closest_distance = d, closest = i;
    }
  }
  std::size_t end = route.size();
  if (std::isfinite(config.max_ahead_m)) {
    const double limit = (vehicle_progress_m ? *vehicle_progress_m : route[closest].progress_m) + config.max_ahead_m;
    while (end > closest + 1 && route[end - 1].progress_m > limit) --end;
  }
  if (std::isfinite(config.max_detour_m)) end = std::min(end, DetourEnd(route, closest, end, config.max_detour_m));
  if (std::isfinite(config.max_gap_m)) {
    double gap_start = -1.0;
    for (std::size_t i = closest; i < end; ++i) {
      if (map.IsKnownFree(route[i].position.x(), route[i].position.y())) {
        gap_start = -1.0;
      } else if (gap_start < 0.0) {
        gap_start = route[i].progress_m;
      } else if (route[i].progress_m - gap_start > config.max_gap_m) {
        end = i;
        break;
      }
    }
  }
  return {closest, end};
}

}  // namespace

void LocalGoalSelection::Config::Validate() const {
  if (!(min_distance_m >= 0.0) || !std::isfinite(min_distance_m)) {
    throw std::invalid_argument("LocalGoalSelection::Config: min_distance_m must be >= 0, got " + std::to_string(min_distance_m));
  }
  if (!(lateral_offset_penalty >= 0.0) || !std::isfinite(lateral_offset_penalty)) {
    throw std::invalid_argument("LocalGoalSelection::Config: lateral_offset_penalty must be >= 0, got " +
                                std::to_string(lateral_offset_penalty));
  }
  if (!(max_gap_m > 0.0)) throw std::invalid_argument("LocalGoalSelection::Config: max_gap_m must be > 0");
  if (!(max_ahead_m > 0.0)) throw std::invalid_argument("LocalGoalSelection::Config: max_ahead_m must be > 0");
  if (!(max_detour_m > 0.0)) throw std::invalid_argument("LocalGoalSelection::Config: max_detour_m must be > 0");
  if (!(previous_goal_penalty >= 0.0) || !std::isfinite(previous_goal_penalty)) {
    throw std::invalid_argument("LocalGoalSelection::Config: previous_goal_penalty must be >= 0, got " +
                                std::to_string(previous_goal_penalty));
  }
  if (!(keep_previous_within_m >= 0.0) || !std::isfinite(keep_previous_within_m)) {
    throw std::invalid_argument("LocalGoalSelection::Config: keep_previous_within_m must be >= 0, got " +
                                std::to_string(keep_previous_within_m));
  }
  if (!(reach_offset_penalty >= 0.0) || !std::isfinite(reach_offset_penalty)) {
    throw std::invalid_argument("LocalGoalSelection::Config: reach_offset_penalty must be >= 0, got " +
                                std::to_string(reach_offset_penalty));
  }
  if (!(unknown_cost >= 1.0) || !(unknown_cost <= 100.0)) {
    throw std::invalid_argument("LocalGoalSelection::Config: unknown_cost must be in [1, 100], got " + std::to_string(unknown_cost));
  }
  if (!(reach_support_m > 0.0)) {
    throw std::invalid_argument("LocalGoalSelection::Config: reach_support_m must be > 0, got " + std::to_string(reach_support_m));
  }
  if (!(cell_m >= 0.1) || !(cell_m <= 5.0)) {
    throw std::invalid_argument("LocalGoalSelection::Config: cell_m must be in [0.1, 5], got " + std::to_string(cell_m));
  }
  if (!(end_zone_m >= 0.0) || !std::isfinite(end_zone_m)) {
    throw std::invalid_argument("LocalGoalSelection::Config: end_zone_m must be >= 0, got " + std::to_string(end_zone_m));
  }
  if (!(step_m >= 0.01) || !(step_m <= 5.0)) {
    throw std::invalid_argument("LocalGoalSelection::Config: step_m must be in [0.01, 5], got " + std::to_string(step_m));
  }
  for (double offset : lateral_offsets_m) {
    if (!(std::abs(offset) <= 50.0)) {
      throw std::invalid_argument("LocalGoalSelection::Config: lateral_offsets_m must lie within +-50 m, got " +
                                  std::to_string(offset));
    }
  }
}

std::vector<LocalGoal> SelectLocalGoals(const PlanningMap& map, const VehicleBox& vehicle,
                                        const std::vector<Eigen::Vector2d>& route_O,
                                        const Eigen::Isometry3d& T_L_O, const Pose2& vehicle_L,
                                        const LocalGoalSelection::Config& config, const std::optional<LocalGoal>& previous_L,
                                        std::size_t max_count, std::optional<double> vehicle_progress_m) {
  config.Validate();
  std::vector<LocalGoal> goals;
  const std::vector<RoutePoint> route = Resample(route_O, T_L_O, config.step_m);
  if (route.empty() || max_count == 0) return goals;
  const Eigen::Vector2d here(vehicle_L.x_m, vehicle_L.y_m);

  // "Ahead" starts at the vehicle's progress, or else at the route point closest to the vehicle, and
  // ends where the route has been outside known free space for more than max_gap_m.
  const auto [closest, end] = AheadRange(map, route, here, config, vehicle_progress_m);
  if (config.mode == LocalGoalSelection::Config::Mode::kReachable) {
    return internal::ReachableGoals(map, vehicle, route, closest, end, vehicle_L, config, previous_L).Select(max_count);
  }

  std::vector<double> offsets = {0.0};
  for (double d : config.lateral_offsets_m) {
    offsets.push_back(d);
    offsets.push_back(-d);
  }
  const auto qualifies = [&](const Pose2& pose, bool is_end) {
    if (!is_end && (Eigen::Vector2d(pose.x_m, pose.y_m) - here).norm() < config.min_distance_m) return false;
    if (!map.IsKnownFree(pose.x_m, pose.y_m)) return false;
    return !config.require_vehicle_fit || CheckPose(map, vehicle, pose) == PoseCheck::kValid;
  };
  // The farthest point that qualifies on the route and on each offset line beside it, ranked by
  // progress less the offset's penalty and detour (ties: the smaller offset, tried first).
  struct Scored {
    LocalGoal goal;
    double score;
  };
  // Near the route's end a point beside it is no nearer the end than the route point behind it: the
  // offset also counts by how much it lengthens the straight way to the end.
  const auto score_of = [&](double progress_m, double offset) {
    const double remaining = std::max(0.0, route.back().progress_m - progress_m);
    const double detour = std::hypot(remaining, offset) - remaining;
    return progress_m - config.lateral_offset_penalty * std::abs(offset) - detour;
  };
  std::vector<Scored> scored;
  for (double offset : offsets) {
    for (std::size_t i = end; i-- > closest;) {
      const RoutePoint& r = route[i];
      const Eigen::Vector2d side(-std::sin(r.yaw_rad), std::cos(r.yaw_rad));
      const Eigen::Vector2d p = r.position + offset * side;
      const bool is_end = offset == 0.0 && (r.is_end || route.back().progress_m - r.progress_m <= config.end_zone_m);
      const Pose2 pose{p.x(), p.y(), r.yaw_rad};
      if (qualifies(pose, is_end)) {
        scored.push_back({LocalGoal{pose, r.progress_m, is_end, offset}, score_of(r.progress_m, offset)});
        break;
      }
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.score > b.score; });
  if (previous_L && config.keep_previous_within_m > 0.0 && qualifies(previous_L->pose, previous_L->is_route_end) &&
      (scored.empty() || scored.front().score <= score_of(previous_L->route_progress_m, previous_L->lateral_offset_m) +
                                                    config.keep_previous_within_m)) {
    goals.push_back(*previous_L);
  }
  for (const Scored& s : scored) {
    if (goals.size() >= max_count) break;
    goals.push_back(s.goal);
  }
  return goals;
}

std::optional<LocalGoal> SelectLocalGoal(const PlanningMap& map, const VehicleBox& vehicle,
                                         const std::vector<Eigen::Vector2d>& route_O,
                                         const Eigen::Isometry3d& T_L_O, const Pose2& vehicle_L,
                                         const LocalGoalSelection::Config& config,
                                         const std::optional<LocalGoal>& previous_L) {
  const std::vector<LocalGoal> goals = SelectLocalGoals(map, vehicle, route_O, T_L_O, vehicle_L, config, previous_L, 1);
  if (goals.empty()) return std::nullopt;
  return goals.front();
}

double RouteProgress(const std::vector<Eigen::Vector2d>& route, const Eigen::Vector2d& p, double from_m,
                     double back_m, double ahead_m) {
  if (route.size() < 2) return 0.0;
  const double lo = from_m - back_m, hi = from_m + ahead_m;
  double best_d = std::numeric_limits<double>::infinity(), best_s = from_m;
  double s0 = 0.0;
  for (std::size_t i = 0; i + 1 < route.size(); ++i) {
    const Eigen::Vector2d a = route[i], ab = route[i + 1] - route[i];
    const double len = ab.norm();
    // The part of this leg inside the window, as parameters t in [t_lo, t_hi].
    const double t_lo = len > 0.0 ? std::max(0.0, (lo - s0) / len) : 0.0;
    const double t_hi = len > 0.0 ? std::min(1.0, (hi - s0) / len) : 1.0;
    if (t_lo <= t_hi && s0 <= hi && s0 + len >= lo) {
      const double t = len > 0.0 ? std::clamp((p - a).dot(ab) / (len * len), t_lo, t_hi) : 0.0;
      const double d = (a + t * ab - p).norm();
      if (d < best_d) best_d = d, best_s = s0 + t * len;
    }
    s0 += len;
  }
  return best_s;
}

}  // namespace ovpc::planner
