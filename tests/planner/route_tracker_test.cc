// Progress along a route in its order: U-turns, laps side by side, a figure of eight, cut corners.
#include "ovpc/planner/route_tracker.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ovpc::planner {
namespace {

// Out 18 m along y = 0, a U-turn, back along a lane 8 m to the side (the route of 44 m).
std::vector<Eigen::Vector2d> UTurn() { return {{0, 0}, {18, 0}, {18, 8}, {0, 8}}; }

// Drives `tracker` from a to b in steps of 0.1 m; returns the last progress.
double Drive(RouteTracker* tracker, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int n = static_cast<int>(std::ceil((b - a).norm() / 0.1));
  double s = tracker->progress_m();
  for (int i = 1; i <= n; ++i) s = tracker->Update(a + (b - a) * (static_cast<double>(i) / n));
  return s;
}

TEST(RouteTrackerTest, FollowsAUTurnLegByLeg) {
  RouteTracker t(UTurn());
  EXPECT_NEAR(Drive(&t, {0, 0}, {17, 0}), 17.0, 1e-9);
  EXPECT_NEAR(Drive(&t, {17, 0}, {18, 0.5}), 18.5, 0.2);
  EXPECT_NEAR(Drive(&t, {18, 0.5}, {18, 8}), 26.0, 1e-9);
  EXPECT_NEAR(Drive(&t, {18, 8}, {0, 8}), 44.0, 1e-9);
}

TEST(RouteTrackerTest, OnTheWayOutTheReturnLaneBesideItDoesNotCount) {
  // Driving the outbound leg 1 m to the side (towards the return lane) stays on the outbound leg.
  RouteTracker t(UTurn());
  EXPECT_NEAR(Drive(&t, {0, 1}, {10, 1}), 10.0, 1e-9);
}

TEST(RouteTrackerTest, ACutCornerIsScoredFromWhereItRejoinsTheRoute) {
  // The vehicle turns back 10 m before the route's turn and crosses straight to the return lane,
  // skipping 20 m of the route (what the planner does when the return lane's cost to go is less).
  RouteTracker t(UTurn());
  Drive(&t, {0, 0}, {8, 0});
  Drive(&t, {8, 0}, {8, 8});
  EXPECT_NEAR(t.progress_m(), 36.0, 0.2) << "rejoined the return leg at x = 8";
  EXPECT_NEAR(Drive(&t, {8, 8}, {0, 8}), 44.0, 1e-9);
  // A window that only moves (no rejoining) stays on the way out: the return leg is never reached.
  RouteTracker window_only(UTurn(), RouteTracker::Config{5.0, 10.0, 1.5, 0.0});
  Drive(&window_only, {0, 0}, {8, 0});
  Drive(&window_only, {8, 0}, {8, 8});
  EXPECT_LT(Drive(&window_only, {8, 8}, {0, 8}), 12.0);
}

TEST(RouteTrackerTest, AFigureOfEightIsFollowedThroughItsCrossing) {
  // Two 10 m squares sharing the corner (10, 10): the crossing is passed twice.
  const std::vector<Eigen::Vector2d> eight = {{0, 0}, {10, 0}, {10, 10}, {10, 20}, {20, 20}, {20, 10},
                                              {10, 10}, {0, 10}, {0, 0}};
  RouteTracker t(eight);
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < eight.size(); ++i) {
    const double before = t.progress_m();
    s = Drive(&t, eight[i], eight[i + 1]);
    EXPECT_NEAR(s - before, (eight[i + 1] - eight[i]).norm(), 1e-6) << "leg " << i;
  }
  EXPECT_NEAR(s, 80.0, 1e-6);
}

TEST(RouteTrackerTest, LapsSideBySideAreNotSkipped) {
  // Two laps of a 20 x 6 m loop: being at the start again after the first lap is 52 m, not 0 or 104.
  std::vector<Eigen::Vector2d> laps;
  for (int lap = 0; lap < 2; ++lap) {
    for (const Eigen::Vector2d& p : std::vector<Eigen::Vector2d>{{0, 0}, {20, 0}, {20, 6}, {0, 6}}) laps.push_back(p);
  }
  laps.push_back({0, 0});
  RouteTracker t(laps);
  for (std::size_t i = 0; i + 1 < 5; ++i) Drive(&t, laps[i], laps[i + 1]);
  EXPECT_NEAR(t.progress_m(), 52.0, 1e-6);
}

TEST(RouteTrackerTest, RefusesARouteOfOnePoint) {
  EXPECT_THROW(RouteTracker({{0, 0}}), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::planner
