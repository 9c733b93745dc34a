#include "ovpc/scenarios/diagnosis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <iomanip>
#include <map>
#include <sstream>
#include <vector>
#include <string>
#include "format.h"
#include "ovpc/planner/route_tracker.h"

namespace ovpc::scenarios {
namespace {

using internal::Fixed;

constexpr double kStandingMps = 0.05;    // slower than this counts as standing
constexpr double kMovingMps = 0.1;       // a direction counts once this fast (hysteresis)
constexpr double kWindowS = 30.0;        // "lately"
constexpr double kStalledS = 10.0;       // standing this long at the end: stalled
constexpr int kRockingReversals = 4;     // this many reversals lately ...
constexpr double kRockingMaxMoveM = 3.0; // ... while getting less far than this: rocking

bool CriterionFailed(const RunResult& r, const std::string& name) {
  return std::any_of(r.criteria.begin(), r.criteria.end(),
                     [&](const CriterionResult& c) { return c.name == name && !c.passed; });
}

bool CriterionPassed(const RunResult& r, const std::string& name) {
  return std::any_of(r.criteria.begin(), r.criteria.end(),
                     [&](const CriterionResult& c) { return c.name == name && c.passed; });
}

void ReadMotion(const RunResult& r, Diagnosis* d) {
  const auto& t = r.trajectory;
  if (t.empty()) return;
  const double end_s = t.back().time_s;
  int direction = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double v = t[i].speed_mps;
    const double dt = i + 1 < t.size() ? t[i + 1].time_s - t[i].time_s : 0.0;
    if (std::abs(v) < kStandingMps) {
      d->stood_still_s += dt;
      d->still_at_end_s += dt;
    } else {
      d->still_at_end_s = 0.0;
    }
    if (std::abs(v) >= kMovingMps) {
      const int s = v > 0 ? 1 : -1;
      if (direction != 0 && s != direction) {
        ++d->reversals;
        if (t[i].time_s >= end_s - kWindowS) ++d->reversals_last_30s;
      }
      direction = s;
    }
  }
  const auto from = std::find_if(t.begin(), t.end(), [&](const TrajectorySample& s) { return s.time_s >= end_s - kWindowS; });
  d->moved_last_30s_m = (t.back().T_W_B.translation().head<2>() - from->T_W_B.translation().head<2>()).norm();
}

void ReadPlans(const RunResult& r, Diagnosis* d) {
  std::array<std::size_t, planner::kNumPoseChecks> rejected{};
  std::map<std::string, std::size_t> failures;
  for (const PlanRecord& record : r.plan_log) {
    const navigation::PlanAttempt& p = record.attempt;
    // A plan found and one found but not taken (the current path kept) are not failures.
    if (p.outcome == "found" || p.outcome == "kept current") d->last_plan_found_s = p.time_s;
    else ++failures[p.outcome];
    for (std::size_t c = 1; c < planner::kNumPoseChecks; ++c) rejected[c] += p.state_checks[c];
  }
  const auto most = std::max_element(rejected.begin() + 1, rejected.end());
  if (*most > 0) d->commonest_rejection = planner::PoseCheckName(static_cast<planner::PoseCheck>(most - rejected.begin()));
  std::size_t best = 0;
  for (const auto& [outcome, n] : failures) {
    if (n > best) best = n, d->commonest_failure = outcome;
  }
}

// The last map's points in a corridor from the vehicle towards the route ahead (or along its
// heading): obstacles above the ground clearance, a drop below the vehicle's ground,
// non-traversable ground, and where the seen ground ends.
std::string ReadMapAhead(const RunResult& r) {
  if (r.trajectory.empty() || r.last_map_points.empty()) return "";
  const Eigen::Isometry3d& T_W_B = r.trajectory.back().T_W_B;
  const Eigen::Vector2d at = T_W_B.translation().head<2>();
  // Where the robot had to go: towards the route 6 m past its progress (the route as scored), else
  // along its heading.
  Eigen::Vector2d dir = T_W_B.linear().col(0).head<2>();
  if (r.route_m.size() >= 2) {
    const Eigen::Vector2d next = planner::RouteTracker(r.route_m).PointAt(r.route_progress_m + 6.0);
    if ((next - at).norm() > 0.5) dir = next - at;
  }
  if (dir.norm() < 1e-9) return "";
  dir.normalize();
  const Eigen::Vector2d side(-dir.y(), dir.x());
  const double z0 = T_W_B.translation().z();
  // Heights are taken from the vehicle's ground continued sideways at its roll: across a slope the
  // downhill side is not a drop.
  const Eigen::Vector3d n = T_W_B.linear().col(2);
  const double side_grade = n.z() > 1e-6 ? -(n.x() * side.x() + n.y() * side.y()) / n.z() : 0.0;
  // The corridor: from the rear axle to 6 m ahead, 1.5 m to either side (the vehicle and a margin).
  constexpr double kAheadM = 6.0, kHalfWidthM = 1.5, kClearanceM = 0.35, kDropM = 0.5;
  double obstacle_at = kAheadM + 1, obstacle_h = 0.0, drop_at = kAheadM + 1, drop_h = 0.0, rough_at = kAheadM + 1;
  double seen_to = 0.0;
  std::size_t ground = 0, non_traversable_ground = 0;
  for (const MapPoint& p : r.last_map_points) {
    const Eigen::Vector2d d = p.position_W.head<2>() - at;
    const double along = d.dot(dir), across = d.dot(side), h = p.position_W.z() - z0 - across * side_grade;
    if (along < 0.0 || along > kAheadM || std::abs(across) > kHalfWidthM) continue;
    if (h > kClearanceM && !p.traversable) {
      if (along < obstacle_at) obstacle_at = along, obstacle_h = h;
    } else if (h < -kDropM && along < drop_at) {
      drop_at = along, drop_h = -h;
    } else if (std::abs(h) <= kClearanceM) {
      ++ground;
      if (p.traversable) seen_to = std::max(seen_to, along);
      else if (along < rough_at) rough_at = along, ++non_traversable_ground;
      else ++non_traversable_ground;
    }
  }
  // The obstacle's height: its highest point within half a metre behind its nearest.
  for (const MapPoint& p : r.last_map_points) {
    const Eigen::Vector2d d = p.position_W.head<2>() - at;
    const double along = d.dot(dir), h = p.position_W.z() - z0 - d.dot(side) * side_grade;
    if (!p.traversable && h > kClearanceM && std::abs(d.dot(side)) <= kHalfWidthM && along >= obstacle_at &&
        along <= obstacle_at + 0.5) {
      obstacle_h = std::max(obstacle_h, h);
    }
  }
  std::vector<std::string> parts;
  if (obstacle_at <= kAheadM) parts.push_back("an obstacle " + Fixed(obstacle_h, 1) + " m high " + Fixed(obstacle_at, 1) + " m ahead");
  if (drop_at <= kAheadM) parts.push_back("ground " + Fixed(drop_h, 1) + " m lower " + Fixed(drop_at, 1) + " m ahead");
  if (non_traversable_ground > 0 && 4 * non_traversable_ground >= ground) {
    parts.push_back("non-traversable ground from " + Fixed(rough_at, 1) + " m ahead (" +
                    std::to_string(non_traversable_ground) + " of " + std::to_string(ground) + " ground points)");
  }
  if (seen_to < kAheadM - 1.0) parts.push_back("seen traversable ground ends " + Fixed(seen_to, 1) + " m ahead (unseen beyond)");
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : ", ") + part;
  return out;
}

// "a 3, b 1" from counts, commonest first (ties by name), at most `most` of them.
std::string CountsText(const std::map<std::string, std::size_t>& counts, std::size_t most, const std::string& unit) {
  std::vector<std::pair<std::string, std::size_t>> sorted(counts.begin(), counts.end());
  std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string out;
  for (std::size_t i = 0; i < sorted.size() && i < most; ++i) {
    out += (i ? ", " : "") + std::to_string(sorted[i].second) + unit + " " + sorted[i].first;
  }
  return out;
}

// The planner in the run's last 30 s: local goals tried (and how many were places to look from),
// plans found, failed and why, paths blocked and by what, and which checks rejected the sampled
// states (a crest, unseen ground, a steep face, an obstacle).
std::string ReadPlannerLately(const RunResult& r) {
  if (r.plan_log.empty() || r.trajectory.empty()) return "";
  const double from_s = r.trajectory.back().time_s - kWindowS;
  std::size_t calls = 0, found = 0, blocked = 0, no_goal = 0, looks = 0;
  std::map<std::string, std::size_t> blocked_by, failed;
  std::array<std::size_t, planner::kNumPoseChecks> rejected{};
  double nearest_goal = 1e9, farthest_goal = 0.0;
  for (const PlanRecord& record : r.plan_log) {
    const navigation::PlanAttempt& p = record.attempt;
    if (p.time_s < from_s) continue;
    ++calls;
    if (p.outcome == "found" || p.outcome == "kept current") ++found;
    else if (p.has_goal) ++failed[p.outcome];
    if (!p.has_goal) ++no_goal;
    if (!p.blocked_by.empty()) ++blocked, ++blocked_by[p.blocked_by];
    if (p.has_goal) {
      const double d = (record.GoalW().head<2>() - record.VehicleW().head<2>()).norm();
      nearest_goal = std::min(nearest_goal, d);
      farthest_goal = std::max(farthest_goal, d);
      if (p.goal_is_look) ++looks;
    }
    for (std::size_t c = 1; c < planner::kNumPoseChecks; ++c) rejected[c] += p.state_checks[c];
  }
  if (calls == 0) return "";
  std::ostringstream s;
  s << calls << " plans in the last 30 s, " << found << " found";
  if (calls > no_goal) {
    s << ", goals " << Fixed(nearest_goal, 1) << "-" << Fixed(farthest_goal, 1) << " m away";
    if (looks > 0) s << " (" << looks << " of them places to look from, where seen ground ends)";
  }
  if (no_goal > 0) s << ", " << no_goal << " without a local goal";
  if (!failed.empty()) s << ", failed: " << CountsText(failed, 3, "");
  if (blocked > 0) {
    const auto most = std::max_element(blocked_by.begin(), blocked_by.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    s << ", " << blocked << " paths blocked (mostly " << most->first << ")";
  }
  std::size_t total = 0;
  for (std::size_t n : rejected) total += n;
  if (total > 0) {
    std::map<std::string, std::size_t> percent;
    for (std::size_t c = 1; c < planner::kNumPoseChecks; ++c) {
      const std::size_t pc = (100 * rejected[c] + total / 2) / total;
      if (pc >= 5) percent[planner::PoseCheckName(static_cast<planner::PoseCheck>(c))] = pc;
    }
    if (!percent.empty()) s << ", sampled states rejected as " << CountsText(percent, 3, " %");
  }
  return s.str();
}

// Stretches of standing of at least kStalledS.
void FindStalls(const std::vector<TrajectorySample>& t, std::vector<Spell>* spells) {
  for (std::size_t i = 0; i < t.size();) {
    if (std::abs(t[i].speed_mps) >= kStandingMps) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < t.size() && std::abs(t[j].speed_mps) < kStandingMps) ++j;
    const double end_s = j < t.size() ? t[j].time_s : t.back().time_s;
    if (end_s - t[i].time_s >= kStalledS) {
      spells->push_back({"stall", t[i].time_s, end_s, t[i].T_W_B.translation().head<2>()});
    }
    i = j;
  }
}

// Direction reversals as ReadMotion counts them. The verdict's rule from each reversal on: at least
// kRockingReversals of them within the next kWindowS (or to the run's end), and the window's end
// less than kRockingMaxMoveM from its start; overlapping stretches are one spell, ending at its
// last reversal.
void FindRocking(const std::vector<TrajectorySample>& t, std::vector<Spell>* spells) {
  std::vector<std::size_t> reversals;
  int direction = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (std::abs(t[i].speed_mps) < kMovingMps) continue;
    const int s = t[i].speed_mps > 0 ? 1 : -1;
    if (direction != 0 && s != direction) reversals.push_back(i);
    direction = s;
  }
  const auto xy = [&](std::size_t i) -> Eigen::Vector2d { return t[i].T_W_B.translation().head<2>(); };
  const std::size_t first = spells->size();
  for (std::size_t k = 0; k + kRockingReversals - 1 < reversals.size(); ++k) {
    const double start_s = t[reversals[k]].time_s;
    std::size_t last = k;  // the last reversal within the window
    while (last + 1 < reversals.size() && t[reversals[last + 1]].time_s <= start_s + kWindowS) ++last;
    if (last + 1 < k + kRockingReversals) continue;
    const auto window_end = std::upper_bound(t.begin() + reversals[k], t.end(), start_s + kWindowS,
                                             [](double time, const TrajectorySample& s) { return time < s.time_s; });
    const std::size_t end_i = static_cast<std::size_t>(window_end - t.begin()) - 1;
    if (!((xy(end_i) - xy(reversals[k])).norm() < kRockingMaxMoveM)) continue;
    const double end_s = t[reversals[last]].time_s;
    if (spells->size() > first && start_s <= spells->back().end_s) {
      spells->back().end_s = std::max(spells->back().end_s, end_s);
    } else {
      spells->push_back({"rocking", start_s, end_s, xy(reversals[k])});
    }
  }
}

}  // namespace

std::vector<Spell> FindSpells(const RunResult& r) {
  std::vector<Spell> stalls, rocking;
  FindStalls(r.trajectory, &stalls);
  FindRocking(r.trajectory, &rocking);
  std::vector<Spell> spells;
  std::merge(stalls.begin(), stalls.end(), rocking.begin(), rocking.end(), std::back_inserter(spells),
             [](const Spell& a, const Spell& b) { return a.start_s < b.start_s; });
  return spells;
}

Diagnosis Diagnose(const RunResult& r) {
  Diagnosis d;
  ReadMotion(r, &d);
  ReadPlans(r, &d);
  const bool arrived = CriterionPassed(r, "goal_reached") || r.end_reason == "route end reached";
  if (arrived) {
    d.verdict = CriterionFailed(r, "completion_time") ? "late" : "arrived";
  } else if (CriterionFailed(r, "goal_reached") || CriterionFailed(r, "min_progress")) {
    if (d.still_at_end_s >= kStalledS) d.verdict = "stalled";
    else if (d.reversals_last_30s >= kRockingReversals && d.moved_last_30s_m < kRockingMaxMoveM) d.verdict = "rocking";
    else d.verdict = "driving";
  }
  std::ostringstream s;
  const Eigen::Vector2d at =
      r.trajectory.empty() ? Eigen::Vector2d::Zero() : Eigen::Vector2d(r.trajectory.back().T_W_B.translation().head<2>());
  const std::string where = "at (" + Fixed(at.x(), 1) + ", " + Fixed(at.y(), 1) + ")";
  if (d.verdict == "stalled") {
    s << "stalled " << where << ": stood still for the last " << Fixed(d.still_at_end_s, 1) << " s";
  } else if (d.verdict == "rocking") {
    s << "rocking " << where << ": " << d.reversals_last_30s << " direction reversals and "
      << Fixed(d.moved_last_30s_m, 1) << " m covered in the last 30 s";
  } else if (d.verdict == "driving") {
    s << "still driving " << where << " when the time ran out: " << Fixed(d.moved_last_30s_m, 1)
      << " m covered in the last 30 s";
  } else {
    s << (d.verdict.empty() ? "arrival not scored" : d.verdict);
  }
  s << "; stood still " << Fixed(d.stood_still_s, 1) << " s in all, " << d.reversals << " reversals";
  s << "; last plan found " << (d.last_plan_found_s ? "at t=" + Fixed(*d.last_plan_found_s, 1) + " s" : std::string("never"));
  if (!d.commonest_failure.empty()) s << "; commonest failed plan: " << d.commonest_failure;
  if (!d.commonest_rejection.empty()) s << "; planner mostly rejected: " << d.commonest_rejection;
  if (!arrived && !d.verdict.empty()) {
    d.map_ahead = ReadMapAhead(r);
    d.planner_lately = ReadPlannerLately(r);
    if (!d.map_ahead.empty()) s << "; the map there: " << d.map_ahead;
    if (!d.planner_lately.empty()) s << "; the planner there: " << d.planner_lately;
  }
  d.summary = s.str();
  return d;
}

}  // namespace ovpc::scenarios
