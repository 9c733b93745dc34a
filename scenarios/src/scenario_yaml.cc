#include "ovpc/scenarios/scenario_yaml.h"

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config_yaml.h"
#include "ovpc/core/internal/hash.h"
#include "scenario_node.h"

namespace ovpc::scenarios {

ScenarioError::ScenarioError(const std::string& what)
    : std::runtime_error([&what] {
        std::string line;
        line.reserve(what.size());
        for (const char c : what) {
          const auto u = static_cast<unsigned char>(c);
          if (u < 0x20 || u == 0x7f) {
            constexpr char kHex[] = "0123456789abcdef";
            line += "\\x";
            line += kHex[u >> 4];
            line += kHex[u & 15];
          } else {
            line += c;
          }
        }
        return line;
      }()) {}

namespace {

using internal::ConfigReader;
using internal::MapReader;
using internal::Where;


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
  internal::ValidateAt(r.file(), r.node(), "terrain", [t] { t->Validate(); });
}

// A post field: posts on a grid of `spacing_m` over the rectangle x_m × y_m, each moved by up to
// jitter × spacing / 2 in x and y (0: rows; 1: scattered, neighbours still at least
// spacing × (1 - jitter) apart, as posts may not overlap), from its own seeded stream: the same file
// gives the same posts on every machine.
void ReadPostField(MapReader& r, const YAML::Node& item, sim::World* w) {
  Eigen::Vector2d xs(0.0, 0.0), ys(0.0, 0.0);
  if (const YAML::Node n = r.Child("x_m")) xs = r.GetXY(n, r.Key("x_m"));
  else r.Fail(item, "'" + r.Key("x_m") + "' is required: [min, max]");
  if (const YAML::Node n = r.Child("y_m")) ys = r.GetXY(n, r.Key("y_m"));
  else r.Fail(item, "'" + r.Key("y_m") + "' is required: [min, max]");
  double spacing = 3.0, jitter = 0.0, radius = 0.1, height = 2.0;
  int seed = 1;
  r.Get("spacing_m", &spacing);
  r.Get("jitter", &jitter);
  r.Get("radius_m", &radius);
  r.Get("height_m", &height);
  r.Get("seed", &seed);
  if (!(xs.y() >= xs.x()) || !(ys.y() >= ys.x())) r.Fail(item, "'" + r.Key("x_m") + "' and 'y_m' must be [min, max] with min <= max");
  if (!(jitter >= 0.0 && jitter <= 1.0)) r.Fail(r.Child("jitter"), "'" + r.Key("jitter") + "' must be in [0, 1]");
  if (!(radius > 0.0) || !(spacing * (1.0 - jitter) > 2.0 * radius)) {
    r.Fail(item, "'" + r.Key("spacing_m") + "' × (1 - jitter) must exceed the posts' diameter");
  }
  constexpr double kMaxPosts = 10000;  // a field larger than this is not a scene the loop can run
  const double nx = std::floor((xs.y() - xs.x()) / spacing) + 1, ny = std::floor((ys.y() - ys.x()) / spacing) + 1;
  if (!(nx * ny <= kMaxPosts)) r.Fail(item, "'" + r.Key("spacing_m") + "' gives more than 10000 posts over the field");
  std::uint64_t state = ovpc::internal::kGoldenGamma * (static_cast<std::uint64_t>(seed) + 1);
  const auto uniform = [&state]() {  // a splitmix64 stream, 53 bits in [0, 1)
    return ovpc::internal::ToUnitInterval(ovpc::internal::MixBits(state += ovpc::internal::kGoldenGamma));
  };
  for (int iy = 0; iy < static_cast<int>(ny); ++iy) {
    for (int ix = 0; ix < static_cast<int>(nx); ++ix) {
      sim::CylinderObject o;
      o.x_m = xs.x() + ix * spacing + jitter * spacing * (uniform() - 0.5);
      o.y_m = ys.x() + iy * spacing + jitter * spacing * (uniform() - 0.5);
      o.radius_m = radius;
      o.height_m = height;
      w->cylinders.push_back(o);
    }
  }
}

// How many objects of each kind a world holds.
struct ObjectCounts {
  explicit ObjectCounts(const sim::World& w)
      : boxes(w.boxes.size()), cylinders(w.cylinders.size()), ellipsoids(w.ellipsoids.size()), carports(w.carports.size()) {}
  std::size_t boxes, cylinders, ellipsoids, carports;
};

// The objects read since `before` alone, validated (a violation names the item's key and line).
void ValidateAdded(const ObjectCounts& before, const sim::World& w, const MapReader& r, const std::string& ctx) {
  sim::World added;
  const auto tail = [](const auto& all, std::size_t from) { return std::vector(all.begin() + from, all.end()); };
  added.boxes = tail(w.boxes, before.boxes);
  added.cylinders = tail(w.cylinders, before.cylinders);
  added.ellipsoids = tail(w.ellipsoids, before.ellipsoids);
  added.carports = tail(w.carports, before.carports);
  try {
    added.Validate();
  } catch (const std::invalid_argument& e) {
    std::string what = e.what();  // "World: boxes[0].length_m must be > 0": the field is the item's key
    const std::size_t field = what.find("].");
    if (what.rfind("World: ", 0) == 0 && field != std::string::npos) what = what.substr(field + 2);
    const std::optional<YAML::Node> at = internal::NodeNamedBy(r.node(), what);
    r.Fail(at ? *at : r.node(), "in '" + ctx + "': " + what);
  }
}

void ReadObjects(const YAML::Node& list, const std::string& file, sim::World* w) {
  if (!list.IsSequence()) throw ScenarioError(Where(file, list) + ": 'objects' must be a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string ctx = "objects[" + std::to_string(i) + "]";
    if (!item.IsMap() || item.size() != 1) {
      throw ScenarioError(Where(file, item) + ": '" + ctx +
                          "' must be one of {box: ...}, {cylinder: ...}, {sphere: ...}, {ellipsoid: ...}, {carport: ...}, "
                          "{post_field: ...}");
    }
    const std::string type = item.begin()->first.as<std::string>();
    MapReader r(item.begin()->second, ctx + "." + type, file);
    const ObjectCounts before(*w);
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
    } else if (type == "post_field") {
      ReadPostField(r, item, w);
    } else {
      r.Fail(item, "unknown object type '" + type + "' in '" + ctx + "' (box, cylinder, sphere, ellipsoid, carport, post_field)");
    }
    r.Finish();
    ValidateAdded(before, *w, r, ctx + "." + type);
  }
}

void ReadRecord(MapReader r, Recording::Config* c, const YAML::Node& node) {
  ConfigReader reader(r);
  ovpc::VisitFields(*c, reader);
  r.Finish();
  try {
    c->Validate();
  } catch (const std::invalid_argument& e) {
    r.Fail(node, e.what());
  }
}

// Keys of the navigator: section that moved into a section of their own, with their new place.
constexpr std::pair<const char*, const char*> kMovedNavigatorKeys[] = {
    {"map_rate_hz", "timing.map_rate_hz"},
    {"control_rate_hz", "timing.control_rate_hz"},
    {"latency_s", "timing.latency_s"},
    {"goal_candidates", "path_choice.goal_candidates"},
    {"route_end_any_heading", "path_choice.route_end_any_heading"},
    {"known_support_margin_m", "path_choice.known_support_margin_m"},
    {"keep_path_within_m", "path_choice.keep_path_within_m"},
    {"cusp_cost_m", "path_choice.cusp_cost_m"},
    {"rollout_margin_m", "path_choice.rollout_margin_m"},
    {"blocked_stop_short_m", "path_choice.blocked_stop_short_m"},
    {"min_prefix_m", "path_choice.min_prefix_m"},
    {"progress_back_m", "progress.back_m"},
    {"progress_ahead_m", "progress.ahead_m"},
};

void RefuseMovedKeys(MapReader& m, const YAML::Node& navigator) {
  if (!navigator.IsMap()) return;
  for (const auto& [old_key, new_key] : kMovedNavigatorKeys) {
    if (const YAML::Node n = navigator[old_key]) {
      m.Fail(n, "'navigator." + std::string(old_key) + "' is now 'navigator." + new_key + "'");
    }
  }
}

// The robot's configuration and the recording settings from a root map (a preset, or a scenario's
// navigator: and record: sections over the preset).
void ReadNavigatorAndRecord(MapReader& r, Scenario* s) {
  if (const YAML::Node n = r.Child("navigator")) {
    MapReader m(n, "navigator", r.file());
    RefuseMovedKeys(m, n);
    ConfigReader reader(m);
    ovpc::VisitFields(s->navigator, reader);
    ovpc::VisitFields(s->map_backends, reader);
    m.Finish();
    // What holds across sections (the planner's box is the vehicle model's size with its rules).
    try {
      s->navigator.Validate();
      s->map_backends.Validate();
    } catch (const std::invalid_argument& e) {
      const std::optional<YAML::Node> at = internal::NodeNamedBy(r.node(), e.what());
      m.Fail(at ? *at : n, std::string("in 'navigator': ") + e.what());
    }
  }
  if (const YAML::Node n = r.Child("record")) ReadRecord(MapReader(n, "record", r.file()), &s->record, n);
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
      std::string by = "footprint";
      f.Get("by", &by);
      if (by == "wheels") {
        region.by = Region::By::kWheels;
      } else if (by != "footprint") {
        f.Fail(f.Child("by"), "'" + ctx + ".by' must be footprint or wheels, got '" + by + "'");
      }
      f.Finish();
      c->forbidden.push_back(region);
    }
  }
  r.Finish();
}

void ApplySetting(YAML::Node root, const std::string& setting, const std::string& file) {
  const std::size_t eq = setting.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ScenarioError(file + ": --set '" + setting + "' must be key=value (e.g. navigator.ovpc.mapper.ghpr.gamma=-0.02)");
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

void Recording::Config::Validate() const {
  if (!(record_rate_hz > 0.0) || !std::isfinite(record_rate_hz)) throw std::invalid_argument("record.record_rate_hz must be > 0");
  if (!(mesh_snapshot_period_s >= 0.0)) throw std::invalid_argument("record.mesh_snapshot_period_s must be >= 0");
  if (!(mcap_scan_period_s >= 0.0) || !std::isfinite(mcap_scan_period_s)) throw std::invalid_argument("record.mcap_scan_period_s must be >= 0");
  if (!(mcap_map_period_s >= 0.0) || !std::isfinite(mcap_map_period_s)) throw std::invalid_argument("record.mcap_map_period_s must be >= 0");
}

void Scenario::Validate() const {
  auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  // A day of simulated time: a run is bounded, and a typo (.inf, 1e9) does not run for ever.
  if (!(time_limit_s > 0.0) || !(time_limit_s <= 86400.0)) fail("time_limit_s must be in (0, 86400] s");
  // A route is a line to follow: from a first waypoint to a last one elsewhere.
  if (route_m.size() < 2) fail("route needs two or more waypoints");
  // The start, the route and the goal lie on the terrain (centred on the origin).
  const double half_x = 0.5 * sim.world.terrain.size_x_m, half_y = 0.5 * sim.world.terrain.size_y_m;
  const auto on_terrain = [&](const Eigen::Vector2d& p) { return std::abs(p.x()) <= half_x && std::abs(p.y()) <= half_y; };
  std::ostringstream spans;
  spans << " (the terrain spans x and y within +-" << half_x << " and +-" << half_y << " m)";
  const std::string extent = spans.str();
  for (std::size_t i = 0; i < route_m.size(); ++i) {
    if (!route_m[i].allFinite()) fail("route[" + std::to_string(i) + "] must be finite");
    if (!on_terrain(route_m[i])) fail("route[" + std::to_string(i) + "] lies off the terrain" + extent);
  }
  double length_m = 0.0;
  for (std::size_t i = 1; i < route_m.size(); ++i) length_m += (route_m[i] - route_m[i - 1]).norm();
  if (!(length_m > 0.0)) fail("route has no length: its waypoints are all one point");
  if (!on_terrain(Eigen::Vector2d(sim.start_x_m, sim.start_y_m))) fail("start lies off the terrain" + extent);
  if (criteria.goal_m && !(criteria.goal_m->allFinite() && on_terrain(*criteria.goal_m))) {
    fail("criteria.goal must be finite and on the terrain" + extent);
  }
  if (!(criteria.goal_radius_m <= 100.0)) fail("criteria.goal.radius_m must be at most 100 m");
  if (criteria.goal_radius_m <= 0.0) fail("criteria.goal.radius_m must be > 0");
  for (const Region& r : criteria.forbidden) {
    if (!r.min_m.allFinite() || !r.max_m.allFinite()) fail("criteria.forbidden '" + r.name + "': corners must be finite");
    if (!(r.min_m.array() < r.max_m.array()).all()) fail("criteria.forbidden '" + r.name + "': min_m must be below max_m");
  }
  sim.Validate();
  record.Validate();
  navigator.Validate();
  map_backends.Validate();
}

Preset LoadPreset(const std::string& path) { return Preset{ReadSmallRegularFile(path, "preset file"), path}; }

namespace {

void ApplyPreset(const Preset& preset, Scenario* s) {
  YAML::Node root;
  try {
    root = YAML::Load(preset.yaml);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(preset.file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ScenarioError(preset.file + ": a preset must be a mapping with 'navigator' (and, as --print-config writes it, 'record')");
  MapReader r(root, "", preset.file);
  ReadNavigatorAndRecord(r, s);
  r.Finish();
}

}  // namespace

std::string FormatRunConfig(const Scenario& scenario) {
  internal::YamlWriter nav(2), record(2);
  ovpc::VisitFields(scenario.navigator, nav);
  ovpc::VisitFields(scenario.map_backends, nav);
  ovpc::VisitFields(scenario.record, record);
  return "navigator:\n" + nav.str() + "record:\n" + record.str();
}

namespace {

Scenario Parse(const std::string& yaml_text, const std::string& file, const std::vector<std::string>& settings,
               const Preset& preset) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ScenarioError(file + ": a scenario file must be a mapping of keys to values");
  if (const YAML::Node p = static_cast<const YAML::Node&>(root)["parameters"]) {
    throw ScenarioError(Where(file, p) + ": this is a scenario family ('parameters:'): run its draws with `ovpc suite " + file +
                        " --samples N`, or write them with `ovpc family " + file + " --samples N --out DIR`");
  }
  for (const std::string& setting : settings) ApplySetting(root, setting, file);
  return internal::ParseScenarioNode(root, file, preset);
}

}  // namespace

namespace internal {

Scenario ParseScenarioNode(const YAML::Node& root, const std::string& file, const Preset& preset) try {
  Scenario s;
  s.path = file;
  ApplyPreset(preset, &s);
  MapReader r(root, "", file);
  r.Required("name", &s.name);
  ValidateName(file, root["name"].Mark().line + 1, s.name);
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
  if (!route.IsSequence() || route.size() < 2) r.Fail(route, "'route' must be a list of two or more [x, y] waypoints");
  for (std::size_t i = 0; i < route.size(); ++i) s.route_m.push_back(r.GetXY(route[i], "route[" + std::to_string(i) + "]"));
  if (const YAML::Node n = r.Child("sensor")) {
    MapReader m(n, "sensor", file);
    m.Get("range_sigma_m", &s.sim.lidar.range_sigma_m);
    m.Get("dropout_fraction", &s.sim.lidar.dropout_fraction);
    m.Get("outlier_fraction", &s.sim.lidar.outlier_fraction);
    m.Get("extra_noise_sigma_m", &s.sim.lidar.extra_noise_sigma_m);
    m.Finish();
    internal::ValidateAt(file, n, "sensor", [&s] { s.sim.lidar.Validate(); });
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
    internal::ValidateAt(file, n, "odometry", [&o] { o.Validate(); });
  }
  if (const YAML::Node n = r.Child("params")) {
    r.Fail(n, "'params' is gone: the robot's settings are under 'navigator', with the keys of "
              "navigation/presets/default.yaml (ovpc run --print-config shows them)");
  }
  ReadNavigatorAndRecord(r, &s);
  if (const YAML::Node n = r.Child("criteria")) ReadCriteria(MapReader(n, "criteria", file), &s.criteria);
  r.Finish();
  try {
    s.Validate();
  } catch (const std::invalid_argument& e) {
    // At the line of the key it names ("route[2] lies off the terrain"), when the file has it.
    const std::optional<YAML::Node> at = internal::NodeNamedBy(root, e.what());
    throw ScenarioError((at ? Where(file, *at) : file) + ": " + e.what());
  }
  return s;
} catch (const YAML::Exception& e) {
  // What the readers do not name themselves (a value yaml-cpp cannot convert, ...).
  throw ScenarioError(file + (e.mark.line >= 0 ? ":" + std::to_string(e.mark.line + 1) : std::string()) + ": " + e.msg);
}

}  // namespace internal

Scenario ParseScenario(const std::string& yaml_text, const std::string& file, const std::vector<std::string>& settings,
                       const Preset& preset) {
  try {
    return Parse(yaml_text, file, settings, preset);
  } catch (const YAML::Exception& e) {
    // What the readers above do not name themselves (a value yaml-cpp cannot convert, ...).
    throw ScenarioError(file + (e.mark.line >= 0 ? ":" + std::to_string(e.mark.line + 1) : std::string()) + ": " + e.msg);
  }
}

Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings, const Preset& preset) {
  return ParseScenario(ReadSmallRegularFile(path, "scenario file"), path, settings, preset);
}

}  // namespace ovpc::scenarios
