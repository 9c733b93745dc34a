// Every setting of the robot's stack, listed once per Config: the YAML reader, the YAML and JSON
// writers (`ovpc run --print-config`, result.json) and any adapter a user writes (ROS parameters, a
// GUI) walk these lists, so a key is always the field's own name and the sections mirror the
// structs. A visitor V provides:
//   v.Field("name", value)                 double, int, unsigned, bool, std::size_t, std::uint64_t,
//                                          std::vector<double>
//   v.Choice("name", value, {{"a", E::kA}, ...})   an enum by its names
//   v.Section("name", config)              a nested Config (calls VisitFields on it)
// Fields that are not settings are left out: per-update inputs (VertexCloudMap::Config's ground
// reference and known support), the planner's per-run seed, the gravity direction of the map frame,
// and the geometry the Navigator derives from its VehicleModel (Navigator::Config::Derived). The
// comparison backends' settings are listed beside them, in backends/config_fields.h.
#pragma once

#include "ovpc/core/ghpr.h"
#include "ovpc/core/vehicle_model.h"
#include "ovpc/navigation/navigator.h"

namespace ovpc::navigation {

template <class V>
void VisitFields(V& v, VehicleModel& c) {
  v.Field("length_m", c.length_m);
  v.Field("width_m", c.width_m);
  v.Field("height_m", c.height_m);
  v.Field("rear_overhang_m", c.rear_overhang_m);
  v.Field("wheelbase_m", c.wheelbase_m);
  v.Field("track_m", c.track_m);
  v.Field("max_steering_deg", c.max_steering_deg);
  v.Field("turning_radius_m", c.turning_radius_m);
}

template <class V>
void VisitFields(V& v, PointCloudBuffer::Config& c) {
  v.Field("max_scans", c.max_scans);
  v.Field("crop_radius_m", c.crop_radius_m);
  v.Field("voxel_size_m", c.voxel_size_m);
  v.Field("min_hits", c.min_hits);
  v.Field("near_range_m", c.near_range_m);
  v.Field("near_min_hits", c.near_min_hits);
  v.Field("max_points", c.max_points);
  v.Field("seed", c.seed);
}

template <class V>
void VisitFields(V& v, MapPreparation::Config& c) {
  v.Field("footprint_prior_margin_m", c.footprint_prior_margin_m);
  v.Choice("footprint_prior_mode", c.footprint_prior_mode,
           {{"replace", MapPreparation::PriorMode::kReplace}, {"fill", MapPreparation::PriorMode::kFill}});
  v.Field("footprint_prior_blend_m", c.footprint_prior_blend_m);
  v.Field("footprint_grid_m", c.footprint_grid_m);
  v.Field("footprint_edge_band_m", c.footprint_edge_band_m);
  v.Field("body_margin_m", c.body_margin_m);
  v.Field("isolated_point_radius_m", c.isolated_point_radius_m);
  v.Field("isolated_point_reach_m", c.isolated_point_reach_m);
}

template <class V>
void VisitFields(V& v, Ghpr::Config& c) {
  v.Choice("kernel", c.kernel, {{"exponential", GhprKernel::kExponential}, {"linear", GhprKernel::kLinear}});
  v.Field("gamma", c.gamma);
  v.Field("reference_hull", c.reference_hull);
}

template <class V>
void VisitFields(V& v, Traversability::Config& c) {
  v.Field("alpha_max_rad", c.alpha_max_rad);
  v.Field("delta_h_max_m", c.delta_h_max_m);
  v.Field("noise_floor_m", c.noise_floor_m);
  v.Field("noise_floor_on_slopes", c.noise_floor_on_slopes);
}

template <class V>
void VisitFields(V& v, OvpcMapper::Config& c) {
  v.Section("ghpr", c.ghpr);
  v.Section("traversability", c.traversability);
  v.Field("min_range_m", c.min_range_m);
}

template <class V>
void VisitFields(V& v, planner::VertexCloudMap::Config& c) {
  v.Field("max_projection_distance_m", c.max_projection_distance_m);
  v.Field("normal_neighbours", c.normal_neighbours);
  v.Field("normal_radius_m", c.normal_radius_m);
}

template <class V>
void VisitFields(V& v, OvpcMapBackend::Config& c) {
  v.Section("mapper", c.mapper);
  v.Section("map", c.map);
}

template <class V>
void VisitFields(V& v, planner::VehicleBox& c) {
  v.Field("margin_m", c.margin_m);
  v.Field("ground_clearance_m", c.ground_clearance_m);
  v.Field("footprint_depth_m", c.footprint_depth_m);
  v.Choice("footprint_check", c.footprint_check,
           {{"all_points", planner::VehicleBox::FootprintCheck::kAllPoints},
            {"wheels", planner::VehicleBox::FootprintCheck::kWheels}});
  v.Field("wheel_support_m", c.wheel_support_m);
  v.Field("edge_tolerance_m", c.edge_tolerance_m);
  v.Choice("placement", c.placement,
           {{"nearest_point", planner::VehicleBox::Placement::kNearestPoint},
            {"wheel_contacts", planner::VehicleBox::Placement::kWheelContacts}});
  v.Field("max_tilt_deg", c.max_tilt_deg);
  v.Field("max_roll_deg", c.max_roll_deg);
}

template <class V>
void VisitFields(V& v, planner::LocalPlanner::Config& c) {
  v.Section("vehicle", c.vehicle);
  v.Field("max_iterations", c.max_iterations);
  v.Field("range_m", c.range_m);
  v.Field("check_resolution_m", c.check_resolution_m);
  v.Field("output_resolution_m", c.output_resolution_m);
  v.Field("simplify_rounds", c.simplify_rounds);
}

template <class V>
void VisitFields(V& v, planner::LocalGoalSelection::Config& c) {
  v.Choice("mode", c.mode, {{"route", planner::LocalGoalSelection::Config::Mode::kRoute},
                            {"reachable", planner::LocalGoalSelection::Config::Mode::kReachable}});
  v.Field("cell_m", c.cell_m);
  v.Field("reach_offset_penalty", c.reach_offset_penalty);
  v.Field("reach_support_m", c.reach_support_m);
  v.Field("min_distance_m", c.min_distance_m);
  v.Field("end_zone_m", c.end_zone_m);
  v.Field("step_m", c.step_m);
  v.Field("require_vehicle_fit", c.require_vehicle_fit);
  v.Field("lateral_offsets_m", c.lateral_offsets_m);
  v.Field("lateral_offset_penalty", c.lateral_offset_penalty);
  v.Field("previous_goal_penalty", c.previous_goal_penalty);
  v.Field("unknown_cost", c.unknown_cost);
  v.Field("keep_previous_within_m", c.keep_previous_within_m);
  v.Field("max_gap_m", c.max_gap_m);
  v.Field("max_ahead_m", c.max_ahead_m);
}

template <class V>
void VisitFields(V& v, planner::Replanning::Config& c) {
  v.Field("period_s", c.period_s);
  v.Field("goal_too_close_m", c.goal_too_close_m);
  v.Field("blocked_confirmations", c.blocked_confirmations);
  v.Field("blocked_near_m", c.blocked_near_m);
  v.Field("unseen_block_near_m", c.unseen_block_near_m);
}

template <class V>
void VisitFields(V& v, controller::PurePursuit::Config& c) {
  v.Field("target_speed_mps", c.target_speed_mps);
  v.Field("reverse_speed_mps", c.reverse_speed_mps);
  v.Field("creep_speed_mps", c.creep_speed_mps);
  v.Field("lookahead_gain_s", c.lookahead_gain_s);
  v.Field("lookahead_min_m", c.lookahead_min_m);
  v.Field("lookahead_max_m", c.lookahead_max_m);
  v.Field("max_lateral_accel_mps2", c.max_lateral_accel_mps2);
  v.Field("stop_decel_mps2", c.stop_decel_mps2);
  v.Field("stop_tolerance_m", c.stop_tolerance_m);
  v.Field("standstill_mps", c.standstill_mps);
  v.Field("presteer_tolerance_rad", c.presteer_tolerance_rad);
}

template <class V>
void VisitFields(V& v, Navigator::Config& c) {
  v.Field("map_rate_hz", c.map_rate_hz);
  v.Field("control_rate_hz", c.control_rate_hz);
  v.Section("vehicle", c.vehicle);
  v.Section("buffer", c.buffer);
  v.Section("preparation", c.preparation);
  v.Section("ovpc", c.ovpc);
  v.Section("planner", c.planner);
  v.Section("local_goal", c.local_goal);
  v.Section("replan", c.replan);
  v.Section("follower", c.follower);
  v.Field("goal_candidates", c.goal_candidates);
  v.Field("route_end_any_heading", c.route_end_any_heading);
  v.Field("known_support_margin_m", c.known_support_margin_m);
  v.Field("blocked_stop_short_m", c.blocked_stop_short_m);
  v.Field("min_prefix_m", c.min_prefix_m);
  v.Field("keep_path_within_m", c.keep_path_within_m);
  v.Field("cusp_cost_m", c.cusp_cost_m);
  v.Field("rollout_margin_m", c.rollout_margin_m);
  v.Field("progress_back_m", c.progress_back_m);
  v.Field("progress_ahead_m", c.progress_ahead_m);
  v.Field("latency_s", c.latency_s);
}

}  // namespace ovpc::navigation
