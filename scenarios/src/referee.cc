#include "ovpc/scenarios/referee.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "ovpc/planner/local_goal.h"
#include "format.h"

namespace ovpc::scenarios {
namespace {

using internal::Fixed;

void RollPitchDeg(const Eigen::Isometry3d& T, double* roll_deg, double* pitch_deg) {
  const Eigen::Matrix3d& R = T.linear();
  *pitch_deg = RadToDeg(std::asin(std::clamp(-R(2, 0), -1.0, 1.0)));
  *roll_deg = RadToDeg(std::atan2(R(2, 1), R(2, 2)));
}

bool Inside(const Vec3& p, const Region& r) {
  return p.x() >= r.min_m.x() && p.x() <= r.max_m.x() && p.y() >= r.min_m.y() && p.y() <= r.max_m.y();
}

// Does the vehicle footprint at the true pose touch the region? Checked on a grid of footprint points.
bool FootprintInRegion(const Eigen::Isometry3d& T_W_B, const sim::GatorParams& v, const Region& r) {
  const double x0 = -v.rear_overhang_m, x1 = v.length_m - v.rear_overhang_m;
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 2; ++j) {
      const Vec3 p_B(x0 + (x1 - x0) * i / 4.0, -v.width_m / 2 + v.width_m * j / 2.0, 0.0);
      const Vec3 p = T_W_B * p_B;
      if (Inside(p, r)) return true;
    }
  }
  return false;
}

// The wheels' contact points at the true pose (frame B: the rear axle's middle on the ground).
std::array<Vec3, 4> WheelContacts(const Eigen::Isometry3d& T_W_B, const sim::GatorParams& v) {
  return {T_W_B * Vec3(0.0, -0.5 * v.track_m, 0.0), T_W_B * Vec3(0.0, 0.5 * v.track_m, 0.0),
          T_W_B * Vec3(v.wheelbase_m, -0.5 * v.track_m, 0.0), T_W_B * Vec3(v.wheelbase_m, 0.5 * v.track_m, 0.0)};
}

// Does a wheel's contact point lie inside the region?
bool WheelInRegion(const Eigen::Isometry3d& T_W_B, const sim::GatorParams& v, const Region& r) {
  const auto wheels = WheelContacts(T_W_B, v);
  return std::any_of(wheels.begin(), wheels.end(), [&r](const Vec3& p) { return Inside(p, r); });
}

// Does a wheel's contact point lie outside the terrain's extent (centred on the origin)? A body
// overhanging the edge stands; a wheel past it drops.
bool WheelOffTerrain(const Eigen::Isometry3d& T_W_B, const sim::GatorParams& v, const sim::TerrainConfig& t) {
  const Region inside{"terrain", Eigen::Vector2d(-0.5 * t.size_x_m, -0.5 * t.size_y_m),
                      Eigen::Vector2d(0.5 * t.size_x_m, 0.5 * t.size_y_m)};
  const auto wheels = WheelContacts(T_W_B, v);
  return std::any_of(wheels.begin(), wheels.end(), [&inside](const Vec3& p) { return !Inside(p, inside); });
}

// The route length at the route point nearest `p`; of points about as near, the last along the
// route (a lap's goal is at its end, not at its start).
double LastNearestProgress(const std::vector<Eigen::Vector2d>& route, const Eigen::Vector2d& p) {
  double best_d = std::numeric_limits<double>::infinity(), best_s = 0.0, s0 = 0.0;
  for (std::size_t i = 0; i + 1 < route.size(); ++i) {
    const Eigen::Vector2d ab = route[i + 1] - route[i];
    const double len = ab.norm();
    const double t = len > 0.0 ? std::clamp((p - route[i]).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
    const double d = (route[i] + t * ab - p).norm();
    if (d <= best_d + 1e-6) {
      best_d = std::min(best_d, d);
      best_s = s0 + t * len;
    }
    s0 += len;
  }
  return best_s;
}

}  // namespace

Referee::Referee(const Scenario& scenario, const sim::GatorParams& vehicle, const Eigen::Isometry3d& T_W_B)
    : scenario_(scenario),
      vehicle_(vehicle),
      last_position_(T_W_B.translation()),
      route_(scenario.route_m),
      region_entered_(scenario.criteria.forbidden.size(), false) {
  if (scenario.criteria.goal_m) goal_progress_m_ = LastNearestProgress(scenario.route_m, *scenario.criteria.goal_m);
}

void Referee::Observe(double time_s, const Eigen::Isometry3d& T_W_B, const std::vector<sim::BodyContact>& contacts) {
  distance_m_ += (T_W_B.translation() - last_position_).norm();
  last_position_ = T_W_B.translation();
  double roll, pitch;
  RollPitchDeg(T_W_B, &roll, &pitch);
  max_roll_deg_ = std::max(max_roll_deg_, std::abs(roll));
  max_pitch_deg_ = std::max(max_pitch_deg_, std::abs(pitch));
  const Eigen::Vector2d xy = T_W_B.translation().head<2>();
  // In the route's order (a route that comes back beside itself is not done from its way out); a
  // vehicle that cut a corner is scored from where it rejoins the route.
  best_progress_m_ = std::max(best_progress_m_, route_.Update(xy));
  if (!contacts.empty()) {
    ++collision_steps_;
    if (collisions_.size() < 5) {
      collisions_.push_back("t=" + Fixed(time_s, 2) + " s: " + contacts.front().vehicle_geom + " touched " +
                            contacts.front().world_geom);
    }
  }
  if (!off_terrain_ && WheelOffTerrain(T_W_B, vehicle_, scenario_.sim.world.terrain)) off_terrain_ = true;
  for (std::size_t i = 0; i < region_entered_.size(); ++i) {
    const Region& r = scenario_.criteria.forbidden[i];
    if (!region_entered_[i] && (r.by == Region::By::kWheels ? WheelInRegion(T_W_B, vehicle_, r) : FootprintInRegion(T_W_B, vehicle_, r))) {
      region_entered_[i] = true;
    }
  }
}

bool Referee::GoalReached(double time_s, const Eigen::Isometry3d& T_W_B) {
  const Criteria& c = scenario_.criteria;
  if (!c.goal_m || (T_W_B.translation().head<2>() - *c.goal_m).norm() > c.goal_radius_m) return false;
  // Within the goal radius of the goal's place on the route, and the route tracker's slack.
  if (best_progress_m_ < goal_progress_m_ - c.goal_radius_m - planner::RouteTracker::Config{}.on_route_m) return false;
  goal_time_s_ = time_s;
  return true;
}

void Referee::Score(RunResult* result) const {
  result->distance_m = distance_m_;
  result->route_progress_m = best_progress_m_;
  result->collision_steps = collision_steps_;
  result->collisions = collisions_;
  const Criteria& c = scenario_.criteria;
  auto add = [&](std::string name, std::string expected, std::string actual, bool passed) {
    result->criteria.push_back({std::move(name), std::move(expected), std::move(actual), passed});
  };
  if (c.goal_m) {
    const double d = (Eigen::Vector2d(last_position_.head<2>()) - *c.goal_m).norm();
    // At the goal's place but not there along the route (it skipped legs): say so, not just "0 m away".
    std::string actual = "no, " + Fixed(d, 1) + " m away";
    if (goal_time_s_) {
      actual = "at t=" + Fixed(*goal_time_s_, 1) + " s";
    } else if (d <= c.goal_radius_m) {
      actual += ", but it followed the route only " + Fixed(best_progress_m_, 1) + " of the goal's " + Fixed(goal_progress_m_, 1) + " m";
    }
    add("goal_reached", "within " + Fixed(c.goal_radius_m, 1) + " m of (" + Fixed(c.goal_m->x(), 1) + ", " + Fixed(c.goal_m->y(), 1) + ")",
        actual, goal_time_s_.has_value());
  }
  if (c.no_collision) {
    add("no_collision", "0 body contacts", collision_steps_ == 0 ? "none" : collisions_.front(), collision_steps_ == 0);
  }
  if (c.max_roll_deg) {
    add("max_roll", "<= " + Fixed(*c.max_roll_deg, 1) + " deg", Fixed(max_roll_deg_, 1) + " deg", max_roll_deg_ <= *c.max_roll_deg);
  }
  if (c.max_pitch_deg) {
    add("max_pitch", "<= " + Fixed(*c.max_pitch_deg, 1) + " deg", Fixed(max_pitch_deg_, 1) + " deg",
        max_pitch_deg_ <= *c.max_pitch_deg);
  }
  if (c.max_time_s) {
    add("completion_time", "<= " + Fixed(*c.max_time_s, 0) + " s", goal_time_s_ ? Fixed(*goal_time_s_, 1) + " s" : "not completed",
        goal_time_s_ && *goal_time_s_ <= *c.max_time_s);
  }
  if (c.min_progress_m) {
    add("min_progress", ">= " + Fixed(*c.min_progress_m, 1) + " m", Fixed(best_progress_m_, 1) + " m",
        best_progress_m_ >= *c.min_progress_m);
  }
  add("on_terrain", "no wheel over the terrain's edge", off_terrain_ ? "a wheel went over the edge" : "stayed on", !off_terrain_);
  for (std::size_t i = 0; i < c.forbidden.size(); ++i) {
    add("never_enter:" + c.forbidden[i].name, "never entered", region_entered_[i] ? "entered" : "never entered",
        !region_entered_[i]);
  }
  result->passed = std::all_of(result->criteria.begin(), result->criteria.end(), [](const CriterionResult& r) { return r.passed; });
}

}  // namespace ovpc::scenarios
