#include "reachable_goals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

#include "ovpc/planner/path.h"

namespace ovpc::planner::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

ReachableGoals::ReachableGoals(const PlanningMap& map, const VehicleBox& vehicle, const std::vector<RoutePoint>& route,
                               std::size_t closest, std::size_t end, const Pose2& vehicle_L,
                               const LocalGoalSelection::Config& config, const std::optional<LocalGoal>& previous_L)
    : map_(map), vehicle_(vehicle), route_(route), closest_(closest), end_(end), vehicle_L_(vehicle_L), config_(config),
      previous_L_(previous_L), here_(vehicle_L.x_m, vehicle_L.y_m), route_length_(route.back().progress_m) {}

std::vector<LocalGoal> ReachableGoals::Select(std::size_t max_count) {
  std::vector<LocalGoal> goals;
  if (!MakeGrid()) return goals;
  ClassifyCells();
  GrowBlocked();
  CostToGo();
  if (!Reach()) return goals;
  Score();
  AddRouteEndOrPrevious(&goals);
  AddBestCells(max_count, &goals);
  return goals;
}

// The grid covers the map and a border of unknown ground around it, at most kMaxCells a side.
bool ReachableGoals::MakeGrid() {
  bounds_ = map_.Bounds();
  if (!(bounds_.max_x_m >= bounds_.min_x_m) || !(bounds_.max_y_m >= bounds_.min_y_m)) return false;
  constexpr double kBorderM = 4.0;
  constexpr int kMaxCells = 400;
  cell_ = std::max(config_.cell_m, (std::max(bounds_.max_x_m - bounds_.min_x_m, bounds_.max_y_m - bounds_.min_y_m) +
                                    2 * kBorderM) / (kMaxCells - 1));
  x0_ = bounds_.min_x_m - kBorderM;
  y0_ = bounds_.min_y_m - kBorderM;
  nx_ = static_cast<int>((bounds_.max_x_m - bounds_.min_x_m + 2 * kBorderM) / cell_) + 1;
  ny_ = static_cast<int>((bounds_.max_y_m - bounds_.min_y_m + 2 * kBorderM) / cell_) + 1;
  return true;
}

bool ReachableGoals::CellOf(const Eigen::Vector2d& p, int* ix, int* iy) const {
  *ix = static_cast<int>(std::floor((p.x() - x0_) / cell_));
  *iy = static_cast<int>(std::floor((p.y() - y0_) / cell_));
  return *ix >= 0 && *iy >= 0 && *ix < nx_ && *iy < ny_;
}

// Cells: known traversable, known non-traversable (blocked) or unknown, from the ground projection
// of the cell's centre. Known ground with a map point over it in the vehicle's height band (above
// the ground clearance, below the mast's top) is overhead-blocked: the vehicle cannot be there, so
// neither the reach nor the cost to go passes under a roof too low for it. Known traversable comes
// from the nearest visible point; known non-traversable only from a point in the cell, so that a
// single steep vertex among sparse ground claims no cells around it.
void ReachableGoals::ClassifyCells() {
  VehicleBox column = vehicle_;
  column.length_m = column.width_m = cell_;
  column.centre_ahead_m = 0.0;
  column.margin_m = 0.0;
  column.footprint_check = VehicleBox::FootprintCheck::kWheels;
  state_.assign(static_cast<std::size_t>(nx_) * ny_, kUnknown);
  for (int iy = 0; iy < ny_; ++iy) {
    for (int ix = 0; ix < nx_; ++ix) {
      const Eigen::Vector2d c = Centre(ix, iy);
      if (!bounds_.Contains(c.x(), c.y())) continue;
      const std::optional<GroundPose> g = map_.Project(Pose2{c.x(), c.y(), 0.0});
      if (!g) continue;
      if (g->traversable) {
        // Known ground is ground a wheel could stand on: with the wheel rule, no farther from a
        // visible point than the wheel's support there (VehicleBox::WheelSupportAt).
        double support = config_.reach_support_m;
        if (vehicle_.footprint_check == VehicleBox::FootprintCheck::kWheels) {
          support = std::min(support, vehicle_.WheelSupportAt(c.norm()));
        }
        if ((g->surface_point.head<2>() - c).norm() <= support) {
          state_[Index(ix, iy)] = map_.CheckBox(*g, column) == PoseCheck::kCollision ? kOverhead : kFree;
        }
      } else if ((g->surface_point.head<2>() - c).cwiseAbs().maxCoeff() <= 0.5 * cell_) {
        state_[Index(ix, iy)] = kBlocked;
        blocking_.push_back(g->surface_point.head<2>());
        blocking_cell_.push_back(Index(ix, iy));
      }
    }
  }
}

// Cells the vehicle's centre cannot be in: within half its width and its margin of a
// non-traversable point (measured from the point itself, not from its cell: growing whole cells
// would close a lane between posts 2.7 m apart that the 1.5 m vehicle fits through). Overhead
// cells do not grow: a single stray return over the ground (an outlier the buffer kept) then costs
// a detour of one cell, not a vehicle's width.
void ReachableGoals::GrowBlocked() {
  blocked_.assign(state_.size(), 0);
  const double half_width = 0.5 * vehicle_.width_m + vehicle_.margin_m;
  const int grow = static_cast<int>(std::ceil(half_width / cell_)) + 1;
  for (std::size_t k = 0; k < blocking_.size(); ++k) {
    const int ix = static_cast<int>(blocking_cell_[k] % nx_), iy = static_cast<int>(blocking_cell_[k] / nx_);
    for (int dy = -grow; dy <= grow; ++dy) {
      for (int dx = -grow; dx <= grow; ++dx) {
        const int jx = ix + dx, jy = iy + dy;
        if (jx >= 0 && jy >= 0 && jx < nx_ && jy < ny_ && (Centre(jx, jy) - blocking_[k]).norm() <= half_width) {
          blocked_[Index(jx, jy)] = 1;
        }
      }
    }
  }
}

// Dijkstra over the 8-connected grid from the seeded (finite) cells, through the cells `passable`
// allows; unknown cells cost unknown_cost times their length.
void ReachableGoals::Dijkstra(std::vector<double>* cost, const std::function<bool(std::size_t)>& passable) const {
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
    const int ix = static_cast<int>(i % nx_), iy = static_cast<int>(i / nx_);
    for (const auto& step : kSteps) {
      const int jx = ix + step[0], jy = iy + step[1];
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      const std::size_t j = Index(jx, jy);
      if (!passable(j)) continue;
      const double next = c + cell_ * ((step[0] != 0 && step[1] != 0) ? std::sqrt(2.0) : 1.0) *
                                  (state_[j] == kUnknown ? config_.unknown_cost : 1.0);
      if (next < (*cost)[j]) {
        (*cost)[j] = next;
        open.push({next, j});
      }
    }
  }
}

// Cost to go: from the last route point ahead inside the grid (where the route leaves the map, or
// its end), its remaining route length; every other place counts its way to that point. Seeding
// every route point with its remaining length instead would make the foot of a wall across the
// route as good as the route beyond it. The cost to go goes round known non-traversable cells
// themselves (optimistic, like unknown ground); the vehicle's reach keeps half its width from them.
void ReachableGoals::CostToGo() {
  to_go_.assign(state_.size(), kInf);
  for (std::size_t i = end_; i-- > closest_;) {
    int ix, iy;
    if (!CellOf(route_[i].position, &ix, &iy) || Impassable(Index(ix, iy))) continue;
    to_go_[Index(ix, iy)] = route_length_ - route_[i].progress_m;
    break;
  }
  Dijkstra(&to_go_, [&](std::size_t j) { return !Impassable(j); });
}

// Reach: from the vehicle over known-traversable cells outside the grown blocked ones; the cells
// within a vehicle's width of the vehicle are passable whatever they are (it stands there).
// False when the vehicle is outside the grid.
bool ReachableGoals::Reach() {
  reach_.assign(state_.size(), kInf);
  int vx, vy;
  if (!CellOf(here_, &vx, &vy)) return false;
  reach_[Index(vx, vy)] = 0.0;
  Dijkstra(&reach_, [&](std::size_t j) {
    if (state_[j] == kFree && !blocked_[j]) return true;
    return !Impassable(j) && (CentreOf(j) - here_).norm() <= vehicle_.width_m;
  });
  return true;
}

bool ReachableGoals::Qualifies(const Pose2& pose, bool is_end, const VehicleBox* vehicle) const {
  if (!is_end && (Eigen::Vector2d(pose.x_m, pose.y_m) - here_).norm() < config_.min_distance_m) return false;
  if (!map_.IsKnownFree(pose.x_m, pose.y_m)) return false;
  return !config_.require_vehicle_fit || CheckPose(map_, vehicle ? *vehicle : vehicle_, pose) == PoseCheck::kValid;
}

// The ground under the front wheels of `pose`, by the map's plane fit over its neighbourhood
// (PlanningMap::ProjectForBox), slopes at most max_tilt_deg: a look does not put the front wheels on
// a face that a noisy face test lets through at its top, where the fit over a patch sees its slope.
bool ReachableGoals::FrontOnSlopeWithinTilt(const Pose2& pose) const {
  const double cos_max = std::cos(vehicle_.max_tilt_deg * kPi / 180.0);
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  for (double side : {-0.5 * vehicle_.track_m, 0.5 * vehicle_.track_m}) {
    const Pose2 wheel{pose.x_m + vehicle_.wheelbase_m * c - side * s, pose.y_m + vehicle_.wheelbase_m * s + side * c,
                      pose.yaw_rad};
    const std::optional<GroundPose> ground = map_.ProjectForBox(wheel);
    if (!ground || ground->T_L_B.linear()(2, 2) < cos_max) return false;
  }
  return true;
}

double ReachableGoals::OffRoute(const Eigen::Vector2d& p) const {
  double best = kInf;
  for (const Eigen::Vector2d& r : route_ahead_) best = std::min(best, (r - p).squaredNorm());
  return route_ahead_.empty() ? 0.0 : std::sqrt(best);
}

// Score of each reached cell: cost to go, plus reach_offset_penalty per metre away from the route
// ahead (sampled every metre), plus previous_goal_penalty per metre from the previous goal.
void ReachableGoals::Score() {
  if (config_.reach_offset_penalty > 0.0) {
    for (std::size_t i = closest_; i < end_; i += 4) route_ahead_.push_back(route_[i].position);
    if (end_ > closest_) route_ahead_.push_back(route_[end_ - 1].position);
  }
  score_.assign(state_.size(), kInf);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (!std::isfinite(reach_[i]) || !std::isfinite(to_go_[i])) continue;
    const Eigen::Vector2d c = CentreOf(i);
    score_[i] = to_go_[i] + config_.reach_offset_penalty * OffRoute(c);
    if (previous_L_ && config_.previous_goal_penalty > 0.0) {
      score_[i] += config_.previous_goal_penalty * (c - Eigen::Vector2d(previous_L_->pose.x_m, previous_L_->pose.y_m)).norm();
    }
    order_.push_back(i);
  }
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return score_[a] < score_[b]; });
  best_score_ = order_.empty() ? kInf : score_[order_.front()];
}

double ReachableGoals::CostAt(const Eigen::Vector2d& p, const std::vector<double>& field) const {
  int ix, iy;
  return CellOf(p, &ix, &iy) ? field[Index(ix, iy)] : kInf;
}

// The route's end, when it is reached, and else the previous goal, when it is still nearly as good.
void ReachableGoals::AddRouteEndOrPrevious(std::vector<LocalGoal>* goals) const {
  if (route_.back().is_end && end_ == route_.size()) {
    const RoutePoint& r = route_.back();
    const Pose2 pose{r.position.x(), r.position.y(), r.yaw_rad};
    if (std::isfinite(CostAt(r.position, reach_)) && Qualifies(pose, true)) goals->push_back({pose, r.progress_m, true});
  }
  if (goals->empty() && previous_L_ && config_.keep_previous_within_m > 0.0) {
    const Eigen::Vector2d p(previous_L_->pose.x_m, previous_L_->pose.y_m);
    if (std::isfinite(CostAt(p, reach_)) && CostAt(p, score_) <= best_score_ + config_.keep_previous_within_m &&
        Qualifies(previous_L_->pose, previous_L_->is_route_end)) {
      goals->push_back(*previous_L_);
    }
  }
}

// Only cells inside the known region, not on its rim: the rim of what is known is where sparse
// ground comes and goes from one map update to the next. (Known, not reached: a lane between posts
// may be one cell wide in the reach.)
bool ReachableGoals::Interior(int ix, int iy, int rim) const {
  for (int dy = -rim; dy <= rim; ++dy) {
    for (int dx = -rim; dx <= rim; ++dx) {
      const int jx = ix + dx, jy = iy + dy;
      if (!(jx >= 0 && jy >= 0 && jx < nx_ && jy < ny_ && state_[Index(jx, jy)] != kUnknown)) return false;
    }
  }
  return true;
}

// Heading: towards the cell with the least cost to go within `around` cells (a wide stencil, so
// that the heading does not jump between the eight grid directions).
double ReachableGoals::DownhillYaw(std::size_t i, int ix, int iy, int around) const {
  double best = to_go_[i], yaw = vehicle_L_.yaw_rad;
  for (int dy = -around; dy <= around; ++dy) {
    for (int dx = -around; dx <= around; ++dx) {
      const int jx = ix + dx, jy = iy + dy;
      if ((dx == 0 && dy == 0) || jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_ || dx * dx + dy * dy > around * around) continue;
      const double v = to_go_[Index(jx, jy)];
      if (v < best) best = v, yaw = std::atan2(static_cast<double>(dy), static_cast<double>(dx));
    }
  }
  return yaw;
}

// Candidates: reached cells by score, at least kMinSpacingM from each goal already taken, inside
// the known region, each with the heading down the cost-to-go field; at most kMaxChecked tried.
void ReachableGoals::AddBestCells(std::size_t max_count, std::vector<LocalGoal>* goals) const {
  constexpr std::size_t kMaxChecked = 400;
  constexpr double kMinSpacingM = 2.0;
  constexpr double kInteriorM = 0.5;
  constexpr double kHeadingM = 2.5;
  const int rim = static_cast<int>(std::ceil(kInteriorM / cell_));
  const int around = static_cast<int>(std::ceil(kHeadingM / cell_));
  std::size_t checked = 0;
  bool look_open = config_.look_at_rim && goals->empty();
  for (std::size_t i : order_) {
    if (goals->size() >= max_count || checked >= kMaxChecked) break;
    const int ix = static_cast<int>(i % nx_), iy = static_cast<int>(i / nx_);
    const Eigen::Vector2d c = Centre(ix, iy);
    if (std::any_of(goals->begin(), goals->end(), [&](const LocalGoal& g) {
          return (Eigen::Vector2d(g.pose.x_m, g.pose.y_m) - c).norm() < kMinSpacingM;
        })) {
      continue;
    }
    if (!Interior(ix, iy, rim)) continue;
    const double yaw = DownhillYaw(i, ix, iy, around);
    ++checked;
    const Pose2 pose{c.x(), c.y(), NormalizeYaw(yaw)};
    const double progress = std::max(0.0, route_length_ - to_go_[i]);
    if (look_open) {
      // The best place the vehicle fits may be nearer than min_distance_m: the map's seen ground
      // ends just ahead (a crest, an edge). That place is a candidate too, to be looked from, in
      // its turn among the farther ones (tried when they give no path: the places along a crest
      // that are blocked on the next map). Taking it first, before them, passed descent_20 five
      // times of ten, in its turn ten of ten (docs/notes/descents.md).
      // The place fits with its wheels kLookMarginM short of the rim: the vehicle fits there moved
      // that far ahead too, so the wheels stand on ground seen well, not on the rim's sparse points.
      // Nearer is better for the look itself: below a crest the ramp is seen at a grazing angle,
      // about one return a voxel from 3.2 m back, and the two-hit filter drops it; 0.4 m nearer
      // the rays meet it half again as steeply. With 0.8 m a 22 degree descent and descent_20
      // arrived in 32 of 36 runs (seeds 1-18), rocking at the crest; with 0.4 m in 36 of 36, and
      // 16 % sooner (docs/notes/descents.md). The edge test below still holds every wheel 0.2 m
      // short of the last seen ground; what put a wheel over a ditch's lip with 0.4 m was the
      // follower's drift off a kept path, which the navigator's rollout now checks.
      constexpr double kLookMarginM = 0.4;
      const Pose2 ahead{pose.x_m + kLookMarginM * std::cos(pose.yaw_rad), pose.y_m + kLookMarginM * std::sin(pose.yaw_rad),
                        pose.yaw_rad};
      // There every wheel has seen ground beyond it (the edge test, kLookEdgeM) and a visible point
      // within kLookSupportM: at a ditch or a drop the wheel-support radius alone would let a front
      // wheel stand half a metre past the last seen ground. The front wheels' ground, by a plane
      // fitted over their neighbourhood, slopes within max_tilt_deg: a steep face seen sparsely,
      // whose top faces a noisy face test lets through, put a front wheel 0.38 m onto a 33 degree
      // face (docs/notes/descents.md).
      constexpr double kLookEdgeM = 0.2;
      constexpr double kLookSupportM = 0.25;
      VehicleBox careful = vehicle_;
      careful.edge_tolerance_m = std::min(careful.edge_tolerance_m, kLookEdgeM);
      careful.wheel_support_m = std::min(careful.wheel_support_m, kLookSupportM);
      if (Qualifies(pose, true) && Qualifies(ahead, true, &careful) && FrontOnSlopeWithinTilt(ahead)) {
        look_open = false;
        // Within kLookReachedM the vehicle is there already: it looks by standing, and a goal that
        // near at another heading would only make it manoeuvre at the rim.
        constexpr double kLookReachedM = 1.0;
        const double away = (c - here_).norm();
        if (away < config_.min_distance_m) {
          if (away < kLookReachedM) continue;
          LocalGoal look{pose, progress, false};
          look.is_look = true;
          goals->push_back(look);
          continue;
        }
      }
    }
    if (Qualifies(pose, false)) goals->push_back({pose, progress, false});
  }
}

}  // namespace ovpc::planner::internal
