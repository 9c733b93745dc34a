// The Navigator on generated scans (the analytic scene and the paper's spinning VLP-16): one cycle
// maps, plans and drives; the seams take a user's map backend, planner and follower.
#include "ovpc/navigation/navigator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/planner/local_goal.h"
#include "ovpc/planner/path.h"
#include "ovpc/synth/synthetic_scene.h"
#include "../support/test_navigation.h"

namespace ovpc::navigation {
namespace {

using planner::Pose2;

using testing::FirstCycle;
using testing::FlatConfig;
using testing::FlatGroundScans;

TEST(NavigatorTest, OneCycleMapsPlansAheadAndSetsOff) {
  Navigator nav(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}});
  const controller::Command before = nav.Control(0.0, Eigen::Isometry3d::Identity(), 0.0);
  EXPECT_TRUE(before.done) << "no path yet: stand";
  EXPECT_EQ(before.speed_mps, 0.0);
  FirstCycle(&nav, FlatGroundScans(1));

  ASSERT_EQ(nav.cycles().size(), 1u);
  EXPECT_TRUE(nav.cycles()[0].map_ok);
  EXPECT_EQ(nav.cycles()[0].trigger, "no path");
  EXPECT_EQ(nav.cycles()[0].outcome, "found");
  // The stages' thread CPU time: spent (a mesh and a plan were made), and never more than the wall
  // time of the same stage on the one thread that ran it (plus the clocks' granularity).
  const CycleRecord& rec = nav.cycles()[0];
  EXPECT_GT(rec.map_cpu_ms, 0.0);
  EXPECT_GT(rec.plan_cpu_ms, 0.0);
  EXPECT_LE(rec.prepare_cpu_ms, rec.prepare_ms + 0.1);
  EXPECT_LE(rec.map_cpu_ms, rec.map_ms + 0.1);
  EXPECT_LE(rec.plan_cpu_ms, rec.plan_ms + 0.1);
  ASSERT_NE(nav.map(), nullptr);
  EXPECT_TRUE(nav.has_path());
  ASSERT_TRUE(nav.goal_O().has_value());
  EXPECT_GT(nav.goal_O()->x(), 2.5) << "the local goal lies ahead on the route";
  EXPECT_NEAR(nav.goal_O()->y(), 0.0, 6.0 + 1e-9);
  const auto poses = nav.path_O().Poses();
  ASSERT_GE(poses.size(), 2u);
  EXPECT_NEAR(poses.front().pose.x_m, 0.0, 1e-6);
  EXPECT_NEAR((Eigen::Vector2d(poses.back().pose.x_m, poses.back().pose.y_m) - *nav.goal_O()).norm(), 0.0, 0.05);
  EXPECT_EQ(nav.stats().map_updates, 1u);
  EXPECT_EQ(nav.stats().replans_found, 1u);

  // The next control tick follows the path: forward, not done.
  const controller::Command cmd = nav.Control(0.2, Eigen::Isometry3d::Identity(), 0.0);
  EXPECT_FALSE(cmd.done);
  EXPECT_GE(cmd.speed_mps, 0.0);
  // The map's points are there to look at.
  const MapView view = nav.map_backend().View();
  ASSERT_NE(view.points_L, nullptr);
  EXPECT_GT(view.points_L->size(), 1000u);
  ASSERT_NE(view.mesh_L, nullptr);
}

TEST(NavigatorTest, SameInputsGiveTheSamePath) {
  Navigator a(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}}), b(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}});
  FirstCycle(&a, FlatGroundScans(3));
  FirstCycle(&b, FlatGroundScans(3));
  const auto pa = a.path_O().Poses(), pb = b.path_O().Poses();
  ASSERT_EQ(pa.size(), pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].pose.x_m, pb[i].pose.x_m);
    EXPECT_EQ(pa[i].pose.y_m, pb[i].pose.y_m);
    EXPECT_EQ(pa[i].pose.yaw_rad, pb[i].pose.yaw_rad);
  }
}

// A backend that never has a map: the navigator plans nothing and the vehicle stands.
class BlindBackend final : public MapBackend {
 public:
  std::shared_ptr<const planner::PlanningMap> Update(const Points& points_L, const MapContext&) override {
    points_seen = points_L.size();
    return nullptr;
  }
  const char* name() const override { return "blind"; }
  std::size_t points_seen = 0;
};

TEST(NavigatorTest, AMapBackendWithoutAMapLeavesTheVehicleStanding) {
  auto backend = std::make_unique<BlindBackend>();
  const BlindBackend* seen = backend.get();
  Navigator::Plugins plugins;
  plugins.map = std::move(backend);
  Navigator nav(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  FirstCycle(&nav, FlatGroundScans(1));
  EXPECT_GT(seen->points_seen, 1000u) << "the backend gets the prepared cloud";
  EXPECT_EQ(nav.stats().map_failures, 1u);
  EXPECT_FALSE(nav.has_path());
  EXPECT_TRUE(nav.Control(0.2, Eigen::Isometry3d::Identity(), 0.0).done);
  EXPECT_STREQ(nav.map_backend().name(), "blind");
}

// A planner that goes straight to the goal and a follower that records what it is given.
class StraightPlanner final : public PathPlanner {
 public:
  planner::PlanResult Plan(const planner::PlanningMap&, const Pose2& start, const Pose2& goal,
                           const std::vector<double>&) const override {
    planner::PlanResult r;
    r.status = planner::PlanStatus::kFound;
    planner::PathSegment seg;
    seg.poses = {{start, 0.0}, {goal, 0.0}};
    r.path = planner::Path({seg});
    return r;
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap&, const planner::Path&,
                                              std::size_t) const override {
    return std::nullopt;
  }
};

class RecordingFollower final : public PathFollower {
 public:
  explicit RecordingFollower(int* updates) : updates_(updates) {}
  void Follow(const planner::Path& path_O) override { path_ = path_O; }
  void Clear() override { path_ = {}; }
  bool has_path() const override { return !path_.empty(); }
  bool done() const override { return false; }
  controller::Command Update(const Pose2&, double) override {
    ++*updates_;
    return {0.1, 0.7, false};
  }

 private:
  planner::Path path_;
  int* updates_;
};

TEST(NavigatorTest, ItsPlannerAndFollowerCanBeAUsers) {
  int updates = 0;
  Navigator::Plugins plugins;
  plugins.planner = std::make_unique<StraightPlanner>();
  plugins.follower = std::make_unique<RecordingFollower>(&updates);
  Navigator nav(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  FirstCycle(&nav, FlatGroundScans(1));
  ASSERT_TRUE(nav.has_path());
  EXPECT_EQ(nav.path_O().Poses().size(), 2u) << "the user's straight path";
  // Control runs the follower at the control rate (50 Hz) and repeats its command in between; a
  // caller that fell behind gets one tick, not one per missed tick.
  EXPECT_EQ(nav.Control(0.19, Eigen::Isometry3d::Identity(), 0.0).speed_mps, 0.7);
  EXPECT_EQ(updates, 1);
  updates = 0;
  for (int i = 0; i < 10; ++i) {
    const controller::Command c = nav.Control(0.2 + 0.01 * i, Eigen::Isometry3d::Identity(), 0.0);
    EXPECT_EQ(c.speed_mps, 0.7);
  }
  EXPECT_EQ(updates, 5);
}

// A planner whose first path goes straight to the goal and whose later ones back up 1 m first.
class BackingUpPlanner final : public PathPlanner {
 public:
  planner::PlanResult Plan(const planner::PlanningMap&, const Pose2& start, const Pose2& goal,
                           const std::vector<double>&) const override {
    planner::PlanResult r;
    r.status = planner::PlanStatus::kFound;
    std::vector<planner::PathSegment> segments;
    planner::PathSegment straight;
    if (calls_++ > 0) {
      const Pose2 back{start.x_m - 1.0, start.y_m, start.yaw_rad};
      planner::PathSegment reverse;
      reverse.direction = planner::Direction::kReverse;
      reverse.poses = {{start, 0.0}, {back, 0.0}};
      segments.push_back(reverse);
      straight.poses = {{back, 0.0}, {goal, 0.0}};
    } else {
      straight.poses = {{start, 0.0}, {goal, 0.0}};
    }
    segments.push_back(straight);
    r.path = planner::Path(std::move(segments));
    return r;
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap&, const planner::Path&,
                                              std::size_t) const override {
    return std::nullopt;
  }

 private:
  mutable int calls_ = 0;
};

TEST(NavigatorTest, APeriodicReplanKeepsTheCurrentPathUnlessTheNewOneIsBetter) {
  for (const double keep : {-1.0, 1.0}) {
    Navigator::Config config = FlatConfig();
    config.path_choice.keep_path_within_m = keep;
    config.path_choice.cusp_cost_m = 3.0;
    Navigator::Plugins plugins;
    plugins.planner = std::make_unique<BackingUpPlanner>();
    Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
    FirstCycle(&nav, FlatGroundScans(1));
    ASSERT_EQ(nav.path_O().NumCusps(), 0);
    for (double t = 0.4; t < 1.25; t += 0.2) nav.Update(t, Eigen::Isometry3d::Identity());
    // At 1.2 s the period has elapsed: the new path backs up first (2 m longer, and a cusp and a
    // turn round at 3 m each) and replaces the current one only under the paper's rule.
    EXPECT_EQ(nav.cycles().back().trigger, "period elapsed") << keep;
    if (keep < 0.0) {
      EXPECT_EQ(nav.cycles().back().outcome, "found");
      EXPECT_EQ(nav.path_O().NumCusps(), 1);
    } else {
      EXPECT_EQ(nav.cycles().back().outcome, "kept current");
      EXPECT_EQ(nav.path_O().NumCusps(), 0);
    }
  }
  Navigator::Config bad = FlatConfig();
  bad.path_choice.cusp_cost_m = -1.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// A planner whose path is one forward segment of the poses `shape` gives for the start pose,
// whatever the goal, and whose paths are never blocked.
class ShapePlanner final : public PathPlanner {
 public:
  explicit ShapePlanner(std::function<std::vector<Pose2>(const Pose2&)> shape) : shape_(std::move(shape)) {}
  planner::PlanResult Plan(const planner::PlanningMap&, const Pose2& start, const Pose2&,
                           const std::vector<double>&) const override {
    planner::PlanResult r;
    r.status = planner::PlanStatus::kFound;
    planner::PathSegment seg;
    for (const Pose2& p : shape_(start)) seg.poses.push_back({p, 0.0});
    r.path = planner::Path({seg});
    return r;
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap&, const planner::Path&,
                                              std::size_t) const override {
    return std::nullopt;
  }

 private:
  std::function<std::vector<Pose2>(const Pose2&)> shape_;
};

// A path 6 m along x that turns into +y at a right angle: a corner sharper than the vehicle's
// full-lock circle. Its poses keep 1 m clear of a post at (8, 3); the follower swings out past the
// corner and would hit it.
std::unique_ptr<PathPlanner> CornerPlanner() {
  return std::make_unique<ShapePlanner>([](const Pose2& start) {
    std::vector<Pose2> poses;
    for (int i = 0; i <= 60; ++i) poses.push_back(Pose2{start.x_m + 0.1 * i, start.y_m, 0.0});
    for (int i = 1; i <= 50; ++i) poses.push_back(Pose2{start.x_m + 6.0, start.y_m + 0.1 * i, kPi / 2});
    return poses;
  });
}

// A path 10 m straight ahead of the start pose.
std::unique_ptr<PathPlanner> StraightAheadPlanner() {
  return std::make_unique<ShapePlanner>([](const Pose2& start) {
    std::vector<Pose2> poses;
    const double c = std::cos(start.yaw_rad), s = std::sin(start.yaw_rad);
    for (int i = 0; i <= 100; ++i) poses.push_back(Pose2{start.x_m + 0.1 * i * c, start.y_m + 0.1 * i * s, start.yaw_rad});
    return poses;
  });
}

TEST(NavigatorTest, APathTheFollowerWouldNotKeepToIsNotTaken) {
  synth::Scene scene;
  scene.cylinders.push_back({Vec3(8.0, 3.0, 0.0), 0.2, 2.0});
  const auto scans = [&] {
    return synth::SimulateScans(scene, SpinningLidarMount{}, Eigen::Isometry3d::Identity(), 0.0, 25, 0.01, 1);
  };
  for (const double margin : {-1.0, 0.05}) {
    Navigator::Config config = FlatConfig();
    config.path_choice.rollout_margin_m = margin;
    Navigator::Plugins plugins;
    plugins.planner = CornerPlanner();
    Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
    FirstCycle(&nav, scans());
    ASSERT_FALSE(nav.plan_log().empty());
    if (margin < 0.0) {
      EXPECT_TRUE(nav.has_path()) << "without the rollout the path is taken";
      EXPECT_EQ(nav.plan_log().back().outcome, "found");
    } else {
      EXPECT_FALSE(nav.has_path());
      EXPECT_EQ(nav.plan_log().back().outcome, "rollout collision");
      EXPECT_EQ(nav.cycles().back().outcome, "rollout collision");
    }
  }
  // Without the post the same path is taken: a new path's rollout checks collisions, nothing else.
  Navigator::Config config = FlatConfig();
  config.path_choice.rollout_margin_m = 0.05;
  Navigator::Plugins plugins;
  plugins.planner = CornerPlanner();
  Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  FirstCycle(&nav, synth::SimulateScans(synth::Scene{}, SpinningLidarMount{}, Eigen::Isometry3d::Identity(), 0.0,
                                        25, 0.01, 1));
  EXPECT_TRUE(nav.has_path());
  Navigator::Config bad = FlatConfig();
  bad.path_choice.rollout_margin_m = 2.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// The path straight along x from the origin in `scene`, kept on re-plans (a new one is never
// better enough); the vehicle then stands 1 m on, 0.3 m to the left and turned 25 deg to the left,
// and updates until the periodic re-plan. `check` sees the navigator after it.
void DriftOffAStraightPath(const synth::Scene& scene, double rollout_margin_m,
                           const std::function<void(const Navigator&)>& check) {
  Navigator::Config config = FlatConfig();
  config.path_choice.rollout_margin_m = rollout_margin_m;
  config.path_choice.keep_path_within_m = 50.0;  // a new path is never better enough
  Navigator::Plugins plugins;
  plugins.planner = StraightAheadPlanner();
  Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  FirstCycle(&nav, synth::SimulateScans(scene, SpinningLidarMount{}, Eigen::Isometry3d::Identity(), 0.0, 25, 0.01, 1));
  ASSERT_TRUE(nav.has_path()) << "from the start the follower keeps to it";
  Eigen::Isometry3d drifted = Eigen::Isometry3d::Identity();
  drifted.translation() = Vec3(1.0, 0.3, 0.0);
  drifted.linear() = Eigen::AngleAxisd(25.0 * kPi / 180.0, Vec3::UnitZ()).toRotationMatrix();
  for (double t = 0.4; t < 1.25; t += 0.2) nav.Update(t, drifted);
  ASSERT_EQ(nav.cycles().back().trigger, "period elapsed") << rollout_margin_m;
  check(nav);
}

// The path runs along x, its poses 0.45 m clear of a post at (4, 1.4). The vehicle then stands 1 m
// on, 0.3 m to the left and turned 25 deg to the left (as after a cusp taken at another heading):
// from there the follower would swing its nose into the post before it is back on the path. The
// periodic re-plan does not keep that path; the new one (straight on at 25 deg) hits the post too,
// so the vehicle stands. Without the rollout the current path is kept.
TEST(NavigatorTest, APathTheFollowerCanNoLongerKeepToIsNotKept) {
  synth::Scene scene;
  scene.cylinders.push_back({Vec3(4.0, 1.4, 0.0), 0.1, 2.0});
  for (const double margin : {-1.0, 0.05}) {
    DriftOffAStraightPath(scene, margin, [&](const Navigator& nav) {
      if (margin < 0.0) {
        EXPECT_EQ(nav.cycles().back().outcome, "kept current");
        EXPECT_TRUE(nav.has_path());
      } else {
        EXPECT_EQ(nav.plan_log().back().outcome, "rollout collision");
        EXPECT_FALSE(nav.has_path()) << "the vehicle stands";
        EXPECT_EQ(nav.stats().plan_outcomes.at("current path rollout collision"), 1u);
      }
    });
  }
}

// The same drift beside a low bank (0.15 m high, under the box's ground clearance, from 2 to 9 m
// along the path) instead of a post: the path's left wheels pass its edge 0.8 m clear, but from the
// drifted pose the follower swings them on to the edge, ground the planner rejects. That path is not
// kept (the re-plan takes a new one); it is kept without the rollout, and with the bank 0.6 m
// farther off. This is how a front wheel reached a ditch's lip (docs/notes/descents.md).
TEST(NavigatorTest, APathTheFollowerWouldLeaveForRejectedGroundIsNotKept) {
  for (const double bank_y : {1.4, 2.0}) {
    for (const double margin : {-1.0, 0.05}) {
      synth::Scene scene;
      scene.boxes.push_back({Vec3(2.0, bank_y, 0.0), Vec3(9.0, bank_y + 3.0, 0.15)});
      DriftOffAStraightPath(scene, margin, [&](const Navigator& nav) {
        const bool kept = nav.cycles().back().outcome == "kept current";
        EXPECT_EQ(kept, margin < 0.0 || bank_y > 1.5) << "bank at y " << bank_y << ", rollout margin " << margin;
        if (!kept) {
          EXPECT_EQ(nav.cycles().back().outcome, "found") << "a new path from where the vehicle is";
        }
      });
    }
  }
}

// A planner that records the goal and the other goal headings it is asked for, and finds nothing.
class RecordingPlanner final : public PathPlanner {
 public:
  struct Call {
    Pose2 start, goal;
    std::vector<double> other_yaws;
  };
  explicit RecordingPlanner(std::vector<Call>* calls) : calls_(calls) {}
  planner::PlanResult Plan(const planner::PlanningMap&, const Pose2& start, const Pose2& goal,
                           const std::vector<double>& other_yaws) const override {
    calls_->push_back({start, goal, other_yaws});
    planner::PlanResult r;
    r.status = planner::PlanStatus::kNoPath;
    return r;
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap&, const planner::Path&,
                                              std::size_t) const override {
    return std::nullopt;
  }

 private:
  std::vector<Call>* calls_;
};

// Past a hairpin (the route turns back by 148 degrees) the goal's heading is the next leg's: the
// vehicle, facing the first leg, would have to have turned already. With direct_heading_turn_deg
// the planner may also reach the goal heading straight from the vehicle to it; on a straight route,
// or with the rule off, only the goal's own heading is asked for.
TEST(NavigatorTest, AGoalPastAHairpinMayBeReachedHeadingStraightAtIt) {
  const std::vector<Eigen::Vector2d> hairpin = {{0.0, 0.0}, {12.0, 0.0}, {1.8, 6.3}, {-8.4, 12.6}};
  const std::vector<Eigen::Vector2d> straight = {{0.0, 0.0}, {20.0, 0.0}};
  for (const double turn : {std::numeric_limits<double>::infinity(), 90.0}) {
    for (const auto* route : {&hairpin, &straight}) {
      Navigator::Config config = FlatConfig();
      config.path_choice.direct_heading_turn_deg = turn;
      std::vector<RecordingPlanner::Call> calls;
      Navigator::Plugins plugins;
      plugins.planner = std::make_unique<RecordingPlanner>(&calls);
      Navigator nav(config, *route, std::move(plugins));
      FirstCycle(&nav, FlatGroundScans(1));
      ASSERT_FALSE(calls.empty()) << turn;
      for (const RecordingPlanner::Call& call : calls) {
        const bool turned = std::abs(planner::NormalizeYaw(call.goal.yaw_rad - call.start.yaw_rad)) > kPi / 2;
        EXPECT_EQ(turned, route == &hairpin) << "the goals past the hairpin face back: " << call.goal.yaw_rad;
        if (turned && std::isfinite(turn)) {
          ASSERT_EQ(call.other_yaws.size(), 1u) << turn;
          EXPECT_NEAR(call.other_yaws[0], std::atan2(call.goal.y_m - call.start.y_m, call.goal.x_m - call.start.x_m), 1e-9);
        } else {
          EXPECT_TRUE(call.other_yaws.empty()) << turn << (route == &hairpin ? " hairpin" : " straight");
        }
      }
    }
  }
}

// When no candidate gives a path and the vehicle has none, nearer_goal_fraction adds one more try:
// that fraction of the way to the best candidate, heading straight at it.
TEST(NavigatorTest, WithNoPathWhileStandingAGoalPartOfTheWayIsTried) {
  for (const double fraction : {0.0, 0.5}) {
    Navigator::Config config = FlatConfig();
    config.path_choice.nearer_goal_fraction = fraction;
    std::vector<RecordingPlanner::Call> calls;
    Navigator::Plugins plugins;
    plugins.planner = std::make_unique<RecordingPlanner>(&calls);
    Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
    FirstCycle(&nav, FlatGroundScans(1));
    const std::size_t candidates = static_cast<std::size_t>(config.path_choice.goal_candidates);
    ASSERT_GE(calls.size(), 1u);
    if (fraction == 0.0) {
      EXPECT_LE(calls.size(), candidates);
      continue;
    }
    ASSERT_GE(calls.size(), 2u);
    const Pose2 best = calls.front().goal, nearer = calls.back().goal;
    EXPECT_NEAR(nearer.x_m, 0.5 * best.x_m, 1e-9);
    EXPECT_NEAR(nearer.y_m, 0.5 * best.y_m, 1e-9);
    EXPECT_NEAR(nearer.yaw_rad, std::atan2(best.y_m, best.x_m), 1e-9);
    EXPECT_FALSE(nav.has_path());
  }
  Navigator::Config bad = FlatConfig();
  bad.path_choice.nearer_goal_fraction = 1.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// With a latency the cycle's path is driven from time_s + latency_s: it starts where the vehicle
// will be then (here 1 m/s straight ahead for 0.1 s), not where it was when the cycle started.
TEST(NavigatorTest, WithALatencyThePathStartsWhereTheVehicleWillBe) {
  for (const double latency : {0.0, 0.1}) {
    Navigator::Config config = FlatConfig();
    config.timing.latency_s = latency;
    Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}});
    const Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
    nav.Control(0.0, T_O_B, 1.0);  // measured speed 1 m/s, no path yet: steering 0
    for (Scan& s : FlatGroundScans(1)) nav.AddScan(std::move(s));
    nav.Update(0.2, T_O_B);
    nav.Update(0.2 + latency, T_O_B);  // the cycle takes effect
    ASSERT_TRUE(nav.has_path()) << latency;
    const planner::PathPose start = nav.path_O().Poses().front();
    EXPECT_NEAR(start.pose.x_m, 1.0 * latency, 1e-6) << latency;
    EXPECT_NEAR(start.pose.y_m, 0.0, 1e-6) << latency;
  }
}

// A route that turns back sharply (the corners family). A vehicle driving across the corner towards
// a goal on a later leg is far from the route, and the nearest route point inside the tracking
// window stays on the first leg: its progress is that of its goal less the distance to it. So it is
// once it reaches its goal (within replan.goal_too_close_m), though the way out beside the goal is
// as near. A vehicle on the first leg and short of its goal is where the route tracker puts it: the
// goal's progress less the distance would put it metres ahead of itself, and the next goal could
// then be on the way back.
TEST(NavigatorTest, ProgressFollowsTheGoalOnlyOffTheRouteOrAtTheGoal) {
  const std::vector<Eigen::Vector2d> route = {{0.0, 0.0}, {12.0, 0.0}, {3.1, 8.1}, {4.3, 20.0}};
  const std::vector<Eigen::Vector2d> mirrored = {{0.0, 0.0}, {12.0, 0.0}, {3.1, -8.1}, {4.3, -20.0}};
  const auto to_route = [&](const Eigen::Vector2d& p) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < route.size(); ++i) d = std::min(d, planner::DistanceToSegment(p, route[i], route[i + 1]));
    return d;
  };
  const auto at = [](const Eigen::Vector2d& p) {
    Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
    T_O_B.translation().head<2>() = p;
    return T_O_B;
  };
  {
    const Navigator::Config config = FlatConfig();
    Navigator nav(config, route);
    FirstCycle(&nav, FlatGroundScans(1));
    ASSERT_TRUE(nav.goal_O().has_value());
    const Eigen::Vector2d goal = *nav.goal_O();
    const double goal_progress = nav.plan_log().back().goal_progress_m;
    ASSERT_GT(goal_progress, 14.0) << "the goal lies past the first corner";
    // On the first leg, 0.3 m beside it (no map cycle is due).
    const Eigen::Vector2d on_leg(4.0, 0.3);
    EXPECT_FALSE(nav.Update(0.25, at(on_leg)));
    EXPECT_NEAR(nav.route_progress_m(), on_leg.x(), 1e-6) << "where the route tracker puts it";
    EXPECT_GT(goal_progress - (goal - on_leg).norm(), nav.route_progress_m() + 2.0) << "the goal's bound is metres ahead";
    // Across the corner, towards the goal.
    const Eigen::Vector2d across = 0.5 * goal;
    ASSERT_GT(to_route(across), config.progress.on_route_m) << "off the route";
    EXPECT_FALSE(nav.Update(0.3, at(across)));
    EXPECT_NEAR(nav.route_progress_m(), goal_progress - (goal - across).norm(), 1e-9);
    EXPECT_GT(nav.route_progress_m(), planner::RouteProgress(route, across, 0.0, 5.0, 10.0) + 1.0)
        << "the nearest route point in the window is on the first leg";
  }
  {
    // A goal just past the hairpin (turning away from the post at (9, 3)), reached from the way out
    // beside it.
    Navigator::Config config = FlatConfig();
    config.local_goal.max_ahead_m = 14.5;
    config.path_choice.direct_heading_turn_deg = 90.0;
    Navigator nav(config, mirrored);
    FirstCycle(&nav, FlatGroundScans(1));
    ASSERT_TRUE(nav.goal_O().has_value());
    const Eigen::Vector2d goal = *nav.goal_O();
    const double goal_progress = nav.plan_log().back().goal_progress_m;
    ASSERT_GT(goal_progress, 12.5) << "the goal lies on the way back";
    const Eigen::Vector2d beside(goal.x(), -0.3);
    ASSERT_LT(planner::DistanceToSegment(beside, mirrored[0], mirrored[1]), config.progress.on_route_m);
    ASSERT_LT((goal - beside).norm(), config.replan.goal_too_close_m);
    EXPECT_FALSE(nav.Update(0.25, at(Eigen::Vector2d(0.5 * goal.x(), -0.3))));
    EXPECT_NEAR(nav.route_progress_m(), 0.5 * goal.x(), 1e-6) << "short of its goal";
    EXPECT_FALSE(nav.Update(0.3, at(beside)));
    EXPECT_NEAR(nav.route_progress_m(), goal_progress - (goal - beside).norm(), 1e-9) << "at its goal";
    EXPECT_GT(nav.route_progress_m(), beside.x() + 1.0) << "past the tracker's place on the way out";
  }
}

TEST(NavigatorTest, GeometryIsDerivedFromTheVehicleModel) {
  Navigator::Config config;
  config.vehicle.length_m = 4.0;
  config.vehicle.rear_overhang_m = 1.0;
  config.vehicle.wheelbase_m = 2.5;
  config.vehicle.max_steering_deg = 35.0;
  const Navigator nav(config, {{0.0, 0.0}, {20.0, 0.0}});
  EXPECT_EQ(nav.box().length_m, 4.0);
  EXPECT_EQ(nav.box().centre_ahead_m, 1.0);
  EXPECT_EQ(nav.box().wheelbase_m, 2.5);
  EXPECT_EQ(nav.box().margin_m, config.planner.vehicle.margin_m) << "the rules are the config's";
  const controller::SteeringGeometry steering = controller::SteeringGeometry::Of(config.vehicle);
  EXPECT_EQ(steering.wheelbase_m, 2.5);
  EXPECT_DOUBLE_EQ(steering.max_steering_rad, DegToRad(35.0));
  // The defaults give the library's own numbers, bit for bit.
  EXPECT_EQ(Navigator::Config{}.Box().centre_ahead_m, planner::VehicleBox{}.centre_ahead_m);
  EXPECT_EQ(Navigator::Config{}.Box().length_m, planner::VehicleBox{}.length_m);
}

// A planner whose blocked-pose index lies past the path's end: taken as the last pose, no crash.
class PastTheEndPlanner final : public PathPlanner {
 public:
  planner::PlanResult Plan(const planner::PlanningMap& map, const Pose2& start, const Pose2& goal,
                           const std::vector<double>& yaws) const override {
    return StraightPlanner().Plan(map, start, goal, yaws);
  }
  std::optional<std::size_t> FirstInvalidPose(const planner::PlanningMap&, const planner::Path&,
                                              std::size_t) const override {
    return 1000000;
  }
};

TEST(NavigatorTest, APluginsOddAnswersAndATimeJumpNeitherCrashNorHang) {
  Navigator::Plugins plugins;
  plugins.planner = std::make_unique<PastTheEndPlanner>();
  Navigator nav(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}}, std::move(plugins));
  FirstCycle(&nav, FlatGroundScans(1));
  ASSERT_TRUE(nav.has_path());
  EXPECT_TRUE(nav.Update(0.4, Eigen::Isometry3d::Identity()));
  ASSERT_EQ(nav.cycles().size(), 2u);
  EXPECT_EQ(nav.cycles()[1].trigger, "path blocked");
  // A clock that jumps by years gets one tick, at once.
  nav.Control(1e9, Eigen::Isometry3d::Identity(), 0.0);
  EXPECT_TRUE(nav.Update(1e9, Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(nav.Update(1e9 + 0.1, Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(nav.Update(1e9 + 0.2 + 1e-6, Eigen::Isometry3d::Identity()));
  nav.ClearRecords();
  EXPECT_TRUE(nav.cycles().empty());
  EXPECT_EQ(nav.stats().map_updates, 4u) << "counters are kept";
}

// The default map backend is OVPC's: it maps the scans (free ground ahead, the post in the way),
// plans on the map and times its stages. backends_test checks the comparison backends alike.
TEST(NavigatorTest, TheDefaultMapBackendMapsPlansAndTimesItsStages) {
  Navigator nav(FlatConfig(), {{0.0, 0.0}, {20.0, 0.0}});
  EXPECT_STREQ(nav.map_backend().name(), "ovpc");
  FirstCycle(&nav, FlatGroundScans(1));
  ASSERT_EQ(nav.cycles().size(), 1u);
  EXPECT_TRUE(nav.cycles()[0].map_ok);
  ASSERT_NE(nav.map(), nullptr);
  const planner::VehicleBox& box = nav.box();
  EXPECT_EQ(planner::CheckPose(*nav.map(), box, Pose2{3.0, 0.0, 0.0}), planner::PoseCheck::kValid);
  EXPECT_NE(planner::CheckPose(*nav.map(), box, Pose2{7.5, 3.0, 0.0}), planner::PoseCheck::kValid);
  const std::vector<std::string> stages = {"sanitize", "transform", "hull", "mesh", "traversability", "vertex_cloud",
                                           "planning_map"};
  const NavigatorStats stats = nav.stats();
  ASSERT_EQ(stats.map_stages.size(), stages.size());
  for (std::size_t i = 0; i < stages.size(); ++i) EXPECT_EQ(stats.map_stages[i].first, stages[i]);
}

TEST(NavigatorTest, BadConfigAndRouteAreRejected) {
  Navigator::Config config;
  config.timing.map_rate_hz = 0.0;
  EXPECT_THROW(Navigator(config, {{0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Navigator(Navigator::Config{}, {}), std::invalid_argument);
  EXPECT_THROW(Navigator(Navigator::Config{}, {{0.0, std::nan("")}}), std::invalid_argument);
  Navigator::Config ovpc;
  ovpc.ovpc.map.normal_radius_m = -1.0;
  EXPECT_THROW(Navigator(ovpc, {{0.0, 0.0}}), std::invalid_argument) << "the default backend's section";
  for (const double latency : {-0.01, 0.21, std::nan("")}) {  // at most 5 Hz's 0.2 s
    Navigator::Config late;
    late.timing.latency_s = latency;
    EXPECT_THROW(Navigator(late, {{0.0, 0.0}}), std::invalid_argument) << latency;
  }
  Navigator::Config edge;
  edge.path_choice.edge_speed_mps = 0.0;
  EXPECT_THROW(Navigator(edge, {{0.0, 0.0}}), std::invalid_argument) << "edge_speed_mps";
  edge.path_choice.edge_speed_mps = 0.3;
  edge.path_choice.edge_look_m = std::nan("");
  EXPECT_THROW(Navigator(edge, {{0.0, 0.0}}), std::invalid_argument) << "edge_look_m";
  edge.path_choice.edge_look_m = 1.0;
  edge.planner.vehicle.crest_margin_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(Navigator(edge, {{0.0, 0.0}}), std::invalid_argument) << "crest_margin_m";
  edge.planner.vehicle.crest_margin_m = 0.2;
  EXPECT_NO_THROW(Navigator(edge, {{0.0, 0.0}}));
  for (const double turn : {-1.0, std::nan("")}) {
    Navigator::Config hairpin;
    hairpin.path_choice.direct_heading_turn_deg = turn;
    EXPECT_THROW(Navigator(hairpin, {{0.0, 0.0}}), std::invalid_argument) << "direct_heading_turn_deg " << turn;
  }
  for (const double latency : {0.1, 0.2}) {
    Navigator::Config in_time;
    in_time.timing.latency_s = latency;
    EXPECT_NO_THROW(Navigator(in_time, {{0.0, 0.0}})) << latency;
  }
}

}  // namespace
}  // namespace ovpc::navigation
