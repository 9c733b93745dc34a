#include "ovpc/scenarios/scenario_yaml.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <utility>

#include <yaml-cpp/yaml.h>

namespace ovpc::scenarios {
namespace {

std::string Where(const std::string& file, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return file + " (--set)";
  return file + ":" + std::to_string(mark.line + 1);
}

template <class T>
const char* TypeName() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  else if constexpr (std::is_integral_v<T>) return "a whole number";
  else if constexpr (std::is_floating_point_v<T>) return "a number";
  else return "a string";
}

// Reads one YAML map: every key it is asked for is marked used, and Finish() reports the rest as
// unknown. Errors name the file, the line and the dotted key.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string context, const std::string& file)
      : node_(node), context_(std::move(context)), file_(file) {
    if (!node_.IsMap()) Fail(node_, "'" + context_ + "' must be a mapping of keys to values");
  }

  template <class T>
  void Get(const char* key, T* out) {
    const YAML::Node value = Take(key);
    if (value) *out = Convert<T>(value, key);
  }
  template <class T>
  void GetOptional(const char* key, std::optional<T>* out) {
    const YAML::Node value = Take(key);
    if (value) *out = Convert<T>(value, key);
  }
  template <class T>
  void Required(const char* key, T* out) {
    const YAML::Node value = Take(key);
    if (!value) Fail(node_, "'" + Key(key) + "' is required");
    *out = Convert<T>(value, key);
  }
  /// A key whose value is one of `choices` (name, value); anything else fails naming them.
  template <class T>
  void GetChoice(const char* key, std::initializer_list<std::pair<const char*, T>> choices, T* out) {
    const YAML::Node value = Take(key);
    if (!value) return;
    const std::string text = value.IsScalar() ? value.Scalar() : "";
    std::string names;
    for (const auto& [name, choice] : choices) {
      if (text == name) {
        *out = choice;
        return;
      }
      names += (names.empty() ? "" : " or ") + std::string(name);
    }
    Fail(value, "'" + Key(key) + "' must be " + names + ", got '" + text + "'");
  }
  void GetDegrees(const char* key, double* out_rad) {
    const YAML::Node value = Take(key);
    if (value) *out_rad = DegToRad(Convert<double>(value, key));
  }
  Eigen::Vector2d GetXY(const YAML::Node& value, const std::string& key) const {
    if (!value.IsSequence() || value.size() != 2) Fail(value, "'" + key + "' must be [x, y]");
    return Eigen::Vector2d(ConvertAt<double>(value[0], key), ConvertAt<double>(value[1], key));
  }
  YAML::Node Child(const char* key) { return Take(key); }
  std::string Key(const char* key) const { return context_.empty() ? key : context_ + "." + key; }
  const std::string& file() const { return file_; }

  void Finish() const {
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!used_.count(key)) Fail(kv.first, "unknown key '" + Key(key.c_str()) + "'");
    }
  }

  [[noreturn]] void Fail(const YAML::Node& at, const std::string& what) const {
    throw ScenarioError(Where(file_, at) + ": " + what);
  }

  template <class T>
  T ConvertAt(const YAML::Node& value, const std::string& key) const {
    if (!value.IsScalar()) Fail(value, "'" + key + "' must be " + TypeName<T>());
    try {
      return value.as<T>();
    } catch (const YAML::BadConversion&) {
      Fail(value, "'" + key + "' must be " + TypeName<T>() + ", got '" + value.Scalar() + "'");
    }
  }

 private:
  YAML::Node Take(const char* key) {
    used_.insert(key);
    const YAML::Node& node = node_;  // const lookup never inserts the key
    return node[key];
  }
  template <class T>
  T Convert(const YAML::Node& value, const char* key) const {
    return ConvertAt<T>(value, Key(key));
  }

  YAML::Node node_;
  std::string context_;
  const std::string& file_;
  std::set<std::string> used_;
};

void ReadTerrain(MapReader r, sim::TerrainConfig* t) {
  std::string kind = "flat";
  r.Get("kind", &kind);
  if (kind == "flat") t->kind = sim::TerrainConfig::Kind::kFlat;
  else if (kind == "slope") t->kind = sim::TerrainConfig::Kind::kSlope;
  else if (kind == "ramp") t->kind = sim::TerrainConfig::Kind::kRamp;
  else if (kind == "ditch") t->kind = sim::TerrainConfig::Kind::kDitch;
  else if (kind == "rough") t->kind = sim::TerrainConfig::Kind::kRough;
  else r.Fail(r.Child("kind"), "'" + r.Key("kind") + "' must be flat, slope, ramp, ditch or rough, got '" + kind + "'");
  if (const YAML::Node size = r.Child("size_m")) {
    const Eigen::Vector2d s = r.GetXY(size, r.Key("size_m"));
    t->size_x_m = s.x();
    t->size_y_m = s.y();
  }
  r.Get("cell_m", &t->cell_m);
  r.Get("direction_deg", &t->direction_deg);
  if (const YAML::Node n = r.Child("slope")) {
    MapReader s(n, r.Key("slope"), r.file());
    s.Get("angle_deg", &t->slope.angle_deg);
    s.Finish();
  }
  if (const YAML::Node n = r.Child("ramp")) {
    MapReader s(n, r.Key("ramp"), r.file());
    s.Get("start_m", &t->ramp.start_m);
    s.Get("angle_deg", &t->ramp.angle_deg);
    s.Get("height_m", &t->ramp.height_m);
    s.Get("lane_angle_deg", &t->ramp.lane_angle_deg);
    s.Get("lane_centre_m", &t->ramp.lane_centre_m);
    s.Get("lane_width_m", &t->ramp.lane_width_m);
    s.Finish();
  }
  if (const YAML::Node n = r.Child("ditch")) {
    MapReader s(n, r.Key("ditch"), r.file());
    s.Get("centre_m", &t->ditch.centre_m);
    s.Get("depth_m", &t->ditch.depth_m);
    s.Get("bottom_width_m", &t->ditch.bottom_width_m);
    s.Get("wall_angle_deg", &t->ditch.wall_angle_deg);
    s.Finish();
  }
  if (const YAML::Node n = r.Child("rough")) {
    MapReader s(n, r.Key("rough"), r.file());
    s.Get("amplitude_m", &t->rough.amplitude_m);
    s.Get("feature_m", &t->rough.feature_m);
    s.Get("persistence", &t->rough.persistence);
    s.Get("seed", &t->rough.seed);
    s.Finish();
  }
  r.Finish();
}

void ReadObjects(const YAML::Node& list, const std::string& file, sim::World* w) {
  if (!list.IsSequence()) throw ScenarioError(Where(file, list) + ": 'objects' must be a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string ctx = "objects[" + std::to_string(i) + "]";
    if (!item.IsMap() || item.size() != 1) {
      throw ScenarioError(Where(file, item) + ": '" + ctx +
                          "' must be one of {box: ...}, {cylinder: ...}, {sphere: ...}, {ellipsoid: ...}, {carport: ...}");
    }
    const std::string type = item.begin()->first.as<std::string>();
    MapReader r(item.begin()->second, ctx + "." + type, file);
    if (type == "box") {
      sim::BoxObject o;
      r.Required("x_m", &o.x_m);
      r.Required("y_m", &o.y_m);
      r.Get("yaw_deg", &o.yaw_deg);
      r.Get("length_m", &o.length_m);
      r.Get("width_m", &o.width_m);
      r.Get("height_m", &o.height_m);
      r.Get("base_m", &o.base_m);
      w->boxes.push_back(o);
    } else if (type == "cylinder") {
      sim::CylinderObject o;
      r.Required("x_m", &o.x_m);
      r.Required("y_m", &o.y_m);
      r.Get("radius_m", &o.radius_m);
      r.Get("height_m", &o.height_m);
      r.Get("base_m", &o.base_m);
      w->cylinders.push_back(o);
    } else if (type == "sphere" || type == "ellipsoid") {
      sim::EllipsoidObject o;
      r.Required("x_m", &o.x_m);
      r.Required("y_m", &o.y_m);
      r.Get("centre_height_m", &o.centre_height_m);
      if (type == "sphere") {
        double radius = 0.5;
        r.Get("radius_m", &radius);
        o.radius_x_m = o.radius_y_m = o.radius_z_m = radius;
      } else {
        r.Get("yaw_deg", &o.yaw_deg);
        r.Get("radius_x_m", &o.radius_x_m);
        r.Get("radius_y_m", &o.radius_y_m);
        r.Get("radius_z_m", &o.radius_z_m);
      }
      w->ellipsoids.push_back(o);
    } else if (type == "carport") {
      sim::CarportObject o;
      r.Required("x_m", &o.x_m);
      r.Required("y_m", &o.y_m);
      r.Get("yaw_deg", &o.yaw_deg);
      r.Get("length_m", &o.length_m);
      r.Get("width_m", &o.width_m);
      r.Get("roof_height_m", &o.roof_height_m);
      r.Get("roof_thickness_m", &o.roof_thickness_m);
      r.Get("post_radius_m", &o.post_radius_m);
      r.Get("post_inset_m", &o.post_inset_m);
      w->carports.push_back(o);
    } else {
      r.Fail(item, "unknown object type '" + type + "' in '" + ctx + "' (box, cylinder, sphere, ellipsoid, carport)");
    }
    r.Finish();
  }
}

void ReadParams(MapReader r, Scenario* s) {
  if (const YAML::Node n = r.Child("mapper")) {
    MapReader m(n, r.Key("mapper"), r.file());
    std::string kernel = KernelName(s->navigator.ovpc.mapper.ghpr.kernel);
    m.Get("kernel", &kernel);
    try {
      s->navigator.ovpc.mapper.ghpr.kernel = ParseKernel(kernel);
    } catch (const std::invalid_argument& e) {
      m.Fail(m.Child("kernel"), e.what());
    }
    m.Get("gamma", &s->navigator.ovpc.mapper.ghpr.gamma);
    m.GetDegrees("alpha_max_deg", &s->navigator.ovpc.mapper.traversability.alpha_max_rad);
    m.Get("dh_max_m", &s->navigator.ovpc.mapper.traversability.delta_h_max_m);
    m.Get("noise_floor_m", &s->navigator.ovpc.mapper.traversability.noise_floor_m);
    m.Get("noise_floor_on_slopes", &s->navigator.ovpc.mapper.traversability.noise_floor_on_slopes);
    m.Finish();
  }
  if (const YAML::Node n = r.Child("buffer")) {
    MapReader m(n, r.Key("buffer"), r.file());
    m.Get("scans", &s->navigator.buffer.max_scans);
    m.Get("crop_radius_m", &s->navigator.buffer.crop_radius_m);
    m.Get("voxel_m", &s->navigator.buffer.voxel_size_m);
    m.Get("min_hits", &s->navigator.buffer.min_hits);
    m.Get("max_points", &s->navigator.buffer.max_points);
    m.Finish();
  }
  if (const YAML::Node n = r.Child("planner")) {
    MapReader m(n, r.Key("planner"), r.file());
    m.Get("turning_radius_m", &s->navigator.planner.turning_radius_m);
    m.Get("max_iterations", &s->navigator.planner.max_iterations);
    m.Get("range_m", &s->navigator.planner.range_m);
    m.Get("check_resolution_m", &s->navigator.planner.check_resolution_m);
    m.Get("margin_m", &s->navigator.planner.vehicle.margin_m);
    m.Get("vehicle_height_m", &s->navigator.planner.vehicle.height_m);
    m.Get("ground_clearance_m", &s->navigator.planner.vehicle.ground_clearance_m);
    m.GetChoice("footprint_check",
                {{"all_points", planner::VehicleBox::FootprintCheck::kAllPoints},
                 {"wheels", planner::VehicleBox::FootprintCheck::kWheels}},
                &s->navigator.planner.vehicle.footprint_check);
    m.Get("wheel_support_m", &s->navigator.planner.vehicle.wheel_support_m);
    m.GetChoice("placement",
                {{"nearest_point", planner::VehicleBox::Placement::kNearestPoint},
                 {"wheel_contacts", planner::VehicleBox::Placement::kWheelContacts}},
                &s->navigator.planner.vehicle.placement);
    m.Get("max_tilt_deg", &s->navigator.planner.vehicle.max_tilt_deg);
    m.Get("max_roll_deg", &s->navigator.planner.vehicle.max_roll_deg);
    m.Get("goal_min_distance_m", &s->navigator.local_goal.min_distance_m);
    m.Get("goal_keep_within_m", &s->navigator.local_goal.keep_previous_within_m);
    m.Get("goal_max_gap_m", &s->navigator.local_goal.max_gap_m);
    m.Get("goal_max_ahead_m", &s->navigator.local_goal.max_ahead_m);
    m.Get("goal_end_zone_m", &s->navigator.local_goal.end_zone_m);
    m.GetChoice("goal_mode",
                {{"route", planner::LocalGoalConfig::Mode::kRoute}, {"reachable", planner::LocalGoalConfig::Mode::kReachable}},
                &s->navigator.local_goal.mode);
    m.Get("goal_cell_m", &s->navigator.local_goal.cell_m);
    m.Get("goal_reach_offset_penalty", &s->navigator.local_goal.reach_offset_penalty);
    m.Get("goal_reach_support_m", &s->navigator.local_goal.reach_support_m);
    m.Get("goal_offset_penalty", &s->navigator.local_goal.lateral_offset_penalty);
    m.Get("replan_period_s", &s->navigator.replan.period_s);
    m.Get("goal_too_close_m", &s->navigator.replan.goal_too_close_m);
    m.Get("blocked_confirmations", &s->navigator.replan.blocked_confirmations);
    m.Get("blocked_near_m", &s->navigator.replan.blocked_near_m);
    m.Get("max_projection_distance_m", &s->navigator.ovpc.map.max_projection_distance_m);
    m.Get("normal_neighbours", &s->navigator.ovpc.map.normal_neighbours);
    m.Get("normal_radius_m", &s->navigator.ovpc.map.normal_radius_m);
    m.Finish();
  }
  if (const YAML::Node n = r.Child("controller")) {
    MapReader m(n, r.Key("controller"), r.file());
    m.Get("target_speed_mps", &s->navigator.follower.target_speed_mps);
    m.Get("reverse_speed_mps", &s->navigator.follower.reverse_speed_mps);
    m.Get("lookahead_gain_s", &s->navigator.follower.lookahead_gain_s);
    m.Get("lookahead_min_m", &s->navigator.follower.lookahead_min_m);
    m.Get("lookahead_max_m", &s->navigator.follower.lookahead_max_m);
    m.Get("max_lateral_accel_mps2", &s->navigator.follower.max_lateral_accel_mps2);
    m.Finish();
  }
  if (const YAML::Node n = r.Child("loop")) {
    MapReader m(n, r.Key("loop"), r.file());
    m.Get("map_rate_hz", &s->navigator.map_rate_hz);
    m.Get("control_rate_hz", &s->navigator.control_rate_hz);
    m.Get("record_rate_hz", &s->record.record_rate_hz);
    m.Get("mesh_snapshot_period_s", &s->record.mesh_snapshot_period_s);
    m.Get("footprint_prior_margin_m", &s->navigator.preparation.footprint_prior_margin_m);
    m.Get("footprint_prior_blend_m", &s->navigator.preparation.footprint_prior_blend_m);
    m.Get("known_support_margin_m", &s->navigator.known_support_margin_m);
    m.Get("route_end_any_heading", &s->navigator.route_end_any_heading);
    m.Get("isolated_point_radius_m", &s->navigator.preparation.isolated_point_radius_m);
    m.Get("isolated_point_reach_m", &s->navigator.preparation.isolated_point_reach_m);
    m.Get("goal_candidates", &s->navigator.goal_candidates);
    m.GetChoice("footprint_prior_mode",
                {{"replace", navigation::MapPreparation::PriorMode::kReplace},
                 {"fill", navigation::MapPreparation::PriorMode::kFill}},
                &s->navigator.preparation.footprint_prior_mode);
    m.Finish();
  }
  r.Finish();
}

void ReadCriteria(MapReader r, Criteria* c) {
  if (const YAML::Node n = r.Child("goal")) {
    MapReader g(n, r.Key("goal"), r.file());
    Eigen::Vector2d goal;
    g.Required("x_m", &goal.x());
    g.Required("y_m", &goal.y());
    g.Get("radius_m", &c->goal_radius_m);
    g.Finish();
    c->goal_m = goal;
  }
  r.Get("no_collision", &c->no_collision);
  r.GetOptional("max_roll_deg", &c->max_roll_deg);
  r.GetOptional("max_pitch_deg", &c->max_pitch_deg);
  r.GetOptional("max_time_s", &c->max_time_s);
  r.GetOptional("min_progress_m", &c->min_progress_m);
  if (const YAML::Node list = r.Child("forbidden")) {
    if (!list.IsSequence()) r.Fail(list, "'" + r.Key("forbidden") + "' must be a list");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string ctx = r.Key("forbidden") + "[" + std::to_string(i) + "]";
      MapReader f(list[i], ctx, r.file());
      Region region;
      region.name = "region " + std::to_string(i);
      f.Get("name", &region.name);
      const YAML::Node lo = f.Child("min_m"), hi = f.Child("max_m");
      if (!lo || !hi) f.Fail(list[i], "'" + ctx + "' needs min_m: [x, y] and max_m: [x, y]");
      region.min_m = f.GetXY(lo, ctx + ".min_m");
      region.max_m = f.GetXY(hi, ctx + ".max_m");
      f.Finish();
      c->forbidden.push_back(region);
    }
  }
  r.Finish();
}

void ApplySetting(YAML::Node root, const std::string& setting, const std::string& file) {
  const std::size_t eq = setting.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ScenarioError(file + ": --set '" + setting + "' must be key=value (e.g. params.mapper.gamma=-0.02)");
  }
  const std::string key = setting.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(setting.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw ScenarioError(file + ": --set '" + setting + "': value is not valid YAML: " + e.msg);
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  std::vector<YAML::Node> chain = {root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (!next.IsDefined() || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[parts[i]];
    }
    if (!next.IsMap()) throw ScenarioError(file + ": --set '" + key + "': '" + parts[i] + "' is not a section");
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
}

}  // namespace

void RecordConfig::Validate() const {
  if (!(record_rate_hz > 0.0) || !std::isfinite(record_rate_hz)) throw std::invalid_argument("record.record_rate_hz must be > 0");
  if (!(mesh_snapshot_period_s >= 0.0)) throw std::invalid_argument("record.mesh_snapshot_period_s must be >= 0");
}

void Scenario::Validate() const {
  auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  if (!(time_limit_s > 0.0)) fail("time_limit_s must be > 0");
  if (route_m.empty()) fail("route needs at least one waypoint");
  if (criteria.goal_radius_m <= 0.0) fail("criteria.goal.radius_m must be > 0");
  for (const Region& r : criteria.forbidden) {
    if (!(r.min_m.array() < r.max_m.array()).all()) fail("criteria.forbidden '" + r.name + "': min_m must be below max_m");
  }
  sim.Validate();
  record.Validate();
  navigator.Validate();
}

Scenario ParseScenario(const std::string& yaml_text, const std::string& file, const std::vector<std::string>& settings) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ScenarioError(file + ": a scenario file must be a mapping of keys to values");
  for (const std::string& setting : settings) ApplySetting(root, setting, file);

  Scenario s;
  s.path = file;
  // Closed-loop default: the simulated VLP-16's 1.5 cm range noise makes ground slivers look steep.
  s.navigator.ovpc.mapper.traversability.noise_floor_m = 0.05;
  // Closed-loop defaults for the local goal: nearer goals and side offsets keep the vehicle moving
  // when the route runs through the shadow of a post (see docs/CLOSED_LOOP.md).
  s.navigator.local_goal.min_distance_m = 2.5;
  s.navigator.local_goal.lateral_offsets_m = {1.5, 3.0, 4.5, 6.0};
  s.navigator.local_goal.keep_previous_within_m = 1.0;
  s.navigator.local_goal.max_gap_m = 8.0;
  // The last metre of the route counts as its end (noise can make the last waypoint's pose fail).
  s.navigator.local_goal.end_zone_m = 1.0;
  // Short tree extensions: with OMPL's default (a fifth of the map's extent, ~8 m) nearly every
  // extension among posts and shadows fails its motion check (docs/CLOSED_LOOP.md).
  s.navigator.planner.range_m = 1.0;
  // The wheels' footprint rule (docs/CLOSED_LOOP.md), with the Gator's axles.
  s.navigator.planner.vehicle.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
  // The box on the nearest point's tangent plane (the paper's rule); the slope scenarios set
  // placement: wheel_contacts, which broke low_roof_1p6 as a suite-wide default (docs/CLOSED_LOOP.md).
  s.navigator.planner.vehicle.placement = planner::VehicleBox::Placement::kNearestPoint;
  // That tangent plane from the 32 nearest points within 0.5 m rather than one vertex normal, which
  // range noise tilts enough to put flat ground into the box (docs/CLOSED_LOOP.md).
  s.navigator.ovpc.map.normal_neighbours = 32;
  MapReader r(root, "", file);
  r.Required("name", &s.name);
  r.Get("description", &s.description);
  r.Get("seed", &s.seed);
  r.Required("time_limit_s", &s.time_limit_s);
  if (const YAML::Node labels = r.Child("labels")) {
    if (!labels.IsSequence()) r.Fail(labels, "'labels' must be a list of words");
    for (const auto& l : labels) s.labels.push_back(r.ConvertAt<std::string>(l, "labels"));
  }
  if (const YAML::Node n = r.Child("terrain")) ReadTerrain(MapReader(n, "terrain", file), &s.sim.world.terrain);
  if (const YAML::Node n = r.Child("objects")) ReadObjects(n, file, &s.sim.world);
  if (const YAML::Node n = r.Child("start")) {
    MapReader m(n, "start", file);
    m.Get("x_m", &s.sim.start_x_m);
    m.Get("y_m", &s.sim.start_y_m);
    m.GetDegrees("yaw_deg", &s.sim.start_yaw_rad);
    m.Finish();
  }
  const YAML::Node route = r.Child("route");
  if (!route) r.Fail(root, "'route' is required (a list of [x, y] waypoints in metres)");
  if (!route.IsSequence() || route.size() == 0) r.Fail(route, "'route' must be a list of [x, y] waypoints");
  for (std::size_t i = 0; i < route.size(); ++i) s.route_m.push_back(r.GetXY(route[i], "route[" + std::to_string(i) + "]"));
  if (const YAML::Node n = r.Child("sensor")) {
    MapReader m(n, "sensor", file);
    m.Get("range_sigma_m", &s.sim.lidar.range_sigma_m);
    m.Get("dropout_fraction", &s.sim.lidar.dropout_fraction);
    m.Get("outlier_fraction", &s.sim.lidar.outlier_fraction);
    m.Get("extra_noise_sigma_m", &s.sim.lidar.extra_noise_sigma_m);
    m.Finish();
  }
  if (const YAML::Node n = r.Child("odometry")) {
    MapReader m(n, "odometry", file);
    auto& o = s.sim.odometry;
    m.Get("drift_xy_m_per_sqrt_m", &o.drift_xy_m_per_sqrt_m);
    m.Get("drift_z_m_per_sqrt_m", &o.drift_z_m_per_sqrt_m);
    m.GetDegrees("drift_yaw_deg_per_sqrt_m", &o.drift_yaw_rad_per_sqrt_m);
    m.Get("noise_xy_m", &o.noise_xy_m);
    m.Get("noise_z_m", &o.noise_z_m);
    m.GetDegrees("noise_yaw_deg", &o.noise_yaw_rad);
    if (const YAML::Node bumps = m.Child("bumps")) {
      if (!bumps.IsSequence()) m.Fail(bumps, "'odometry.bumps' must be a list");
      for (std::size_t i = 0; i < bumps.size(); ++i) {
        MapReader b(bumps[i], "odometry.bumps[" + std::to_string(i) + "]", file);
        sim::OdometrySim::Bump bump;
        b.Required("time_s", &bump.time_s);
        b.Get("forward_m", &bump.forward_m);
        b.Get("left_m", &bump.left_m);
        b.Get("up_m", &bump.up_m);
        b.GetDegrees("yaw_deg", &bump.yaw_rad);
        b.Finish();
        o.bumps.push_back(bump);
      }
    }
    m.Finish();
  }
  if (const YAML::Node n = r.Child("params")) ReadParams(MapReader(n, "params", file), &s);
  if (const YAML::Node n = r.Child("criteria")) ReadCriteria(MapReader(n, "criteria", file), &s.criteria);
  r.Finish();
  try {
    s.Validate();
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(file + ": " + e.what());
  }
  return s;
}

Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings) {
  std::ifstream in(path);
  if (!in) throw ScenarioError(path + ": cannot open the scenario file");
  std::stringstream text;
  text << in.rdbuf();
  return ParseScenario(text.str(), path, settings);
}

}  // namespace ovpc::scenarios
