#include "ovpc/planner/route_tracker.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "ovpc/planner/local_goal.h"

namespace ovpc::planner {

RouteTracker::RouteTracker(std::vector<Eigen::Vector2d> route, const Config& config)
    : route_(std::move(route)), config_(config) {
  if (route_.size() < 2) throw std::invalid_argument("RouteTracker: a route needs at least two points");
  config_.Validate();
}

void RouteTracker::Config::Validate() const {
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!(back_m >= 0.0) || !(ahead_m > 0.0) || !(on_route_m > 0.0) || !(cut_ratio >= 0.0) || !finite(back_m) ||
      !finite(ahead_m) || !finite(on_route_m) || !finite(cut_ratio)) {
    throw std::invalid_argument("RouteTracker::Config: back_m >= 0, ahead_m > 0, on_route_m > 0 and cut_ratio >= 0, all finite");
  }
}

Eigen::Vector2d RouteTracker::PointAt(double s_m) const {
  double s0 = 0.0;
  for (std::size_t i = 0; i + 1 < route_.size(); ++i) {
    const Eigen::Vector2d ab = route_[i + 1] - route_[i];
    const double len = ab.norm();
    if (s_m <= s0 + len && len > 0.0) return route_[i] + std::max(0.0, s_m - s0) / len * ab;
    s0 += len;
  }
  return s_m <= 0.0 ? route_.front() : route_.back();
}

double RouteTracker::Update(const Eigen::Vector2d& p) {
  const double moved = has_last_ ? (p - last_).norm() : 0.0;
  last_ = p;
  has_last_ = true;
  const double windowed = RouteProgress(route_, p, progress_m_, config_.back_m, config_.ahead_m);
  if ((PointAt(windowed) - p).norm() <= config_.on_route_m) {
    off_route_m_ = 0.0;
    progress_m_ = windowed;
    return progress_m_;
  }
  // Off the route: where it rejoins it, if it has, within the route length a cut corner may skip.
  off_route_m_ += moved;
  const double rejoin =
      RouteProgress(route_, p, progress_m_, config_.back_m, config_.ahead_m + config_.cut_ratio * off_route_m_);
  if (rejoin > windowed && (PointAt(rejoin) - p).norm() <= config_.on_route_m) {
    off_route_m_ = 0.0;
    progress_m_ = rejoin;
  } else {
    progress_m_ = windowed;
  }
  return progress_m_;
}

}  // namespace ovpc::planner
