// What the follower will drive: the pure-pursuit follower run on the kinematic bicycle model.
#pragma once

#include <vector>

#include "ovpc/controller/bicycle_model.h"
#include "ovpc/controller/pure_pursuit.h"
#include "ovpc/planner/path.h"

namespace ovpc::controller {

/// Drives a fresh PurePursuit along `path` from `start` on `model`, one command every `dt_s` (the
/// control period), until the follower is done and the vehicle stands or `max_time_s` has passed.
/// Returns the poses the rear axle passes: the start, then one every `spacing_m` driven, and the
/// last. Where the path asks for more than the follower does (a cusp segment shorter than its stop
/// tolerance is skipped; a short segment's heading change is only partly made; a corner is cut), the
/// poses show it. The follower is called as the closed loop calls it (without the measured steering).
/// @throws std::invalid_argument if dt_s, spacing_m or max_time_s is not positive and finite, or
///         for an invalid follower config.
std::vector<planner::Pose2> Rollout(const PurePursuit::Config& follower, const BicycleModel& model,
                                    const planner::Path& path, const BicycleModel::State& start, double dt_s,
                                    double spacing_m, double max_time_s);

}  // namespace ovpc::controller
