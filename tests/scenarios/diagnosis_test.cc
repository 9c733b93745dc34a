// The run diagnosis on made-up runs: a vehicle that stood, one that rocked, one still driving.
#include "ovpc/scenarios/diagnosis.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

// A run that did not reach its goal: `speed(t)` along x for `duration_s` at 10 Hz.
template <class Speed>
RunResult MadeUpRun(double duration_s, Speed speed) {
  RunResult r;
  r.end_reason = "time limit";
  r.criteria.push_back({"goal_reached", "", "no", false});
  double x = 0.0;
  for (int i = 0; i <= static_cast<int>(duration_s * 10); ++i) {
    TrajectorySample s;
    s.time_s = 0.1 * i;
    s.speed_mps = speed(s.time_s);
    x += 0.1 * s.speed_mps;
    s.T_W_B.translation().x() = x;
    r.trajectory.push_back(s);
  }
  PlanRecord found, failed;
  found.attempt.time_s = 12.0;
  found.attempt.outcome = "found";
  failed.attempt.time_s = 30.0;
  failed.attempt.outcome = "start_invalid:ground under footprint";
  failed.attempt.state_checks[static_cast<std::size_t>(planner::PoseCheck::kCollision)] = 40;
  failed.attempt.state_checks[static_cast<std::size_t>(planner::PoseCheck::kGroundUnderFootprint)] = 90;
  r.plan_log = {found, failed, failed};
  return r;
}

TEST(DiagnosisTest, AVehicleThatStoodAtTheEndStalled) {
  const Diagnosis d = Diagnose(MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; }));
  EXPECT_EQ(d.verdict, "stalled");
  EXPECT_NEAR(d.still_at_end_s, 40.0, 0.15);
  EXPECT_NEAR(d.stood_still_s, 40.0, 0.15);
  EXPECT_EQ(d.reversals, 0);
  ASSERT_TRUE(d.last_plan_found_s.has_value());
  EXPECT_EQ(*d.last_plan_found_s, 12.0);
  EXPECT_EQ(d.commonest_rejection, "ground under footprint");
  EXPECT_EQ(d.commonest_failure, "start_invalid:ground under footprint");
  EXPECT_NE(d.summary.find("stalled at (20.0, 0.0)"), std::string::npos) << d.summary;

  // A plan found but not taken (the current path kept) is a plan found, not a failure.
  RunResult kept = MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; });
  PlanRecord k;
  k.attempt.time_s = 40.0;
  k.attempt.outcome = "kept current";
  kept.plan_log.insert(kept.plan_log.end(), 3, k);
  const Diagnosis dk = Diagnose(kept);
  ASSERT_TRUE(dk.last_plan_found_s.has_value());
  EXPECT_EQ(*dk.last_plan_found_s, 40.0);
  EXPECT_EQ(dk.commonest_failure, "start_invalid:ground under footprint");
}

TEST(DiagnosisTest, BackAndForthOnTheSpotIsRocking) {
  // 0.8 m forward, 0.8 m back, every 4 s.
  const Diagnosis d = Diagnose(MadeUpRun(60.0, [](double t) { return std::fmod(t, 4.0) < 2.0 ? 0.4 : -0.4; }));
  EXPECT_EQ(d.verdict, "rocking");
  EXPECT_GE(d.reversals_last_30s, 14);
  EXPECT_LT(d.moved_last_30s_m, 1.0);
}

TEST(DiagnosisTest, SlowButSteadyIsStillDriving) {
  const Diagnosis d = Diagnose(MadeUpRun(60.0, [](double) { return 0.3; }));
  EXPECT_EQ(d.verdict, "driving");
  EXPECT_NEAR(d.moved_last_30s_m, 9.0, 0.1);
  EXPECT_EQ(d.stood_still_s, 0.0);
}

TEST(DiagnosisTest, ArrivalsAreArrivedOrLate) {
  RunResult r = MadeUpRun(20.0, [](double) { return 1.0; });
  r.criteria = {{"goal_reached", "", "at t=20.0 s", true}};
  EXPECT_EQ(Diagnose(r).verdict, "arrived");
  r.criteria.push_back({"completion_time", "<= 15 s", "20.0 s", false});
  EXPECT_EQ(Diagnose(r).verdict, "late");
  r.criteria = {{"no_collision", "0 body contacts", "t=3.00 s: body touched post", false}};
  EXPECT_EQ(Diagnose(r).verdict, "") << "a failure of another criterion is not an arrival question";
}

// The stalled run of MadeUpRun stands at (20, 0) on a route along +x; the last map around it holds
// flat traversable ground from x = 18 up to `ground_to_x`, and whatever `add` puts in.
template <class Add>
Diagnosis DiagnoseWithMap(double ground_to_x, Add add) {
  RunResult r = MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; });
  r.route_m = {{0.0, 0.0}, {60.0, 0.0}};
  r.route_progress_m = 20.0;
  for (double x = 18.0; x <= ground_to_x + 1e-9; x += 0.25) {
    for (double y = -2.0; y <= 2.0; y += 0.25) r.last_map_points.push_back({Vec3(x, y, 0.0), true});
  }
  add(&r.last_map_points);
  return Diagnose(r);
}

TEST(DiagnosisTest, SaysWhatTheMapHeldAheadWhereTheRunEnded) {
  // Seen ground that ends 3 m ahead of the vehicle: a crest, an edge or a shadow.
  const Diagnosis crest = DiagnoseWithMap(23.0, [](std::vector<MapPoint>*) {});
  EXPECT_NE(crest.map_ahead.find("seen traversable ground ends 3.0 m ahead"), std::string::npos) << crest.map_ahead;
  EXPECT_NE(crest.summary.find("the map there: "), std::string::npos) << crest.summary;
  // A wall 1.5 m high 2 m ahead.
  const Diagnosis wall = DiagnoseWithMap(30.0, [](std::vector<MapPoint>* m) {
    for (double z = 0.5; z <= 1.5; z += 0.25) m->push_back({Vec3(22.0, 0.0, z), false});
  });
  EXPECT_NE(wall.map_ahead.find("an obstacle 1.5 m high 2.0 m ahead"), std::string::npos) << wall.map_ahead;
  // Ground 1.2 m lower from 4 m ahead (a drop), beyond seen ground.
  const Diagnosis drop = DiagnoseWithMap(30.0, [](std::vector<MapPoint>* m) { m->push_back({Vec3(24.0, 0.5, -1.2), true}); });
  EXPECT_NE(drop.map_ahead.find("ground 1.2 m lower 4.0 m ahead"), std::string::npos) << drop.map_ahead;
  // Open, seen, traversable ground all the way: nothing stands out.
  EXPECT_EQ(DiagnoseWithMap(30.0, [](std::vector<MapPoint>*) {}).map_ahead, "");
  // The planner's last 30 s: the made-up run's failed attempt at t = 30 s lies in them.
  EXPECT_NE(crest.planner_lately.find("plans in the last 30 s"), std::string::npos) << crest.planner_lately;
}

// Standing rolled 20 degrees across a slope, the ground falls away on the downhill side as the slope
// does: that is not a drop ahead. A drop below the slope's own plane still is.
TEST(DiagnosisTest, TheDownhillSideOfACrossSlopeIsNoDrop) {
  const double roll = 20.0 * M_PI / 180.0;
  RunResult r = MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; });
  for (TrajectorySample& s : r.trajectory) s.T_W_B.linear() = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  r.route_m = {{0.0, 0.0}, {60.0, 0.0}};
  r.route_progress_m = 20.0;
  for (double x = 18.0; x <= 30.0 + 1e-9; x += 0.25) {
    for (double y = -2.0; y <= 2.0; y += 0.25) r.last_map_points.push_back({Vec3(x, y, y * std::tan(roll)), true});
  }
  EXPECT_EQ(Diagnose(r).map_ahead, "");
  r.last_map_points.push_back({Vec3(24.0, -1.0, -std::tan(roll) - 1.2), true});
  EXPECT_NE(Diagnose(r).map_ahead.find("ground 1.2 m lower 4.0 m ahead"), std::string::npos) << Diagnose(r).map_ahead;
}

// Near the end the planner goes to places to look from at a crest, its states mostly fail the crest
// test, and a goal past the crest is rejected: the diagnosis names each.
TEST(DiagnosisTest, SaysWhatThePlannerRejectedLately) {
  RunResult r = MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; });
  PlanRecord look, past, blocked;
  look.attempt.time_s = 40.0;
  look.attempt.has_goal = true;
  look.attempt.goal_is_look = true;
  look.attempt.goal_L = {2.0, 0.0, 0.0};
  look.attempt.outcome = "found";
  look.attempt.state_checks[static_cast<std::size_t>(planner::PoseCheck::kCrest)] = 70;
  look.attempt.state_checks[static_cast<std::size_t>(planner::PoseCheck::kUnseenGround)] = 20;
  look.attempt.state_checks[static_cast<std::size_t>(planner::PoseCheck::kCollision)] = 2;
  past = look;
  past.attempt.goal_is_look = false;
  past.attempt.goal_L = {6.0, 0.0, 0.0};
  past.attempt.outcome = "goal invalid:crest";
  blocked = look;
  blocked.attempt.blocked_by = "crest";
  r.plan_log.insert(r.plan_log.end(), {look, look, past, blocked});
  const Diagnosis d = Diagnose(r);
  // The made-up run's failed start at t = 30 s lies in the last 30 s too (no goal: not a goal's failure).
  EXPECT_NE(d.planner_lately.find("6 plans in the last 30 s, 3 found"), std::string::npos) << d.planner_lately;
  EXPECT_NE(d.planner_lately.find("(3 of them places to look from"), std::string::npos) << d.planner_lately;
  EXPECT_NE(d.planner_lately.find("failed: 1 goal invalid:crest"), std::string::npos) << d.planner_lately;
  EXPECT_NE(d.planner_lately.find("1 paths blocked (mostly crest)"), std::string::npos) << d.planner_lately;
  // 4 x (70 crest + 20 unseen + 2 collision) + 2 x (40 collision + 90 footprint) = 280 + 80 + 88 + 180 of 628.
  EXPECT_NE(d.planner_lately.find("sampled states rejected as 45 % crest, 29 % ground under footprint, 14 % collision"),
            std::string::npos)
      << d.planner_lately;
  EXPECT_NE(d.summary.find("the planner there: "), std::string::npos) << d.summary;
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

TEST(DiagnosisTest, SpellsAreFoundWhereverTheyLie) {
  // Stood from 20 s to the end: one stall, the verdict's.
  const RunResult stood = MadeUpRun(60.0, [](double t) { return t < 20.0 ? 1.0 : 0.0; });
  std::vector<Spell> spells = FindSpells(stood);
  ASSERT_EQ(spells.size(), 1u);
  EXPECT_EQ(spells[0].kind, "stall");
  EXPECT_NEAR(spells[0].start_s, 20.0, 0.05);
  EXPECT_EQ(spells[0].end_s, 60.0);
  EXPECT_NEAR(spells[0].at_m.x(), 20.0, 0.15);
  EXPECT_NEAR(spells[0].end_s - spells[0].start_s, Diagnose(stood).still_at_end_s, 0.15);

  // Stood 12 s in the middle, then drove on and arrived: a stall all the same; 9 s is none.
  spells = FindSpells(MadeUpRun(60.0, [](double t) { return t >= 10.0 && t < 22.0 ? 0.0 : 1.0; }));
  ASSERT_EQ(spells.size(), 1u);
  EXPECT_NEAR(spells[0].start_s, 10.0, 0.05);
  EXPECT_NEAR(spells[0].end_s, 22.0, 0.05);
  EXPECT_TRUE(FindSpells(MadeUpRun(60.0, [](double t) { return t >= 10.0 && t < 19.0 ? 0.0 : 1.0; })).empty());

  // Rocking from the start to the end: one spell from the first reversal.
  spells = FindSpells(MadeUpRun(60.0, [](double t) { return std::fmod(t, 4.0) < 2.0 ? 0.4 : -0.4; }));
  ASSERT_EQ(spells.size(), 1u);
  EXPECT_EQ(spells[0].kind, "rocking");
  EXPECT_NEAR(spells[0].start_s, 2.0, 0.05);
  EXPECT_NEAR(spells[0].end_s, 60.0, 0.05);  // the last reversal, at the last sample

  // Four quick reversals (a three-point turn) and driving on is manoeuvring, not rocking; so is
  // reversing every 20 m.
  EXPECT_TRUE(FindSpells(MadeUpRun(60.0, [](double t) {
                return t < 5.0 || t >= 8.0 ? 1.0 : (static_cast<int>(t) % 2 == 1 ? -0.5 : 0.5);
              })).empty());
  EXPECT_TRUE(FindSpells(MadeUpRun(120.0, [](double t) { return std::fmod(t, 20.0) < 10.0 ? 2.0 : -2.0; })).empty());
  EXPECT_TRUE(FindSpells(RunResult{}).empty());
}

}  // namespace
}  // namespace ovpc::scenarios
