// Why a run did not arrive: from the true trajectory and the planner's log, tell a vehicle that
// stood still ("stalled at the ramp's foot") from one that rocked back and forth on the spot
// ("rocking in front of the wall") and from one that was still driving when the time ran out.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ovpc/scenarios/run_result.h"

namespace ovpc::scenarios {

struct Diagnosis {
  /// "arrived", "late" (the goal, after max_time_s), "stalled", "rocking", "driving" (still
  /// moving on when the time ran out), or "" for a run that failed only other criteria.
  std::string verdict;
  std::string summary;              ///< one line for the scorecard
  double stood_still_s = 0.0;       ///< time the vehicle stood (|true speed| < 0.05 m/s)
  double still_at_end_s = 0.0;      ///< how long it had stood when the run ended
  int reversals = 0;                ///< changes of the direction of travel (forward <-> backward)
  int reversals_last_30s = 0;
  double moved_last_30s_m = 0.0;    ///< straight-line distance covered in the run's last 30 s
  std::optional<double> last_plan_found_s;
  /// The validity check that rejected most of the planner's sampled states (planner::PoseCheckName),
  /// and the commonest planner outcome other than "found".
  std::string commonest_rejection;
  std::string commonest_failure;
  /// What the last map held ahead of the vehicle, towards the route 6 m past its progress, where the run ended
  /// ("an obstacle 1.2 m high 0.8 m ahead", "seen ground ends 1.5 m ahead", ...); "" if nothing
  /// stood out or the run arrived.
  std::string map_ahead;
  /// What the planner did in the run's last 30 s: goals tried, paths found and blocked, and why.
  std::string planner_lately;
};

/// Reads the run's trajectory (true speed and pose), plan log and criteria.
Diagnosis Diagnose(const RunResult& result);

/// A stretch of a run that the verdict's rules call stalled or rocking, wherever in the run it lies
/// (the verdict looks only at the end): a "stall" stood still (|true speed| < 0.05 m/s) for at least
/// 10 s; a "rocking" spell has at least 4 direction reversals within 30 s from its first, and the
/// vehicle less than 3 m from there 30 s later (or at the run's end); overlapping ones are one spell.
struct Spell {
  std::string kind;     ///< "stall" or "rocking"
  double start_s = 0.0;
  double end_s = 0.0;   ///< the run's end for a stall that lasted to it
  Eigen::Vector2d at_m = Eigen::Vector2d::Zero();  ///< true position where it began, world frame
};

/// The run's stalls and rocking spells, by start time (a stall before a rocking spell that starts
/// at the same time). Reads the true trajectory only.
std::vector<Spell> FindSpells(const RunResult& result);

}  // namespace ovpc::scenarios
