#include "ovpc/planner/local_goal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <stdexcept>
#include <string>

namespace ovpc::planner {
namespace {

struct RoutePoint {
  Eigen::Vector2d position;
  double yaw_rad;
  double progress_m;
  bool is_end;
};

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

// The kReachable goals (see LocalGoalSelection::Config::Mode).
std::vector<LocalGoal> SelectReachableGoals(const PlanningMap& map, const VehicleBox& vehicle,
                                            const std::vector<RoutePoint>& route, std::size_t closest, std::size_t end,
                                            const Pose2& vehicle_L, const LocalGoalSelection::Config& config,
                                            const std::optional<LocalGoal>& previous_L, std::size_t max_count) {
  std::vector<LocalGoal> goals;
  const MapBounds bounds = map.Bounds();
  if (!(bounds.max_x_m >= bounds.min_x_m) || !(bounds.max_y_m >= bounds.min_y_m)) return goals;
  // The grid covers the map and a border of unknown ground around it, at most kMaxCells a side.
  constexpr double kBorderM = 4.0;
  constexpr int kMaxCells = 400;
  const double cell = std::max(config.cell_m, (std::max(bounds.max_x_m - bounds.min_x_m, bounds.max_y_m - bounds.min_y_m) +
                                               2 * kBorderM) / (kMaxCells - 1));
  const double x0 = bounds.min_x_m - kBorderM, y0 = bounds.min_y_m - kBorderM;
  const int nx = static_cast<int>((bounds.max_x_m - bounds.min_x_m + 2 * kBorderM) / cell) + 1;
  const int ny = static_cast<int>((bounds.max_y_m - bounds.min_y_m + 2 * kBorderM) / cell) + 1;
  const auto index = [nx](int ix, int iy) { return static_cast<std::size_t>(iy) * nx + ix; };
  const auto centre = [&](int ix, int iy) { return Eigen::Vector2d(x0 + (ix + 0.5) * cell, y0 + (iy + 0.5) * cell); };
  const auto cell_of = [&](const Eigen::Vector2d& p, int* ix, int* iy) {
    *ix = static_cast<int>(std::floor((p.x() - x0) / cell));
    *iy = static_cast<int>(std::floor((p.y() - y0) / cell));
    return *ix >= 0 && *iy >= 0 && *ix < nx && *iy < ny;
  };

  // Cells: known traversable, known non-traversable (blocked) or unknown, from the ground projection
  // of the cell's centre; blocked cells grow by half the vehicle's width. Known ground with a map
  // point over it in the vehicle's height band (above the ground clearance, below the mast's top) is
  // overhead-blocked: the vehicle cannot be there, so neither the reach nor the cost to go passes
  // under a roof too low for it. These cells do not grow: a single stray return over the ground
  // (an outlier the buffer kept) then costs a detour of one cell, not a vehicle's width.
  enum : std::uint8_t { kUnknown, kFree, kBlocked, kOverhead };
  VehicleBox column = vehicle;
  column.length_m = column.width_m = cell;
  column.centre_ahead_m = 0.0;
  column.margin_m = 0.0;
  column.footprint_check = VehicleBox::FootprintCheck::kWheels;
  std::vector<std::uint8_t> state(static_cast<std::size_t>(nx) * ny, kUnknown);
  std::vector<Eigen::Vector2d> blocking;  // the non-traversable point of each kBlocked cell
  std::vector<std::size_t> blocking_cell;
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      const Eigen::Vector2d c = centre(ix, iy);
      if (!bounds.Contains(c.x(), c.y())) continue;
      const std::optional<GroundPose> g = map.Project(Pose2{c.x(), c.y(), 0.0});
      if (!g) continue;
      // Known traversable from the nearest visible point; known non-traversable only from a point
      // in the cell: a single steep vertex among sparse ground claims no cells around it.
      if (g->traversable) {
        if ((g->surface_point.head<2>() - c).norm() <= config.reach_support_m) {
          state[index(ix, iy)] = map.CheckBox(*g, column) == PoseCheck::kCollision ? kOverhead : kFree;
        }
      } else if ((g->surface_point.head<2>() - c).cwiseAbs().maxCoeff() <= 0.5 * cell) {
        state[index(ix, iy)] = kBlocked;
        blocking.push_back(g->surface_point.head<2>());
        blocking_cell.push_back(index(ix, iy));
      }
    }
  }
  const auto impassable = [&state](std::size_t j) { return state[j] == kBlocked || state[j] == kOverhead; };
  // Cells the vehicle's centre cannot be in: within half its width and its margin of a
  // non-traversable point (measured from the point itself, not from its cell: growing whole cells
  // would close a lane between posts 2.7 m apart that the 1.5 m vehicle fits through).
  std::vector<std::uint8_t> blocked(state.size(), 0);
  const double half_width = 0.5 * vehicle.width_m + vehicle.margin_m;
  const int grow = static_cast<int>(std::ceil(half_width / cell)) + 1;
  for (std::size_t k = 0; k < blocking.size(); ++k) {
    const int ix = static_cast<int>(blocking_cell[k] % nx), iy = static_cast<int>(blocking_cell[k] / nx);
    for (int dy = -grow; dy <= grow; ++dy) {
      for (int dx = -grow; dx <= grow; ++dx) {
        const int jx = ix + dx, jy = iy + dy;
        if (jx >= 0 && jy >= 0 && jx < nx && jy < ny && (centre(jx, jy) - blocking[k]).norm() <= half_width) {
          blocked[index(jx, jy)] = 1;
        }
      }
    }
  }

  // Dijkstra over the 8-connected grid from seeded cells, through the cells `passable` allows.
  const auto dijkstra = [&](std::vector<double>* cost, const std::function<bool(std::size_t)>& passable) {
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    for (std::size_t i = 0; i < cost->size(); ++i) {
      if (std::isfinite((*cost)[i])) open.push({(*cost)[i], i});
    }
    static constexpr std::array<std::array<int, 2>, 8> kSteps = {
        {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}};
    while (!open.empty()) {
      const auto [c, i] = open.top();
      open.pop();
      if (c > (*cost)[i]) continue;
      const int ix = static_cast<int>(i % nx), iy = static_cast<int>(i / nx);
      for (const auto& step : kSteps) {
        const int jx = ix + step[0], jy = iy + step[1];
        if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) continue;
        const std::size_t j = index(jx, jy);
        if (!passable(j)) continue;
        const double next = c + cell * ((step[0] != 0 && step[1] != 0) ? std::sqrt(2.0) : 1.0) *
                                    (state[j] == kUnknown ? config.unknown_cost : 1.0);
        if (next < (*cost)[j]) {
          (*cost)[j] = next;
          open.push({next, j});
        }
      }
    }
  };
  const double inf = std::numeric_limits<double>::infinity();
  // Cost to go: from the last route point ahead inside the grid (where the route leaves the map, or
  // its end), its remaining route length; every other place counts its way to that point. Seeding
  // every route point with its remaining length instead would make the foot of a wall across the
  // route as good as the route beyond it.
  const double route_length = route.back().progress_m;
  std::vector<double> to_go(state.size(), inf);
  for (std::size_t i = end; i-- > closest;) {
    int ix, iy;
    if (!cell_of(route[i].position, &ix, &iy) || impassable(index(ix, iy))) continue;
    to_go[index(ix, iy)] = route_length - route[i].progress_m;
    break;
  }
  // The cost to go goes round known non-traversable cells themselves (optimistic, like unknown
  // ground); the vehicle's reach keeps half its width from them.
  dijkstra(&to_go, [&](std::size_t j) { return !impassable(j); });
  // Reach: from the vehicle over known-traversable cells outside the grown blocked ones; the cells
  // within a vehicle's width of the vehicle are passable whatever they are (it stands there).
  const Eigen::Vector2d here(vehicle_L.x_m, vehicle_L.y_m);
  std::vector<double> reach(state.size(), inf);
  int vx, vy;
  if (!cell_of(here, &vx, &vy)) return goals;
  reach[index(vx, vy)] = 0.0;
  dijkstra(&reach, [&](std::size_t j) {
    if (state[j] == kFree && !blocked[j]) return true;
    const Eigen::Vector2d c = centre(static_cast<int>(j % nx), static_cast<int>(j / nx));
    return !impassable(j) && (c - here).norm() <= vehicle.width_m;
  });

  // Candidates: reached cells by cost to go, each with the heading down the cost-to-go field.
  const auto qualifies = [&](const Pose2& pose, bool is_end) {
    if (!is_end && (Eigen::Vector2d(pose.x_m, pose.y_m) - here).norm() < config.min_distance_m) return false;
    if (!map.IsKnownFree(pose.x_m, pose.y_m)) return false;
    return !config.require_vehicle_fit || CheckPose(map, vehicle, pose) == PoseCheck::kValid;
  };
  // Score: cost to go plus reach_offset_penalty per metre away from the route ahead (sampled every
  // metre).
  std::vector<Eigen::Vector2d> route_ahead;
  if (config.reach_offset_penalty > 0.0) {
    for (std::size_t i = closest; i < end; i += 4) route_ahead.push_back(route[i].position);
    if (end > closest) route_ahead.push_back(route[end - 1].position);
  }
  const auto off_route = [&](const Eigen::Vector2d& p) {
    double best = inf;
    for (const Eigen::Vector2d& r : route_ahead) best = std::min(best, (r - p).squaredNorm());
    return route_ahead.empty() ? 0.0 : std::sqrt(best);
  };
  std::vector<double> score(state.size(), inf);
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (!std::isfinite(reach[i]) || !std::isfinite(to_go[i])) continue;
    const Eigen::Vector2d c = centre(static_cast<int>(i % nx), static_cast<int>(i / nx));
    score[i] = to_go[i] + config.reach_offset_penalty * off_route(c);
    if (previous_L && config.previous_goal_penalty > 0.0) {
      score[i] += config.previous_goal_penalty * (c - Eigen::Vector2d(previous_L->pose.x_m, previous_L->pose.y_m)).norm();
    }
    order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] < score[b]; });
  const double best_score = order.empty() ? inf : score[order.front()];

  // The route's end, when it is reached, and the previous goal, when it is still nearly as good.
  const auto cost_at = [&](const Eigen::Vector2d& p, const std::vector<double>& field) {
    int ix, iy;
    return cell_of(p, &ix, &iy) ? field[index(ix, iy)] : inf;
  };
  if (route.back().is_end && end == route.size()) {
    const RoutePoint& r = route.back();
    const Pose2 pose{r.position.x(), r.position.y(), r.yaw_rad};
    if (std::isfinite(cost_at(r.position, reach)) && qualifies(pose, true)) goals.push_back({pose, r.progress_m, true});
  }
  if (goals.empty() && previous_L && config.keep_previous_within_m > 0.0) {
    const Eigen::Vector2d p(previous_L->pose.x_m, previous_L->pose.y_m);
    if (std::isfinite(cost_at(p, reach)) && cost_at(p, score) <= best_score + config.keep_previous_within_m &&
        qualifies(previous_L->pose, previous_L->is_route_end)) {
      goals.push_back(*previous_L);
    }
  }
  constexpr std::size_t kMaxChecked = 400;
  constexpr double kMinSpacingM = 2.0;
  constexpr double kInteriorM = 0.5;
  constexpr double kHeadingM = 2.5;
  const int rim = static_cast<int>(std::ceil(kInteriorM / cell));
  const int around = static_cast<int>(std::ceil(kHeadingM / cell));
  std::size_t checked = 0;
  for (std::size_t i : order) {
    if (goals.size() >= max_count || checked >= kMaxChecked) break;
    const int ix = static_cast<int>(i % nx), iy = static_cast<int>(i / nx);
    const Eigen::Vector2d c = centre(ix, iy);
    if (std::any_of(goals.begin(), goals.end(), [&](const LocalGoal& g) {
          return (Eigen::Vector2d(g.pose.x_m, g.pose.y_m) - c).norm() < kMinSpacingM;
        })) {
      continue;
    }
    // Only cells inside the known region, not on its rim: the rim of what is known is where
    // sparse ground comes and goes from one map update to the next. (Known, not reached: a lane
    // between posts may be one cell wide in the reach.)
    bool interior = true;
    for (int dy = -rim; dy <= rim && interior; ++dy) {
      for (int dx = -rim; dx <= rim && interior; ++dx) {
        const int jx = ix + dx, jy = iy + dy;
        interior = jx >= 0 && jy >= 0 && jx < nx && jy < ny && state[index(jx, jy)] != kUnknown;
      }
    }
    if (!interior) continue;
    // Heading: towards the cell with the least cost to go within kHeadingM (a wide stencil, so that
    // the heading does not jump between the eight grid directions).
    double best = to_go[i], yaw = vehicle_L.yaw_rad;
    for (int dy = -around; dy <= around; ++dy) {
      for (int dx = -around; dx <= around; ++dx) {
        const int jx = ix + dx, jy = iy + dy;
        if ((dx == 0 && dy == 0) || jx < 0 || jy < 0 || jx >= nx || jy >= ny || dx * dx + dy * dy > around * around) continue;
        const double v = to_go[index(jx, jy)];
        if (v < best) best = v, yaw = std::atan2(static_cast<double>(dy), static_cast<double>(dx));
      }
    }
    ++checked;
    const Pose2 pose{c.x(), c.y(), NormalizeYaw(yaw)};
    if (qualifies(pose, false)) goals.push_back({pose, std::max(0.0, route_length - to_go[i]), false});
  }
  return goals;
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
    return SelectReachableGoals(map, vehicle, route, closest, end, vehicle_L, config, previous_L, max_count);
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
