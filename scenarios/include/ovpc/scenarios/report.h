// What a run leaves behind: the scorecard, result.json, trajectory.csv and topdown.png.
#pragma once

#include <string>

#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/scenario.h"

namespace ovpc::scenarios {

/// The scorecard table (criterion, expected, actual, pass/fail) and a summary line.
std::string FormatScorecard(const Scenario& scenario, const RunResult& result);

/// result.json: every criterion, times, real-time factor, distance, re-plans, stage timings.
void WriteResultJson(const Scenario& scenario, const RunResult& result, const std::string& path);

/// trajectory.csv: time, true pose, odometry pose, speed and commands, one row per record.
void WriteTrajectoryCsv(const RunResult& result, const std::string& path);
/// cycles.csv: one row per map-and-plan cycle of the navigator: time, prepared points, whether a map
/// was made, the re-planning trigger and the last plan's outcome ("" when none), wall-clock ms of
/// the preparation, the map update and the planning, then the same three as the CPU time of the
/// thread that ran the cycle (which holds on a loaded machine).
void WriteCyclesCsv(const RunResult& result, const std::string& path);
/// One row per planner call: time, trigger, vehicle and local goal (world frame), outcome,
/// iterations and how many sampled states each validity check rejected.
void WritePlansCsv(const RunResult& result, const std::string& path);

/// topdown.png: the run's figure (topdown.h, DrawTopdown): terrain shading, objects, forbidden
/// regions, the mapped points coloured by traversability, route, path driven, start, goal, end pose,
/// stalls and rocking spells with their times, axes in metres, title, legend and scale bar.
void WriteTopdownPng(const Scenario& scenario, const RunResult& result, const std::string& path);

}  // namespace ovpc::scenarios
